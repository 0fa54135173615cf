// The reason codes a segment can carry (schema::kReasons' stored codes), as a bit set in their
// canonical reporting order: 2 bytes a segment instead of a vector of strings, and always sorted
// and unique.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/schema/reasons.hpp"

namespace roadcross::preprocess {

class ReasonSet {
  static_assert(schema::kStoredReasonCount <= 16,
                "ReasonSet holds 16 bits: widen bits_ for more codes");

 public:
  /// Adds a stored code of schema::kReasons; throws std::logic_error for any other (a typo in
  /// the code, or one only the runtime gives).
  void add(std::string_view code);
  bool contains(std::string_view code) const;
  bool empty() const noexcept { return bits_ == 0; }
  /// The codes, in schema::kReasons order.
  std::vector<std::string> list() const;
  /// The codes joined with `separator`, in schema::kReasons order ("" when empty).
  std::string joined(char separator) const;
  bool operator==(const ReasonSet&) const = default;
  /// The set as its bits (bit i: schema::kReasons[i]), e.g. as a key for joined texts.
  std::uint16_t bits() const noexcept { return bits_; }

 private:
  // 2 bytes (a Segment holds one): bit i for schema::kReasons[i].
  std::uint16_t bits_ = 0;
};

}  // namespace roadcross::preprocess
