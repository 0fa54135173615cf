// The drawing subcommands' names and one-line descriptions, shared by `roadcross` (which lists
// them and hands them on) and `roadcross-viz` (which runs them).
#pragma once

#include <array>

namespace roadcross::cli {

struct VizCommandName {
  const char* name;
  const char* description;
};

inline constexpr std::array<VizCommandName, 3> kVizCommands = {{
    {"render",
     "draw the map as a PNG: segments coloured by a term, designated crossings, hillshade, "
     "legend, scale bar, north arrow (and a .pgw world file beside it)"},
    {"export",
     "write a table of the map as GeoJSON in WGS84, every column a property, plus suitable "
     "and assess_reasons (the runtime's judgement on the centreline)"},
    {"view",
     "write an offline HTML viewer of the map into a folder: segments coloured by "
     "suitability, their terms on hover, a coordinate search that gives assess's answer"},
}};

/// The program that runs them, in the same directory as `roadcross`.
inline constexpr const char* kVizProgram = "roadcross-viz";

}  // namespace roadcross::cli
