#include "roadcross/preprocess/common/reasons.hpp"

#include <stdexcept>

namespace roadcross::preprocess {

namespace {
std::size_t index_of(std::string_view code) {
  const std::size_t index = schema::reason_index(code);
  if (index >= schema::kStoredReasonCount) {
    throw std::logic_error("not a stored reason code: " + std::string(code));
  }
  return index;
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
  for (std::size_t i = 0; i < schema::kStoredReasonCount; ++i) {
    if (bits_ & (1u << i)) out.emplace_back(schema::kReasons[i].code);
  }
  return out;
}

std::string ReasonSet::joined(char separator) const {
  std::string out;
  for (std::size_t i = 0; i < schema::kStoredReasonCount; ++i) {
    if (!(bits_ & (1u << i))) continue;
    if (!out.empty()) out += separator;
    out += schema::kReasons[i].code;
  }
  return out;
}

}  // namespace roadcross::preprocess
