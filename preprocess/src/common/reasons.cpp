#include "roadcross/preprocess/common/reasons.hpp"

#include <algorithm>
#include <stdexcept>

namespace roadcross::preprocess {

namespace {
std::size_t index_of(std::string_view code) {
  const auto it = std::find(kReasonCodes.begin(), kReasonCodes.end(), code);
  if (it == kReasonCodes.end()) throw std::logic_error("unknown reason code " + std::string(code));
  return static_cast<std::size_t>(it - kReasonCodes.begin());
}
}  // namespace

void ReasonSet::add(std::string_view code) {
  bits_ = static_cast<std::uint16_t>(bits_ | (1u << index_of(code)));
}

bool ReasonSet::contains(std::string_view code) const {
  return (bits_ & (1u << index_of(code))) != 0;
}

std::vector<std::string> ReasonSet::list() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < kReasonCodes.size(); ++i) {
    if (bits_ & (1u << i)) out.emplace_back(kReasonCodes[i]);
  }
  return out;
}

std::string ReasonSet::joined(char separator) const {
  std::string out;
  for (std::size_t i = 0; i < kReasonCodes.size(); ++i) {
    if (!(bits_ & (1u << i))) continue;
    if (!out.empty()) out += separator;
    out += kReasonCodes[i];
  }
  return out;
}

}  // namespace roadcross::preprocess
