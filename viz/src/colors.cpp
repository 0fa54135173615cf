#include "roadcross/viz/colors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "roadcross/schema/reasons.hpp"

namespace roadcross::viz {

namespace {

// Viridis (matplotlib) at t = 0, 1/8, ..., 1.
constexpr std::array<const char*, 9> kViridisStops = {"#440154", "#472d7b", "#3b528b",
                                                      "#2c728e", "#21918c", "#28ae80",
                                                      "#5ec962", "#addc30", "#fde725"};

// Weiss landform classes in the cost model's order (docs/cost-model.md), with Paul Tol's muted
// palette (and black for the tenth); structures take their ends' elevation, so a grey of their own.
const std::array<std::pair<const char*, const char*>, 12> kLandforms = {{
    {"canyon", "#332288"},
    {"midslope_drainage", "#88ccee"},
    {"upland_drainage", "#44aa99"},
    {"u_shaped_valley", "#117733"},
    {"plains", "#ddcc77"},
    {"open_slope", "#999933"},
    {"upper_slope", "#cc6677"},
    {"local_ridge", "#882255"},
    {"midslope_ridge", "#aa4499"},
    {"mountain_top", "#000000"},
    {"bridge", "#777777"},
    {"tunnel", "#444444"},
}};

// The deciding reasons a map shows (those that make a place unsuitable), Okabe & Ito's palette
// without the suitable blue; visibility, the commonest, keeps the vermillion of "not suitable".
constexpr std::array<std::pair<std::string_view, const char*>, 7> kReasonColors = {{
    {"NOT_CROSSABLE_CLASS", "#000000"},
    {"TUNNEL", "#777777"},
    {"OVERRIDE", "#cc79a7"},
    {"LIMITED_VISIBILITY", "#d55e00"},
    {"LOW_SCORE", "#e69f00"},
    {"KERB_TOO_HIGH", "#009e73"},
    {"NO_PAVEMENT_FAR_SIDE", "#56b4e9"},
}};
static_assert(
    [] {
      for (const auto& [code, hex] : kReasonColors) {
        // An index, not find_reason's pointer: GCC's UBSan build cannot compare an address
        // with null in a constant expression.
        if (schema::reason_index(code) == schema::kReasons.size()) return false;
      }
      return true;
    }(),
    "every coloured code is a reason code of the DB contract");

constexpr int kRankMax = 14;

// Lower rank is better: show good places yellow, as with context (higher is better).
double rank_t(int rank) {
  return 1.0 - std::clamp(rank, 0, kRankMax) / static_cast<double>(kRankMax);
}

}  // namespace

std::optional<ColorBy> parse_color_by(std::string_view name) {
  for (ColorBy by :
       {ColorBy::suitable, ColorBy::rank, ColorBy::landform, ColorBy::context, ColorBy::reason}) {
    if (name == to_string(by)) return by;
  }
  return std::nullopt;
}

const char* to_string(ColorBy by) noexcept {
  switch (by) {
    case ColorBy::suitable:
      return "suitable";
    case ColorBy::rank:
      return "rank";
    case ColorBy::landform:
      return "landform";
    case ColorBy::context:
      return "context";
    case ColorBy::reason:
      return "reason";
  }
  return "?";
}

std::string Rgb::hex() const {
  auto byte = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(r), byte(g), byte(b));
  return text;
}

Rgb rgb_from_hex(std::string_view hex) {
  auto channel = [&](std::size_t at) {
    return static_cast<double>(std::strtol(std::string(hex.substr(at, 2)).c_str(), nullptr, 16)) /
           255.0;
  };
  return {channel(1), channel(3), channel(5)};
}

