#include "roadcross/preprocess/osm/road_network.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <future>
#include <osmium/handler.hpp>
#include <utility>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/common/sorted_id_cursor.hpp"
#include "roadcross/preprocess/osm/osm_pass.hpp"

namespace roadcross::preprocess {

std::string_view tag_value(const Tags& tags, std::string_view key) noexcept {
  for (const auto& [k, v] : tags) {
    if (k == key) return v;
  }
  return {};
}

bool is_kept_road_class(std::string_view highway) noexcept {
  static constexpr std::array<std::string_view, 16> kKept = {
      "motorway",  "motorway_link",  "trunk",    "trunk_link",    "primary",      "primary_link",
      "secondary", "secondary_link", "tertiary", "tertiary_link", "unclassified", "residential",
      "service",   "busway",         "road",     "living_street"};
  return std::find(kKept.begin(), kKept.end(), highway) != kKept.end();
}

namespace {

/// The values of the keys the ways pass asks every way about (null when absent; of a repeated
/// key the first, as osmium::TagList::operator[] gives it), found in one walk over its tags
/// instead of one walk per key: most ways are not roads and are asked about all four.
struct WayKeys {
  const char* highway = nullptr;
  const char* footway = nullptr;
  const char* cycleway = nullptr;
  const char* area = nullptr;

  explicit WayKeys(const osmium::TagList& tags) {
    const std::array<std::pair<const char*, const char**>, 4> wanted{
        {{"highway", &highway}, {"footway", &footway}, {"cycleway", &cycleway}, {"area", &area}}};
    for (const osmium::Tag& tag : tags) {
      const char* key = tag.key();
      for (const auto& [name, value] : wanted) {
        // The first letter first: most of a way's keys are none of the four.
        if (key[0] == name[0] && std::strcmp(key, name) == 0) {
          if (!*value) *value = tag.value();
          break;
        }
      }
    }
  }

  bool is_area() const { return area && std::strcmp(area, "yes") == 0; }
};

bool is_sidewalk_way(const WayKeys& keys) noexcept {
  return keys.highway && keys.footway && std::strcmp(keys.footway, "sidewalk") == 0 &&
         (std::strcmp(keys.highway, "footway") == 0 || std::strcmp(keys.highway, "path") == 0 ||
          std::strcmp(keys.highway, "cycleway") == 0) &&
         !keys.is_area();
}

}  // namespace

bool is_sidewalk_way(const osmium::TagList& tags) noexcept {
  return is_sidewalk_way(WayKeys(tags));
}

bool is_crossing_way(const Tags& tags) noexcept {
  return (tag_value(tags, "footway") == "crossing" || tag_value(tags, "cycleway") == "crossing") &&
         tag_value(tags, "area") != "yes";
}

const NodeLocation* RoadNetwork::find_location(std::int64_t node_id) const noexcept {
  auto it = std::lower_bound(locations.begin(), locations.end(), node_id,
                             [](const NodeLocation& n, std::int64_t id) { return n.osm_id < id; });
  return (it != locations.end() && it->osm_id == node_id) ? &*it : nullptr;
}

namespace {

Tags copy_tags(const osmium::TagList& tags) {
  Tags out;
  out.reserve(tags.size());
  for (const osmium::Tag& tag : tags) out.emplace_back(tag.key(), tag.value());
  return out;
}

/// Keys that make a node on a road or a crossing way interesting to later stages (crossings,
/// signals, kerbs, refuge islands, ...).
bool has_interesting_tag(const osmium::TagList& tags) {
  static constexpr std::array<const char*, 15> kKeys = {
      "highway",          "crossing",        "crossing_ref",  "crossing:markings",
      "crossing:signals", "traffic_signals", "barrier",       "kerb",
      "kerb:height",      "kerb:left",       "kerb:right",    "kerb:both",
      "crossing:island",  "traffic_calming", "tactile_paving"};
  return std::any_of(kKeys.begin(), kKeys.end(),
                     [&](const char* key) { return tags.has_key(key); });
}

class RoadWayCollector : public osmium::handler::Handler {
 public:
  explicit RoadWayCollector(RoadNetwork& network) : network_(network) {}

