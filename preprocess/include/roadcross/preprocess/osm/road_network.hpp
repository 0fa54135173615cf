// Reading the road network from an OSM file: the ways of the kept road classes and the
// locations of exactly the nodes they use.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace osmium {
class Location;
class Node;
class TagList;
class Relation;
class Way;
}  // namespace osmium

namespace roadcross::preprocess {

class Progress;

using Tags = std::vector<std::pair<std::string, std::string>>;

/// Value of `key` in `tags`, or empty when absent.
std::string_view tag_value(const Tags& tags, std::string_view key) noexcept;

/// highway=* values that are roads a robot may have to cross (docs/cost-model.md, "Road class").
/// motorway and trunk (and their links) are kept so that a robot near them is told it cannot
/// cross; footways, cycleways, paths, steps, tracks and construction are not roads.
bool is_kept_road_class(std::string_view highway) noexcept;

struct RoadWay {
  std::int64_t osm_id = 0;
  std::string highway;
  Tags tags;  ///< all tags of the way
  std::vector<std::int64_t> node_ids;
};

struct NodeLocation {
  std::int64_t osm_id = 0;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
};

/// A node used by a road way that carries tags (crossings, signals, barriers, ...).
struct TaggedNode {
  std::int64_t osm_id = 0;
  Tags tags;
};

/// A footway=crossing or cycleway=crossing way: where it meets a road is a designated
/// crossing. Only these ways of the non-road network are kept (ids and tags, no geometry).
struct CrossingWay {
  std::int64_t osm_id = 0;
  Tags tags;
  std::vector<std::int64_t> node_ids;
};

/// A footway=sidewalk way (highway=footway, path or cycleway): a pavement mapped on its own,
/// beside a road. Ids only; its nodes' locations are in crossing_way_locations.
struct SidewalkWay {
  std::int64_t osm_id = 0;
  std::vector<std::int64_t> node_ids;
};

/// True for the ways kept as SidewalkWay.
bool is_sidewalk_way(const osmium::TagList& tags) noexcept;

/// True for the ways kept as CrossingWay: footway=crossing or cycleway=crossing, not an area.
bool is_crossing_way(const Tags& tags) noexcept;

struct RoadNetwork {
  std::string source_path;
  std::vector<RoadWay> ways;               ///< sorted by osm_id
  std::vector<NodeLocation> locations;     ///< sorted by osm_id, only nodes used by `ways`
  std::vector<TaggedNode> tagged_nodes;    ///< sorted by osm_id, only nodes used by `ways`
  std::vector<CrossingWay> crossing_ways;  ///< sorted by osm_id
  std::vector<SidewalkWay> sidewalk_ways;  ///< footway=sidewalk ways, sorted by osm_id
  /// Locations of the crossing and sidewalk ways' nodes that no road way uses, sorted by osm_id.
  std::vector<NodeLocation> crossing_way_locations;
  /// Tags of the crossing and sidewalk ways' nodes that no road way uses and that carry kerb,
  /// island or crossing tags (a kerb node where a crossing way meets the pavement), sorted by
  /// osm_id.
  std::vector<TaggedNode> crossing_way_tagged_nodes;
  std::uint64_t ways_read = 0;          ///< all ways in the file
  std::uint64_t nodes_read = 0;         ///< all nodes in the file
  std::uint64_t missing_locations = 0;  ///< node references of road ways not in the file
  std::int64_t newest_timestamp_s = 0;  ///< newest object timestamp (s since epoch), 0 if none

  /// Location of a node, or nullptr when the file did not contain it.
  const NodeLocation* find_location(std::int64_t node_id) const noexcept;
};

/// Something else read in the same two passes over the file as the road network (the sight
/// stage's buildings and walls), so that the file is decoded twice and not four times.
class ExtraOsmReader {
 public:
  virtual ~ExtraOsmReader() = default;
  /// First pass: every way of the file.
  virtual void way(const osmium::Way& way) = 0;
  /// First pass: every relation, only when wants_relations() (relations are at the end of a
  /// file: reading them decodes the whole file in the first pass).
  virtual void relation(const osmium::Relation& /*relation*/) {}
  virtual bool wants_relations() const { return false; }
  /// Between the passes: e.g. sort the node ids the second pass must find. Runs on a thread of
  /// its own, beside the road network's work between the passes and the node pass's start;
  /// node() is first called after it has returned (the nodes read meanwhile wait, in order).
  virtual void ways_done() {}
  /// Second pass: every node of the file, in file order, by its id and location.
  virtual void node(std::int64_t id, osmium::Location location) = 0;
  /// After the second pass: e.g. free what only the node lookup needed.
  virtual void nodes_done() {}
};

/// Reads an .osm, .osm.gz, .osm.bz2 or .osm.pbf file in two passes: road ways first, then only
/// the node locations those ways use, so memory follows the road network and not the file.
/// `extra` (may be null) sees the same passes. Throws InputError naming the file (and the line
/// for XML) on missing, empty, truncated or malformed input, or when the file holds no road of
/// a kept class.
RoadNetwork read_road_network(const std::string& path, Progress& progress,
                              ExtraOsmReader* extra = nullptr);

/// The same over several extracts read as one (MergedOsmReader: by type and id, an object held
/// by several files read once). Each file must be sorted by type and id when there are two or
/// more; errors name the file at fault, or all of them joined by " + ".
RoadNetwork read_road_network(const std::vector<std::string>& paths, Progress& progress,
                              ExtraOsmReader* extra = nullptr);

}  // namespace roadcross::preprocess