Rgb viridis(double t) {
  const double x = std::clamp(t, 0.0, 1.0) * (kViridisStops.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(x), kViridisStops.size() - 2);
  const double f = x - static_cast<double>(i);
  const Rgb a = rgb_from_hex(kViridisStops[i]);
  const Rgb b = rgb_from_hex(kViridisStops[i + 1]);
  return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

Rgb reason_color(std::string_view code) {
  if (code.empty()) return kSuitableColor;
  for (const auto& [known, hex] : kReasonColors) {
    if (code == known) return rgb_from_hex(hex);
  }
  return kMissingColor;
}

std::vector<std::string_view> reason_color_codes() {
  std::vector<std::string_view> out;
  for (const schema::ReasonSpec& spec : schema::kReasons) {
    for (const auto& [known, hex] : kReasonColors) {
      if (spec.code == known) out.push_back(known);
    }
  }
  return out;
}

Rgb landform_color(const std::string& landform) {
  for (const auto& [name, hex] : kLandforms) {
    if (landform == name) return rgb_from_hex(hex);
  }
  return kMissingColor;
}

ColorScale::ColorScale(ColorBy by, double threshold, int context_min, int context_max)
    : by_(by), threshold_(threshold), context_min_(context_min), context_max_(context_max) {}

Rgb ColorScale::color_of(const Assessment& a, std::string_view deciding_reason) const {
  switch (by_) {
    case ColorBy::suitable:
      return a.suitable ? kSuitableColor : kUnsuitableColor;
    case ColorBy::rank:
      return a.rank ? viridis(rank_t(*a.rank)) : kMissingColor;
    case ColorBy::landform:
      return a.landform ? landform_color(*a.landform) : kMissingColor;
    case ColorBy::context: {
      if (!a.context_score) return kMissingColor;
      const int span = std::max(1, context_max_ - context_min_);
      return viridis(static_cast<double>(*a.context_score - context_min_) / span);
    }
    case ColorBy::reason:
      return reason_color(deciding_reason);
  }
  return kMissingColor;
}

std::string ColorScale::title() const {
  char text[96];
  switch (by_) {
    case ColorBy::suitable:
      std::snprintf(text, sizeof text, "Crossing (score + context >= %g)", threshold_);
      return text;
    case ColorBy::rank:
      return "Rank (0 best .. 14 worst)";
    case ColorBy::landform:
      return "Landform (Weiss 2001)";
    case ColorBy::context:
      return "Context score (higher is better)";
    case ColorBy::reason:
      return "Why not suitable (the deciding reason)";
  }
  return "";
}

std::vector<LegendEntry> ColorScale::legend(const std::vector<std::string>& present) const {
  const auto is_present = [&](std::string_view value) {
    return std::find(present.begin(), present.end(), value) != present.end();
  };
  std::vector<LegendEntry> out;
  switch (by_) {
    case ColorBy::suitable:
      out = {{"suitable", kSuitableColor}, {"not suitable", kUnsuitableColor}};
      break;
    case ColorBy::rank:
      for (int rank = 0; rank <= kRankMax; rank += 2)
        out.push_back({"rank " + std::to_string(rank), viridis(rank_t(rank))});
      break;
    case ColorBy::landform:
      for (const auto& [name, hex] : kLandforms) {
        if (is_present(name)) out.push_back({name, rgb_from_hex(hex)});
      }
      if (out.empty()) out.push_back({"no elevation data", kMissingColor});
      break;
    case ColorBy::context: {
      const int span = std::max(1, context_max_ - context_min_);
      for (int i = 0; i <= 4; ++i) {
        const int value = context_min_ + static_cast<int>(std::lround(span * i / 4.0));
        out.push_back({"context " + std::to_string(value),
                       viridis(static_cast<double>(value - context_min_) / span)});
      }
      break;
    }
    case ColorBy::reason:
      out.push_back({"suitable", kSuitableColor});
      for (std::string_view code : reason_color_codes()) {
        if (is_present(code)) out.push_back({std::string(code), reason_color(code)});
      }
      break;
  }
  return out;
}

}  // namespace roadcross::viz
