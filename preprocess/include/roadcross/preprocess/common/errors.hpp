// Errors of the build: each names the input file and, where known, the line or OSM object.
#pragma once

#include <stdexcept>
#include <string>

namespace roadcross::preprocess {

/// Bad input: a missing, empty, truncated or malformed file, or values out of range.
class InputError : public std::runtime_error {
 public:
  /// The message reads "FILE: WHAT"; WHAT names the line or object where known.
  InputError(const std::string& file, const std::string& what);
  const std::string& file() const noexcept { return file_; }

 private:
  std::string file_;
};

/// A parameter out of its range; names the parameter.
class ParameterError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The output could not be written (permissions, disk full); names the output path.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace roadcross::preprocess
