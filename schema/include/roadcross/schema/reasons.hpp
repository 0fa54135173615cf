// The reason codes of the DB contract: why a place is poor or forbidden. One table for the build,
// which stores the codes it finds in segments.reasons, and for the runtime, which reads them,
// adds the ones that depend on the query, explains each one and judges with them.
#pragma once

#include <array>
#include <string_view>

namespace roadcross::schema {

struct ReasonSpec {
  std::string_view code;
  /// What it means, for people ("the road bends sharply here: ...").
  std::string_view sentence;
  /// The code alone makes the place unsuitable, whatever the score (under the map's default
  /// parameters: LIMITED_VISIBILITY forbids unless the build ran with
  /// sight.limited_visibility_unsuitable = 0).
  bool makes_unsuitable;
  /// Stored by the build in segments.reasons; otherwise the runtime adds it to an answer.
  bool stored_by_build;
};

/// Every reason code, in the canonical reporting order: the stored codes first (what forbids
/// crossing, then why the place is poor), then the ones the runtime adds.
inline constexpr std::array<ReasonSpec, 15> kReasons = {{
    {"NOT_CROSSABLE_CLASS", "a motorway or trunk road: never crossed on foot", true, true},
    {"TUNNEL", "in a tunnel or under a cover", true, true},
    {"OVERRIDE", "an operator override applies", false, true},
    {"NEAR_JUNCTION", "close to a junction, where traffic turns in from several sides", false,
     true},
    {"SHARP_BEND", "the road bends sharply here: approaching cars are seen late", false, true},
    {"CREST_OR_DIP", "a crest or dip hides approaching cars", false, true},
    {"LIMITED_VISIBILITY", "the view along the road is shorter than a crossing needs", true, true},
    {"BUSY_ROAD", "a fast, wide or busy road", false, true},
    {"NO_ELEVATION", "no elevation data here: crests and dips are unknown", false, true},
    {"TOO_FAR_FROM_ROAD", "too far from the road centreline to be at the kerb", true, false},
    {"LOW_SCORE", "score + context score is below the suitability threshold", true, false},
    // What the robot meets at the kerb (schema version 3): they depend on the robot's
    // capability and on its side of the road, so the runtime adds them.
    {"KERB_TOO_HIGH", "a kerb here is higher than the robot can climb", true, false},
    {"NO_PAVEMENT_FAR_SIDE", "the far side of the road is tagged without a pavement to cross onto",
     true, false},
    // Under position uncertainty (docs/runtime.md, "Position uncertainty").
    {"POSITION_UNCERTAIN",
     "the verdict changes within the region the robot may be in: it needs a better fix", true,
     false},
    {"AMBIGUOUS_ROAD",
     "another road lies within the region the robot may be in: which one it is at is unknown", true,
     false},
}};

/// The number of codes the build stores (they come first in kReasons).
inline constexpr std::size_t kStoredReasonCount = 9;

/// The spec of `code`, or nullptr for a code that is not in the contract.
constexpr const ReasonSpec* find_reason(std::string_view code) {
  for (const ReasonSpec& spec : kReasons) {
    if (spec.code == code) return &spec;
  }
  return nullptr;
}

/// Position of `code` in kReasons, or kReasons.size() when unknown.
constexpr std::size_t reason_index(std::string_view code) {
  for (std::size_t i = 0; i < kReasons.size(); ++i) {
    if (kReasons[i].code == code) return i;
  }
  return kReasons.size();
}

}  // namespace roadcross::schema
