// What a wheeled robot meets at the kerb, read from OSM tags: kerb=* and kerb:height on crossing
// nodes, on barrier=kerb nodes and on the nodes of crossing ways; refuge islands
// (crossing:island, traffic_calming=island); pavements along a road (sidewalk=*,
// sidewalk:left / :right / :both). Pure functions: no I/O, no state. A value not understood is
// never an error: it reads as unknown, and unknown never forbids a crossing
// (docs/cost-model.md, "Kerbs, islands and pavements").
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::preprocess {

/// Height a kerb=* value stands for when no kerb:height is tagged, metres: flush and no 0,
/// lowered and rolled 0.03 (the OSM wiki's typical heights), raised 0.12 (the wiki only says
/// "> 3 cm"; 12 cm is a common street kerb). nullopt for any other value (yes, regular, ...).
std::optional<double> usual_kerb_height_m(std::string_view kerb) noexcept;

/// kerb:height in metres: "0.12", "0.12 m", "12 cm", "12cm", "120 mm", "4 in", "4\"", "0,12".
/// A bare number is metres (the OSM default unit); nullopt for anything not understood, a
/// negative value or one above 1 m (a bare "12" means 12 cm to its mapper, not 12 m: read as
/// not understood rather than guessed).
std::optional<double> parse_kerb_height_m(std::string_view value) noexcept;

/// The kerb and island facts of one OSM object, or of several merged.
struct KerbFacts {
  /// The kerb=* value of the highest kerb seen ("raised", "lowered", "flush", "rolled", "no",
  /// ...), "yes" for a barrier=kerb without kerb=*, empty when no kerb is tagged.
  std::string kerb;
  /// Height of the highest kerb whose height is known (kerb:height, else the usual height of
  /// its kerb=* value), metres.
  std::optional<double> kerb_height_m;
  /// A refuge island in the middle of the crossing: true (crossing:island=yes,
  /// traffic_calming=island), false (crossing:island=no), unknown.
  std::optional<bool> island;

  bool empty() const noexcept { return kerb.empty() && !kerb_height_m && !island; }
};

/// The facts of one object's tags. kerb=*, kerb:left, kerb:right and kerb:both are each a kerb
/// (the robot climbs both kerbs of a crossing: the highest counts); kerb:height (also
/// kerb:left:height, kerb:right:height) is that kerb's measured height and wins over the usual
/// height of its value (a mapper who measured knows better than the category).
KerbFacts kerb_facts(const Tags& tags);

/// Adds `other` to `into`: the higher kerb (a known height beats an unknown one), an island
/// when either says yes, no island when one says no and none says yes.
void merge_kerb_facts(KerbFacts& into, const KerbFacts& other);

/// Pavement on each side of a road way, relative to the way's drawing direction: true (a
/// pavement: yes, or separate = mapped as its own footway), false (no, none), unknown.
struct SidewalkSides {
  std::optional<bool> left;
  std::optional<bool> right;
};

/// From sidewalk=both|left|right|no|none|separate, then sidewalk:both, then sidewalk:left /
/// sidewalk:right, each more specific key overriding the general one for its side (so
/// sidewalk=both + sidewalk:left=no reads left no, right yes). sidewalk=yes names no side and
/// reads as unknown on both.
SidewalkSides sidewalk_sides(const Tags& tags);

}  // namespace roadcross::preprocess
