// The parameter file: every parameter of the model (Parameters::specs()) in one text file that
// is both valid INI and valid TOML:
//
//   # comment
//   [context]                 <- ParameterSpec::section
//   crossing_points = 10      <- ParameterSpec::name = a number
//
// A small parser of exactly this subset, not CLI11's config reader: CLI11 maps [section] to
// subcommands rather than to "section.name" options, and its errors carry no line numbers,
// while every error here names the file, the line and the key. Also accepted: "section.name =
// value" outside a section (a TOML dotted key) and ';' comments (INI).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "roadcross/preprocess/parameters.hpp"

namespace roadcross::preprocess {

/// Every parameter with its current value, its range and its description, as a loadable file.
std::string format_parameter_file(const Parameters& parameters);

/// Sets the parameters the text names (others keep their values). Throws ParameterError
/// "<name>:<line>: <key>: ..." for unknown sections and keys, keys given twice, values that
/// are not numbers, out of range or not whole where a whole number is required, and lines
/// that are none of the above.
void parse_parameter_text(std::string_view text, const std::string& name, Parameters& parameters);

/// The largest parameter file read, bytes (every parameter with a comment is ~10 kB).
inline constexpr std::size_t kMaxParameterFileBytes = 1 << 20;

/// Reads a parameter file; throws ParameterError naming the file if it is not a regular file,
/// is larger than kMaxParameterFileBytes, cannot be read or is invalid.
void read_parameter_file(const std::string& path, Parameters& parameters);

}  // namespace roadcross::preprocess
