// The reason codes a segment can carry, as a bit set in their canonical reporting order (what
// forbids crossing first, then why the place is poor): 2 bytes a segment instead of a vector of
// strings, and always sorted and unique.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace roadcross::preprocess {

// KERB_TOO_HIGH and NO_PAVEMENT_FAR_SIDE are the runtime's (they depend on the robot and on
// its side of the road); they are listed so that the codes have one table.
inline constexpr std::array<std::string_view, 14> kReasonCodes = {"NOT_CROSSABLE_CLASS",
                                                                  "TUNNEL",
                                                                  "OVERRIDE",
                                                                  "NEAR_JUNCTION",
                                                                  "SHARP_BEND",
                                                                  "CREST_OR_DIP",
                                                                  "LIMITED_VISIBILITY",
                                                                  "BUSY_ROAD",
                                                                  "NO_ELEVATION",
                                                                  "BRIDGE",
                                                                  "COVERED",
                                                                  "TOO_FAR_FROM_ROAD",
                                                                  "KERB_TOO_HIGH",
                                                                  "NO_PAVEMENT_FAR_SIDE"};

class ReasonSet {
  static_assert(kReasonCodes.size() <= 16, "ReasonSet holds 16 bits: widen bits_ for more codes");

 public:
  /// Adds a code of kReasonCodes; throws std::logic_error for any other (a typo in the code).
  void add(std::string_view code);
  bool contains(std::string_view code) const;
  bool empty() const noexcept { return bits_ == 0; }
  /// The codes, in kReasonCodes order.
  std::vector<std::string> list() const;
  /// The codes joined with `separator`, in kReasonCodes order ("" when empty).
  std::string joined(char separator) const;
  bool operator==(const ReasonSet&) const = default;

 private:
  // 2 bytes (a Segment holds one): a bit for each of the 14 codes.
  std::uint16_t bits_ = 0;
};

}  // namespace roadcross::preprocess