  void way(const osmium::Way& way) {
    ++network_.ways_read;
    note_timestamp(way);
    const WayKeys keys(way.tags());
    const char* highway = keys.highway;
    if (!highway || !is_kept_road_class(highway) || keys.is_area()) {
      keep_crossing_way(way, keys);
      keep_sidewalk_way(way, keys);
      return;
    }
    RoadWay road;
    road.osm_id = way.id();
    road.highway = highway;
    road.tags = copy_tags(way.tags());
    road.node_ids.reserve(way.nodes().size());
    for (const osmium::NodeRef& ref : way.nodes()) road.node_ids.push_back(ref.ref());
    network_.ways.push_back(std::move(road));
  }

  /// footway=crossing / cycleway=crossing ways: ids and tags only, they are few.
  void keep_crossing_way(const osmium::Way& way, const WayKeys& keys) {
    const bool crossing = (keys.footway && std::strcmp(keys.footway, "crossing") == 0) ||
                          (keys.cycleway && std::strcmp(keys.cycleway, "crossing") == 0);
    if (!crossing || keys.is_area()) return;
    CrossingWay kept;
    kept.osm_id = way.id();
    kept.tags = copy_tags(way.tags());
    for (const osmium::NodeRef& ref : way.nodes()) kept.node_ids.push_back(ref.ref());
    network_.crossing_ways.push_back(std::move(kept));
  }

  /// footway=sidewalk ways (a pavement mapped on its own): node ids only, for the proximity
  /// rule that gives a road's untagged side its pavement.
  void keep_sidewalk_way(const osmium::Way& way, const WayKeys& keys) {
    if (!is_sidewalk_way(keys) || way.nodes().size() < 2) return;
    SidewalkWay kept;
    kept.osm_id = way.id();
    for (const osmium::NodeRef& ref : way.nodes()) kept.node_ids.push_back(ref.ref());
    network_.sidewalk_ways.push_back(std::move(kept));
  }

  void note_timestamp(const osmium::OSMObject& object) {
    network_.newest_timestamp_s = std::max<std::int64_t>(network_.newest_timestamp_s,
                                                         object.timestamp().seconds_since_epoch());
  }

 private:
  RoadNetwork& network_;
};

class NodeLocationCollector : public osmium::handler::Handler {
 public:
  NodeLocationCollector(RoadNetwork& network, const std::vector<std::int64_t>& wanted_sorted,
                        const std::vector<std::int64_t>& crossing_only_sorted)
      : network_(network), wanted_(wanted_sorted), crossing_only_(crossing_only_sorted) {
    // At most one location per wanted node (a file with a node twice grows it): grown by
    // doubling, the table would hold up to twice that until the network is freed.
    network_.locations.reserve(wanted_sorted.size());
  }

  void node(const osmium::Node& node) {
    ++network_.nodes_read;
    network_.newest_timestamp_s =
        std::max<std::int64_t>(network_.newest_timestamp_s, node.timestamp().seconds_since_epoch());
    if (!wanted_.contains(node.id())) {
      keep_crossing_way_node(node);
      return;
    }
    const osmium::Location location = node.location();
    if (!location.valid()) return;  // deleted or invalid coordinates: treated as missing
    network_.locations.push_back({node.id(), location.lat(), location.lon()});
    if (!node.tags().empty() && has_interesting_tag(node.tags())) {
      network_.tagged_nodes.push_back({node.id(), copy_tags(node.tags())});
    }
  }

 private:
  void keep_crossing_way_node(const osmium::Node& node) {
    if (!crossing_only_.contains(node.id())) return;
    if (!node.location().valid()) return;
    network_.crossing_way_locations.push_back(
        {node.id(), node.location().lat(), node.location().lon()});
    if (!node.tags().empty() && has_interesting_tag(node.tags())) {
      network_.crossing_way_tagged_nodes.push_back({node.id(), copy_tags(node.tags())});
    }
  }

  RoadNetwork& network_;
  SortedIdCursor wanted_;
  SortedIdCursor crossing_only_;
};

/// ExtraOsmReader::ways_done() on a thread of its own, with a flag that tells, without a system
/// call, that it has returned (or thrown).
struct WaysDone {
  std::atomic<bool> returned{false};  // (before the future, which waits for the thread first)
  std::future<void> future;

