#include "roadcross/preprocess/context/kerb_tags.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <utility>

namespace roadcross::preprocess {

namespace {

std::string_view trim(std::string_view s) noexcept {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

/// Metres per unit of a kerb:height suffix, or 0 when the suffix is not a length unit.
double metres_per_unit(std::string_view unit) noexcept {
  constexpr std::array<std::pair<std::string_view, double>, 9> kUnits = {{
      {"", 1.0},
      {"m", 1.0},
      {"cm", 0.01},
      {"mm", 0.001},
      {"in", 0.0254},
      {"inch", 0.0254},
      {"inches", 0.0254},
      {"\"", 0.0254},
      {"ft", 0.3048},
  }};
  for (const auto& [name, metres] : kUnits) {
    if (unit == name) return metres;
  }
  return 0.0;
}

/// Sets a side from a sidewalk value: yes/separate -> true, no/none -> false; anything else
/// leaves it as it was.
void apply_side(std::string_view value, std::optional<bool>& side) {
  if (value == "yes" || value == "separate") side = true;
  if (value == "no" || value == "none") side = false;
}

/// A kerb known by its value and (maybe) its height.
struct OneKerb {
  std::string_view value;
  std::optional<double> height_m;
};

}  // namespace

std::optional<double> usual_kerb_height_m(std::string_view kerb) noexcept {
  if (kerb == "flush" || kerb == "no") return 0.0;
  if (kerb == "lowered" || kerb == "rolled") return 0.03;
  if (kerb == "raised") return 0.12;
  return std::nullopt;
}

std::optional<double> parse_kerb_height_m(std::string_view value) noexcept {
  std::string text(trim(value));
  std::size_t length = 0;
  while (length < text.size() && (std::isdigit(static_cast<unsigned char>(text[length])) ||
                                  text[length] == '.' || text[length] == ',')) {
    if (text[length] == ',') text[length] = '.';  // "0,12": decimal comma
    ++length;
  }
  if (length == 0) return std::nullopt;
  double number = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + length, number);
  if (ec != std::errc() || end != text.data() + length) return std::nullopt;
  const double per_unit = metres_per_unit(trim(std::string_view(text).substr(length)));
  if (per_unit <= 0.0) return std::nullopt;
  const double metres = number * per_unit;
  if (!(metres >= 0.0) || metres > 1.0) return std::nullopt;
  return metres;
}

KerbFacts kerb_facts(const Tags& tags) {
  KerbFacts facts;
  // Each kerb the object describes: the node's own (kerb=* with kerb:height), and a crossing
  // node's two sides when they differ.
  const std::array<OneKerb, 4> kerbs = {{
      {tag_value(tags, "kerb"), parse_kerb_height_m(tag_value(tags, "kerb:height"))},
      {tag_value(tags, "kerb:both"), std::nullopt},
      {tag_value(tags, "kerb:left"), parse_kerb_height_m(tag_value(tags, "kerb:left:height"))},
      {tag_value(tags, "kerb:right"), parse_kerb_height_m(tag_value(tags, "kerb:right:height"))},
  }};
  const bool barrier = tag_value(tags, "barrier") == "kerb";
  for (const OneKerb& k : kerbs) {
    KerbFacts one;
    one.kerb = k.value;
    one.kerb_height_m = k.height_m ? k.height_m : usual_kerb_height_m(k.value);
    merge_kerb_facts(facts, one);
  }
  if (facts.kerb.empty() && (barrier || facts.kerb_height_m)) facts.kerb = "yes";
  const std::string_view island = tag_value(tags, "crossing:island");
  if (island == "yes" || tag_value(tags, "traffic_calming") == "island") facts.island = true;
  if (island == "no" && !facts.island) facts.island = false;
  return facts;
}

void merge_kerb_facts(KerbFacts& into, const KerbFacts& other) {
  const bool other_higher =
      other.kerb_height_m && (!into.kerb_height_m || *other.kerb_height_m > *into.kerb_height_m);
  if (other_higher) {
    into.kerb_height_m = other.kerb_height_m;
    into.kerb = other.kerb;
  } else if (into.kerb.empty() && !into.kerb_height_m) {
    into.kerb = other.kerb;
  }
  if (other.island) into.island = *other.island || into.island.value_or(false);
}

SidewalkSides sidewalk_sides(const Tags& tags) {
  SidewalkSides sides;
  const std::string_view general = tag_value(tags, "sidewalk");
  if (general == "both" || general == "separate") sides.left = sides.right = true;
  if (general == "no" || general == "none") sides.left = sides.right = false;
  if (general == "left") sides.left = true, sides.right = false;
  if (general == "right") sides.left = false, sides.right = true;
  const std::string_view both = tag_value(tags, "sidewalk:both");
  apply_side(both, sides.left);
  apply_side(both, sides.right);
  apply_side(tag_value(tags, "sidewalk:left"), sides.left);
  apply_side(tag_value(tags, "sidewalk:right"), sides.right);
  return sides;
}

}  // namespace roadcross::preprocess
