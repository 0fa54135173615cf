// The colour scales of the pictures, chosen to be told apart by colour-blind people:
// Okabe & Ito's blue/vermillion for suitability, viridis for ordered terms, Paul Tol's "muted"
// palette for landform classes. One definition for the PNG and the HTML viewer.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/runtime.hpp"

namespace roadcross::viz {

enum class ColorBy { suitable, rank, landform, context, reason };

/// "suitable", "rank", "landform", "context" or "reason"; nullopt otherwise.
std::optional<ColorBy> parse_color_by(std::string_view name);
const char* to_string(ColorBy by) noexcept;

struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;  ///< 0..1
  std::string hex() const;           ///< "#rrggbb"
};

Rgb rgb_from_hex(std::string_view hex);  ///< "#rrggbb"

inline const Rgb kSuitableColor = rgb_from_hex("#0072b2");    // Okabe-Ito blue
inline const Rgb kUnsuitableColor = rgb_from_hex("#d55e00");  // Okabe-Ito vermillion
inline const Rgb kMissingColor = rgb_from_hex("#bbbbbb");     // a term the DB does not hold

/// Colour of a segment whose deciding reason is `code` (one of schema::kReasons' codes that make
/// a place unsuitable; empty = suitable, kSuitableColor); kMissingColor for any other code.
Rgb reason_color(std::string_view code);

/// The codes reason_color knows, in schema::kReasons' order.
std::vector<std::string_view> reason_color_codes();

/// Viridis at t in [0, 1] (dark purple .. yellow), interpolated between 9 published stops.
Rgb viridis(double t);

struct LegendEntry {
  std::string label;
  Rgb color;
};

class ColorScale {
 public:
  /// `context_min`/`context_max`: the range of context scores to spread viridis over.
  ColorScale(ColorBy by, double threshold, int context_min, int context_max);
  /// `deciding_reason`: the segment's (SegmentLayer::deciding_reason), read by ColorBy::reason.
  Rgb color_of(const Assessment& a, std::string_view deciding_reason = {}) const;
  std::string title() const;
  /// The entries to show; for landform only the classes in `present`, for reason "suitable"
  /// and the deciding reasons in `present` (an empty string stands for suitable).
  std::vector<LegendEntry> legend(const std::vector<std::string>& present) const;

 private:
  ColorBy by_;
  double threshold_;
  int context_min_, context_max_;
};

/// Colour of a Weiss landform class (or "bridge"/"tunnel"), kMissingColor for unknown.
Rgb landform_color(const std::string& landform);

}  // namespace roadcross::viz
