// The one rule that says whether a segment is a suitable place to cross. Every surface that
// says "suitable" (the runtime's assess, assess_segment and better_place, and through them the
// map views, export, batch, Python and ROS) judges through judge_segment, so that they cannot
// disagree. A pure function of a row's columns and the thresholds: the build can store its
// verdict under the map's default thresholds, and the runtime recompute it under others.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace roadcross::schema {

/// The thresholds of a judgement (the DB records the build's as param.suitability.threshold and
/// param.sight.limited_visibility_unsuitable).
struct VerdictThresholds {
  /// Suitable needs score + context_score >= this (points; any finite number).
  double threshold = 20.0;
  /// LIMITED_VISIBILITY forbids crossing (true) or is only a cost already in the rank (false).
  bool limited_visibility_unsuitable = true;
};

/// What the judgement reads of a segment's row (segments table columns of the same names).
struct VerdictTerms {
  std::optional<int> score;          ///< 1..15, none when the segment has no rank
  std::optional<int> context_score;  ///< points, none counts as 0
  /// The row's reason codes, comma-separated (the `reasons` column).
  std::string_view reasons;
  bool tunnel = false;
  bool override_no_crossing = false;
  bool override_force_suitable = false;
};

struct Verdict {
  bool suitable = false;
  /// score + context_score reaches the threshold (false without a score).
  bool score_reaches_threshold = false;
  // Why it is not suitable (all false when suitable). A force_suitable override clears
  // limited_visibility and low_score, never the class, a tunnel or a no_crossing override.
  bool not_crossable_class = false;  ///< NOT_CROSSABLE_CLASS: a motorway or trunk
  bool tunnel = false;               ///< TUNNEL
  bool no_crossing = false;          ///< OVERRIDE: an operator's no_crossing
  bool limited_visibility = false;   ///< LIMITED_VISIBILITY, when it forbids
  bool low_score = false;            ///< LOW_SCORE: below the threshold
};

/// The reason codes that make `verdict` not suitable, in the order above (empty when suitable).
std::vector<std::string_view> forbidding_codes(const Verdict& verdict);

/// True when `code` is one of the comma-separated codes of `reasons`.
bool has_reason(std::string_view reasons, std::string_view code) noexcept;

/// The verdict on a segment for a position on its centreline (the caller adds validity: a
/// position farther than valid_distance_m from the road is never suitable).
Verdict judge_segment(const VerdictTerms& terms, const VerdictThresholds& thresholds);

}  // namespace roadcross::schema
