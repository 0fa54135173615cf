#include "roadcross/schema/verdict.hpp"

namespace roadcross::schema {

bool has_reason(std::string_view reasons, std::string_view code) noexcept {
  std::size_t start = 0;
  while (start <= reasons.size()) {
    std::size_t end = reasons.find(',', start);
    if (end == std::string_view::npos) end = reasons.size();
    if (reasons.substr(start, end - start) == code) return true;
    start = end + 1;
  }
  return false;
}

Verdict judge_segment(const VerdictTerms& terms, const VerdictThresholds& thresholds) {
  Verdict v;
  // In double (exact for any two ints): a damaged map's context_score may be any int, and the
  // runtime reports it as corrupt only after judging.
  const double total = static_cast<double>(terms.score.value_or(0)) +
                       static_cast<double>(terms.context_score.value_or(0));
  v.score_reaches_threshold = terms.score.has_value() && total >= thresholds.threshold;
  // Never suitable, whatever an operator says: the class, a tunnel, a no_crossing override.
  v.not_crossable_class = has_reason(terms.reasons, "NOT_CROSSABLE_CLASS");
  v.tunnel = terms.tunnel || has_reason(terms.reasons, "TUNNEL");
  v.no_crossing = terms.override_no_crossing;
  // An operator's force_suitable overrides the score and the computed sight distance (the
  // operator may know of a mirror, or of a hedge cut back).
  if (!terms.override_force_suitable) {
    v.limited_visibility =
        thresholds.limited_visibility_unsuitable && has_reason(terms.reasons, "LIMITED_VISIBILITY");
    v.low_score = !v.score_reaches_threshold;
  }
  v.suitable =
      !(v.not_crossable_class || v.tunnel || v.no_crossing || v.limited_visibility || v.low_score);
  return v;
}

std::vector<std::string_view> forbidding_codes(const Verdict& verdict) {
  std::vector<std::string_view> out;
  if (verdict.not_crossable_class) out.emplace_back("NOT_CROSSABLE_CLASS");
  if (verdict.tunnel) out.emplace_back("TUNNEL");
  if (verdict.no_crossing) out.emplace_back("OVERRIDE");
  if (verdict.limited_visibility) out.emplace_back("LIMITED_VISIBILITY");
  if (verdict.low_score) out.emplace_back("LOW_SCORE");
  return out;
}

}  // namespace roadcross::schema
