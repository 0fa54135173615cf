// The parameter file (--config) on arbitrary text: parameters within their documented ranges or
// a ParameterError naming the line, nothing else.
#include <cstdlib>

#include "fuzz_support.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/parameter_file.hpp"

namespace rp = roadcross::preprocess;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rp::Parameters parameters;
  try {
    rp::parse_parameter_text(roadcross::fuzz::as_text(data, size), "fuzz.toml", parameters);
  } catch (const rp::ParameterError& e) {
    if (std::string_view(e.what()).substr(0, 10) != "fuzz.toml:") std::abort();
    return 0;
  }
  // Whatever the text set, each value lies in its spec's range (the file checks it per value).
  for (const rp::ParameterSpec& spec : parameters.specs()) {
    if (!(*spec.value >= spec.min && *spec.value <= spec.max)) std::abort();
  }
  try {
    parameters.validate();  // cross-parameter rules may still refuse the set, with a message
  } catch (const rp::ParameterError&) {
  }
  // What is accepted prints and reads back the same.
  rp::Parameters again;
  rp::parse_parameter_text(rp::format_parameter_file(parameters), "printed", again);
  if (rp::format_parameter_file(again) != rp::format_parameter_file(parameters)) std::abort();
  return 0;
}