  void start(ExtraOsmReader& reader) {
    future = std::async(std::launch::async, [&reader, this] {
      struct Flag {
        std::atomic<bool>& returned;
        ~Flag() { returned.store(true, std::memory_order_release); }
      } flag{returned};
      reader.ways_done();
    });
  }
  bool running() const { return future.valid() && !returned.load(std::memory_order_acquire); }
  /// Waits for it (when started and not yet waited for); rethrows what it threw.
  void wait() {
    if (future.valid()) future.get();
  }
};

/// Hands the objects of the passes to an ExtraOsmReader. In the node pass the reader's nodes
/// wait for its ways_done(): while that runs (sorting the obstacles' node references, at the
/// pass's start), the nodes read are kept in order, their ids and locations, up to
/// kMaxWaitingNodes, and handed over before the next node once it has returned. Stopping at the
/// first node instead held the road network's handler and, their queue full, the decoding
/// threads: one core idled for most of ways_done().
class ExtraHandler : public osmium::handler::Handler {
 public:
  ExtraHandler(ExtraOsmReader& reader, WaysDone* ways_done)
      : reader_(reader), ways_done_(ways_done) {}
  void way(const osmium::Way& way) { reader_.way(way); }
  void relation(const osmium::Relation& relation) { reader_.relation(relation); }
  void node(const osmium::Node& node) {
    if (ways_done_ && ways_done_->future.valid()) {
      if (ways_done_->running() && waiting_.size() < kMaxWaitingNodes) {
        if (waiting_.empty()) waiting_.reserve(kMaxWaitingNodes);  // pages taken as filled
        waiting_.push_back({node.id(), node.location()});
        return;
      }
      ways_done_->wait();
    }
    if (!waiting_.empty()) hand_over_waiting();
    reader_.node(node.id(), node.location());
  }
  /// After the pass: the nodes still waiting, once ways_done() has returned.
  void finish() {
    if (ways_done_) ways_done_->wait();
    hand_over_waiting();
  }

 private:
  /// 16 bytes each: 64 MiB at most (~0.3 s of decoding on two cores at 50x tiled Monaco is
  /// ~2 M nodes).
  static constexpr std::size_t kMaxWaitingNodes = std::size_t{1} << 22;
  struct WaitingNode {
    std::int64_t id;
    osmium::Location location;
  };
  void hand_over_waiting() {
    for (const WaitingNode& w : waiting_) reader_.node(w.id, w.location);
    std::vector<WaitingNode>().swap(waiting_);
  }

  ExtraOsmReader& reader_;
  WaysDone* ways_done_;
  std::vector<WaitingNode> waiting_;
};

/// One pass with the road network's handler and, when there is one, the extra reader's.
template <typename Handler>
void read_pass(const std::vector<std::string>& path, osmium::osm_entity_bits::type entities,
               Handler& handler, ExtraOsmReader* extra, Progress& progress,
               WaysDone* ways_done = nullptr) {
  if (!extra) return read_osm_pass(path, entities, progress, handler);
  ExtraHandler extra_handler(*extra, ways_done);
  read_osm_pass(path, entities, progress, handler, extra_handler);
  extra_handler.finish();
}

void check_readable(const std::string& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) {
    throw InputError(path, std::string("cannot open OSM file: ") + std::strerror(errno));
  }
  if (!S_ISREG(status.st_mode)) throw InputError(path, "not a regular file");
  if (status.st_size == 0) throw InputError(path, "the OSM file is empty (0 bytes)");
}

template <typename T>
void sort_by_id_unique(std::vector<T>& items) {
  std::sort(items.begin(), items.end(), [](const T& a, const T& b) { return a.osm_id < b.osm_id; });
  items.erase(std::unique(items.begin(), items.end(),
                          [](const T& a, const T& b) { return a.osm_id == b.osm_id; }),
              items.end());
  // The tables grew by doubling and are held through segmenting, the build's peak: the spare
  // capacity (up to half) is given back while the reading's own buffers are larger anyway.
  items.shrink_to_fit();
}

}  // namespace

