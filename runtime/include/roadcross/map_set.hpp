// A set of roadcross maps answered as one: a fleet's area in several files, possibly in several
// UTM zones. Each query goes to the maps whose coverage (stored in each map, see MapInfo) holds
// the position; where maps overlap, the nearest road over all of them decides. Every answer
// names the map that gave it. Same dependencies and threading rules as roadcross::Map (one
// MapSet per thread).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "roadcross/runtime.hpp"

namespace roadcross {

/// Which map of a set answered.
struct MapSource {
  std::size_t index = 0;  ///< position in the set (MapSet::map(index))
  std::string path;       ///< the map's file, as opened
  std::string map_id;     ///< the map's identifier (metadata map_id), empty when it has none
};

/// An answer and the map it came from.
template <typename T>
struct FromMap {
  T answer;
  MapSource map;
};

/// A UTM zone written as its number and hemisphere: "33N", "34S" ("33" means north; "n" and
/// "s" as well). nullopt for anything else, or a number outside 1..60.
std::optional<geo::UtmZone> parse_utm_zone(const std::string& text) noexcept;

class MapSet {
 public:
  /// Opens every path: a map file, or a directory whose every entry that is not a directory is
  /// a map (opened in name order; subdirectories are not read). Fails on the first file that is
  /// not a readable roadcross map, naming it, and when no map is found. Maps are kept in the
  /// order given (a directory's in name order): where two maps give the same distance, the
  /// earlier one answers.
  static Result<MapSet> open(const std::vector<std::string>& paths) noexcept;

  MapSet(MapSet&&) noexcept;
  MapSet& operator=(MapSet&&) noexcept;
  MapSet(const MapSet&) = delete;
  MapSet& operator=(const MapSet&) = delete;
  ~MapSet();

  std::size_t size() const noexcept;
  /// The map at `index` (< size()).
  Map& map(std::size_t index) noexcept;
  const Map& map(std::size_t index) const noexcept;

  /// The maps that may hold a road within `search_m` (metres, >= 0) of the position: those whose
  /// grid extent, grown by search_m, holds it (a WGS84 box check first, then the grid). Indexes
  /// in set order. A UTM position needs its zone (Position::utm(e, n, zone)): a set spans zones,
  /// so a bare easting/northing is ambiguous and gives invalid_argument.
  Result<std::vector<std::size_t>> covering(const Position& position, double search_m) noexcept;

  /// The index of the map that answers a position (the rule of nearest, assess, ...): for a
  /// host that keeps using that Map (e.g. plan_crossing and gap_crossing, which take a Map).
  /// not_found when no covering map has a road within max_distance_m (metres, > 0).
  Result<std::size_t> choose(const Position& position, double max_distance_m = 1000.0) noexcept;

  /// Map::nearest over the covering maps: the nearest road of all of them.
  Result<FromMap<NearestRoad>> nearest(const Position& position,
                                       double max_distance_m = 1000.0) noexcept;
  /// Map::assess in the map whose road is nearest (options.max_distance_m is the search).
  Result<FromMap<Assessment>> assess(const Position& position,
                                     const AssessOptions& options = {}) noexcept;
  /// Map::better_place in the map whose road is nearest (options.assess.max_distance_m).
  Result<FromMap<BetterPlaces>> better_place(const Position& position,
                                             const BetterPlaceOptions& options = {}) noexcept;
  /// Map::road_heading in the map whose road is nearest.
  Result<FromMap<RoadHeading>> road_heading(const Position& position,
                                            double max_distance_m = 1000.0) noexcept;

 private:
  struct Impl;
  explicit MapSet(std::unique_ptr<Impl> impl) noexcept;
  /// Finds the covering maps and returns the index (in Impl::candidates) of the one whose
  /// road within max_distance_m is nearest, or the error.
  Result<std::size_t> answering_candidate(const Position& position, double max_distance_m) noexcept;
  MapSource source(std::size_t index) const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace roadcross
