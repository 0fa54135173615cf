// One tunable number of the build: where it lives, its range and what it means.
#pragma once

#include <string>

namespace roadcross::preprocess {

struct ParameterSpec {
  std::string section;      ///< "segments", "geometry", "terrain", "context", "suitability"
  std::string name;         ///< snake_case with its unit, e.g. "junction_distance_m"
  double* value = nullptr;  ///< points into the owning Parameters object
  double min = 0.0;         ///< inclusive range
  double max = 0.0;
  bool integer = false;     ///< must be a whole number
  std::string description;  ///< one line: meaning, unit, source of the default

  std::string key() const { return section + "." + name; }
};

/// Formats a double in its shortest round-trip form ("10", "0.75", "1e-05").
std::string format_number(double value);

}  // namespace roadcross::preprocess