RoadNetwork read_road_network(const std::string& path, Progress& progress, ExtraOsmReader* extra) {
  return read_road_network(std::vector<std::string>{path}, progress, extra);
}

RoadNetwork read_road_network(const std::vector<std::string>& paths, Progress& progress,
                              ExtraOsmReader* extra) {
  if (paths.empty()) throw InputError("--osm", "no OSM input given");
  for (const std::string& each : paths) check_readable(each);
  // Errors about the input as a whole name every file of it.
  std::string path = paths.front();
  for (std::size_t i = 1; i < paths.size(); ++i) path += " + " + paths[i];
  RoadNetwork network;
  network.source_path = path;
  try {
    progress.start_stage("reading road ways", "MB");
    RoadWayCollector ways(network);
    const auto first_pass = extra && extra->wants_relations()
                                ? osmium::osm_entity_bits::way | osmium::osm_entity_bits::relation
                                : osmium::osm_entity_bits::way;
    read_pass(paths, first_pass, ways, extra, progress);
    // The extra reader's preparation for the node pass (the sight obstacles': their node
    // references sorted by id, their slots laid out, ~0.1 s at 10x tiled Monaco) runs on the
    // second core beside the road tables' sorting below and the node pass's start (its first
    // blocks decoded); the nodes the node pass reads meanwhile wait for it (ExtraHandler). (A
    // std::async future: an exception on this thread waits for it too.)
    WaysDone extra_ways_done;
    if (extra) extra_ways_done.start(*extra);
    sort_by_id_unique(network.ways);
    sort_by_id_unique(network.crossing_ways);
    progress.finish_stage(std::to_string(network.ways.size()) + " road ways of " +
                          std::to_string(network.ways_read) + " ways");

    std::vector<std::int64_t> wanted;
    for (const RoadWay& way : network.ways)
      wanted.insert(wanted.end(), way.node_ids.begin(), way.node_ids.end());
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());

    // Nodes of crossing ways that no road uses (their locations find where they cross a road).
    std::vector<std::int64_t> crossing_only;
    for (const CrossingWay& way : network.crossing_ways) {
      for (std::int64_t id : way.node_ids) {
        if (!std::binary_search(wanted.begin(), wanted.end(), id)) crossing_only.push_back(id);
      }
    }
    sort_by_id_unique(network.sidewalk_ways);
    for (const SidewalkWay& way : network.sidewalk_ways) {
      for (std::int64_t id : way.node_ids) {
        if (!std::binary_search(wanted.begin(), wanted.end(), id)) crossing_only.push_back(id);
      }
    }
    std::sort(crossing_only.begin(), crossing_only.end());
    crossing_only.erase(std::unique(crossing_only.begin(), crossing_only.end()),
                        crossing_only.end());

    progress.start_stage("reading node locations", "MB");
    NodeLocationCollector nodes(network, wanted, crossing_only);
    read_pass(paths, osmium::osm_entity_bits::node, nodes, extra, progress, &extra_ways_done);
    extra_ways_done.wait();  // a file without nodes
    if (extra) extra->nodes_done();
    sort_by_id_unique(network.locations);
    sort_by_id_unique(network.crossing_way_locations);
    sort_by_id_unique(network.tagged_nodes);
    sort_by_id_unique(network.crossing_way_tagged_nodes);
    network.missing_locations = wanted.size() - network.locations.size();
    progress.finish_stage(std::to_string(network.locations.size()) + " road nodes of " +
                          std::to_string(network.nodes_read) + " nodes");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    // libosmium's XML errors already say "XML parsing error at line L, column C: ...".
    throw InputError(path, std::string("not readable as OSM data: ") + e.what());
  }
  if (network.ways_read == 0 && network.nodes_read == 0) {
    throw InputError(path, "contains no OSM nodes or ways (is it an OSM file?)");
  }
  if (network.ways.empty()) {
    throw InputError(path, "contains " + std::to_string(network.ways_read) +
                               " ways but none is a road of a kept class (highway=primary, "
                               "secondary, tertiary, residential, service, ...)");
  }
  return network;
}

}  // namespace roadcross::preprocess
