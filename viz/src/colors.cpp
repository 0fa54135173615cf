#include "roadcross/viz/colors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

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

constexpr int kRankMax = 14;

// Lower rank is better: show good places yellow, as with context (higher is better).
double rank_t(int rank) {
  return 1.0 - std::clamp(rank, 0, kRankMax) / static_cast<double>(kRankMax);
}

}  // namespace

std::optional<ColorBy> parse_color_by(std::string_view name) {
  for (ColorBy by : {ColorBy::suitable, ColorBy::rank, ColorBy::landform, ColorBy::context}) {
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

Rgb landform_color(const std::string& landform) {
  for (const auto& [name, hex] : kLandforms) {
    if (landform == name) return rgb_from_hex(hex);
  }
  return kMissingColor;
}

ColorScale::ColorScale(ColorBy by, double threshold, int context_min, int context_max)
    : by_(by), threshold_(threshold), context_min_(context_min), context_max_(context_max) {}

Rgb ColorScale::color_of(const Assessment& a) const {
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
  }
  return "";
}

std::vector<LegendEntry> ColorScale::legend(const std::vector<std::string>& landforms) const {
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
        if (std::find(landforms.begin(), landforms.end(), name) != landforms.end())
          out.push_back({name, rgb_from_hex(hex)});
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
  }
  return out;
}

}  // namespace roadcross::viz
