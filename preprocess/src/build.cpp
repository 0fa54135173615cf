#include "roadcross/preprocess/build.hpp"

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <functional>
#include <future>
#include <optional>
#include <utility>

#include "roadcross/files/atomic_file.hpp"
#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/gdal_module.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/common/sha256.hpp"
#include "roadcross/preprocess/context/context.hpp"
#include "roadcross/preprocess/context/osm_tags.hpp"
#include "roadcross/preprocess/context/overrides.hpp"
#include "roadcross/preprocess/geometry/geometry_cost.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/output/gpkg_writer.hpp"
#include "roadcross/preprocess/output/terrain_coverage.hpp"
#include "roadcross/preprocess/rank.hpp"
#include "roadcross/preprocess/sight/sight.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"
#include "roadcross/schema/schema.hpp"

namespace roadcross::preprocess {

namespace {

/// Gives the heap's free pages back to the system. The network's millions of small blocks
/// (tags, node lists) and the stages' hash maps, once freed, leave holes in glibc's heap that
/// stay resident; the later stages allocate mostly large blocks (mmap, fresh pages), so without
/// this the holes would add to the peak.
void return_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

/// ISO 8601 UTC of a POSIX time; `format`: strftime's, e.g. "%Y-%m-%dT%H:%M:%SZ".
std::string utc_text(std::int64_t seconds_since_epoch, const char* format) {
  const std::time_t t = static_cast<std::time_t>(seconds_since_epoch);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[32];
  std::strftime(text, sizeof text, format, &utc);
  return text;
}

/// "2026-03-01T12:00:00.000Z", as GeoPackage's last_change wants it.
std::string iso8601_utc(std::int64_t seconds_since_epoch) {
  return utc_text(seconds_since_epoch, "%Y-%m-%dT%H:%M:%S.000Z");
}

/// "2026-03-01T12:00:00Z": ISO 8601 UTC to the second (OSM timestamps have no fraction).
std::string iso8601_utc_seconds(std::int64_t seconds_since_epoch) {
  return utc_text(seconds_since_epoch, "%Y-%m-%dT%H:%M:%SZ");
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// The buildings' and walls' edges near the roads (the sight stage's obstacles), taken from
/// `reader` on another thread: they need only the roads' zone and box, known once the graph is
/// built, and the stages between do not read the reader.
std::future<Obstacles> take_obstacles_aside(ObstacleReader& reader, const RoadGraph& graph,
                                            const RoadBounds& roads) {
  const PlanePoint min{roads.min_e, roads.min_n}, max{roads.max_e, roads.max_n};
  constexpr double kReachM = 100.0;  // well beyond half of any carriageway's width
  return std::async(std::launch::async, [&reader, zone = graph.zone, min, max] {
    return reader.take_edges(zone, min, max, kReachM);
  });
}

/// Buildings and walls from the OSM file (`taken`: take_obstacles_aside's), then the sight
/// distance of every segment over the stored terrain grid. The grid covers the roads' box plus
/// the largest TPI radius, and every sight line joins two points within half a road width of
/// that box: the whole line is on it. `final_segments`: compute_sight's.
std::vector<std::string> run_sight_stage(const BuildOptions& options, RoadGraph& graph,
                                         const Grid* terrain, std::future<Obstacles>& taken,
                                         DonePrefix* final_segments, Progress& progress) {
  const SightParameters& p = options.parameters.sight;
  progress.start_stage("buildings and walls");
  Obstacles obstacles = taken.get();
  progress.finish_stage(std::to_string(obstacles.report.buildings) + " buildings, " +
                        std::to_string(obstacles.report.walls) + " walls, " +
                        std::to_string(obstacles.report.fences) + " fences, " +
                        std::to_string(obstacles.report.edges) +
                        " edges (taken beside the stages since segmenting)");
  progress.start_stage("sight distance");
  const SightReport report = compute_sight(graph, terrain, obstacles.edges, p, final_segments);
  obstacles.edges = ObstacleEdges();
  progress.finish_stage(
      std::to_string(report.segments) + " segments, " + std::to_string(report.limited) +
      " LIMITED_VISIBILITY, " + std::to_string(report.lines_of_sight) + " lines of sight, " +
      std::to_string(report.fans) + " fans (" + std::to_string(report.clear_fans) + " clear, " +
      std::to_string(report.fan_positions) + " positions settled at once; " +
      std::to_string(report.candidate_edges) + " candidate edges); " +
      std::to_string(report.open_directions) + " of " +
      std::to_string(report.open_directions_tried) + " directions tried open to both kerbs");
  std::vector<std::string> notes;
  notes.push_back("sight distance: " + std::to_string(report.limited) + " of " +
                  std::to_string(report.segments) + " segments LIMITED_VISIBILITY (" +
                  std::to_string(report.skipped_tunnels) + " tunnel segments not computed)");
  notes.push_back("sight obstacles: " + std::to_string(obstacles.report.buildings) +
                  " buildings, " + std::to_string(obstacles.report.walls) + " walls, " +
                  std::to_string(obstacles.report.fences) + " fences (" +
                  std::to_string(obstacles.report.default_height) + " with a default height, " +
                  std::to_string(obstacles.report.relations_skipped) +
                  " multipolygon buildings not read)");
  return notes;
}

/// Runs `write`, naming the file the user asked for in its OutputError (the temporary one is
/// gone when the error propagates).
template <typename Write>
void naming_the_output(const BuildOptions& options, Write&& write) {
  try {
    write();
  } catch (const OutputError& e) {
    throw OutputError(options.output_path + ": " + e.what() +
                      " (is the disk full, or a file size limit reached?)");
  }
}

/// Every OSM input: osm_path, then extra_osm_paths.
std::vector<std::string> osm_inputs(const BuildOptions& options) {
  std::vector<std::string> paths{options.osm_path};
  paths.insert(paths.end(), options.extra_osm_paths.begin(), options.extra_osm_paths.end());
  return paths;
}

/// SHA-256 of every input file, for the provenance metadata.
struct InputHashes {
  std::vector<std::string> osm;        ///< in the order of osm_inputs(options)
  std::vector<std::string> elevation;  ///< in the order of options.elevation.sources
  std::string overrides;               ///< empty without an overrides file
};

InputHashes hash_inputs(const BuildOptions& options) {
  InputHashes hashes;
  for (const std::string& path : osm_inputs(options)) hashes.osm.push_back(sha256_of_file(path));
  for (const ElevationSource& source : options.elevation.sources) {
    hashes.elevation.push_back(sha256_of_file(source.path));
  }
  if (!options.overrides_path.empty()) hashes.overrides = sha256_of_file(options.overrides_path);
  return hashes;
}

/// What the stages hand on to each other.
struct Pipeline {
  RoadNetwork network;
  RoadGraph graph;
  RoadBounds roads;
  ContextReport context;
  std::vector<Override> overrides;
  Parameters parameters;  ///< as given, with the terrain cell size chosen
  CellSizeChoice cell;
  TerrainReport terrain;
  Grid terrain_grid{GridSpec{}};
  std::vector<std::string> sight_notes;
  std::size_t road_ways = 0;
  std::size_t junctions = 0;
  std::string last_change;
  /// The newest OSM object's timestamp (ISO 8601), none when the input has none.
  std::optional<std::string> osm_timestamp;
};

/// The folder an output path is in ("." for a bare name).
std::string folder_of(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? std::string(".") : parent;
}

void check_options(const BuildOptions& options) {
  options.parameters.validate();
  if (options.osm_path.empty()) throw ParameterError("an OSM input file is required (--osm)");
  if (options.output_path.empty()) throw ParameterError("an output path is required (-o)");
  // Elevation needs the GDAL module: a missing one fails here, before minutes of work.
  if (!options.elevation.sources.empty()) gdal_module();
  if (!options.country.empty() && !has_implicit_speeds(options.country)) {
    throw ParameterError("--country " + options.country +
                         ": no implicit speed limits for it (known: CZ, SK, DE, AT, PL, FR, MC, "
                         "default)");
  }
}

void segment_stage(const BuildOptions& options, Pipeline& p, Progress& progress) {
  progress.start_stage("segmenting");
  const geo::UtmZone zone = choose_utm_zone(p.network);
  p.graph = build_road_graph(p.network, zone, options.parameters.segments.max_segment_length_m);
  if (p.graph.segments.empty()) {
    throw InputError(p.network.source_path, "no road way has two nodes with locations in the file");
  }
  p.roads = road_bounds(p.graph);
  progress.finish_stage(std::to_string(p.graph.segments.size()) + " segments in UTM zone " +
                        std::to_string(zone.zone) + (zone.northern ? "N" : "S"));
  p.last_change = iso8601_utc(p.network.newest_timestamp_s);
  // An OSM file without timestamps (osmium's --omit-timestamp, many extracts' nodes) reads as 0:
  // no timestamp then, rather than 1970.
  if (p.network.newest_timestamp_s > 0)
    p.osm_timestamp = iso8601_utc_seconds(p.network.newest_timestamp_s);
}

/// The context stage's tag and crossing part reads only what segmenting set, so it runs first:
/// the ways, their tags and the node locations are then freed before the cost stages and the
/// writing add to the peak memory.
void context_tags_stage(const BuildOptions& options, Pipeline& p, Progress& progress) {
  progress.start_stage("context");
  p.context = compute_way_context(p.graph, p.network, options.parameters.context, options.country);
  progress.finish_stage(std::to_string(p.context.crossings.size()) + " crossings");
  p.road_ways = p.network.ways.size();
  p.network = RoadNetwork{};
  // The crossings search above was the last reader of the pieces' node ids.
  p.graph.free_piece_node_ids();
  return_freed_memory();
}

void geometry_stage(const BuildOptions& options, Pipeline& p, Progress& progress) {
  progress.start_stage("geometry cost");
  compute_geometry_costs(p.graph, options.parameters.geometry);
  // The node degrees were the geometry stage's (junctions); counted for the summary and freed
  // before the terrain stage, whose tiles and stored grid make the DEM build's peak.
  for (const auto& [node, degree] : p.graph.degree) p.junctions += degree >= 3 ? 1 : 0;
  p.graph.degree = {};
  return_freed_memory();
  progress.finish_stage("class, junctions, curvature");
}

/// `segment_index`: the R*Tree being written beside the cost stages; it finishes before the
/// terrain's grids and both cores' tiles are allocated (overlapping the two would add their
/// peaks; its errors come at get(), later).
void terrain_stage(const BuildOptions& options, Pipeline& p, std::future<void>& segment_index,
                   Progress& progress) {
  // The cell size follows the elevation inputs when not given; their zone and the roads are
  // known only now. The DB's metadata records the size used.
  p.parameters = options.parameters;
  p.cell = choose_cell_size(p.graph.zone, p.roads, options.elevation, p.parameters.terrain);
  p.parameters.terrain.cell_size_m = p.cell.cell_m;
  p.parameters.validate();
  if (options.elevation.sources.empty()) {
    mark_without_elevation(p.graph);
    return;
  }
  segment_index.wait();
  p.terrain = compute_terrain(p.graph, p.roads, options.elevation, p.cell, p.parameters.terrain,
                              progress, &p.terrain_grid);
}

/// The crossing distances (a search over the whole graph, so run once the network is freed) pick
/// the context scores; the overrides change any cost, so they (and BUSY_ROAD after them) come
/// after the other stages.
void context_scores_stage(const BuildOptions& options, Pipeline& p,
                          std::future<void>& crossing_distances, Progress& progress) {
  progress.start_stage("context: crossing distances, overrides");
  crossing_distances.get();
  score_context(p.graph, options.parameters.context, p.overrides, p.context);
  progress.finish_stage(std::to_string(p.context.busy_segments) + " BUSY_ROAD segments");
}

/// The metadata rows: parameters, tool, attribution, inputs by file name and hash (not by
/// absolute path, so that the same inputs give the same bytes wherever they are built).
std::vector<std::pair<std::string, std::string>> metadata_rows(const BuildOptions& options,
                                                               const Pipeline& p,
                                                               const InputHashes& hashes) {
  std::vector<std::pair<std::string, std::string>> rows = p.parameters.as_metadata();
  rows.emplace_back(schema::meta::kToolVersion, options.tool_version);
  rows.emplace_back(schema::meta::kAttribution,
                    "Map data (c) OpenStreetMap contributors, ODbL 1.0");
  if (p.osm_timestamp) rows.emplace_back(schema::meta::kOsmTimestamp, *p.osm_timestamp);
  // The OSM inputs are input.0 .. input.<k-1> in the order given, the elevation inputs next.
  const std::vector<std::string> osm_paths = osm_inputs(options);
  for (std::size_t i = 0; i < osm_paths.size(); ++i) {
    const std::string input = std::string(schema::meta::kInputPrefix) + std::to_string(i) + ".";
    rows.emplace_back(input + "kind", "osm");
    rows.emplace_back(input + "file", base_name(osm_paths[i]));
    rows.emplace_back(input + "sha256", hashes.osm[i]);
  }
  for (std::size_t i = 0; i < options.elevation.sources.size(); ++i) {
    const ElevationSource& source = options.elevation.sources[i];
    const std::string key =
        std::string(schema::meta::kInputPrefix) + std::to_string(i + osm_paths.size()) + ".";
    const bool xyz = source.kind == ElevationKind::xyz;
    rows.emplace_back(key + "kind", xyz ? "elevation-xyz" : "elevation-raster");
    rows.emplace_back(key + "file", base_name(source.path));
    rows.emplace_back(key + "sha256", hashes.elevation[i]);
    if (xyz) rows.emplace_back(key + "crs", p.terrain.xyz_crs);
  }
  rows.emplace_back(schema::meta::kContextCountry, p.context.country.country);
  rows.emplace_back(schema::meta::kCrossingCount, std::to_string(p.context.crossings.size()));
  if (!options.overrides_path.empty()) {
    // The next free input number (other inputs, e.g. elevation, may be recorded before).
    std::size_t n = 0;
    for (const auto& [key, value] : rows) n += key.ends_with(".kind") ? 1 : 0;
    const std::string overrides_input =
        std::string(schema::meta::kInputPrefix) + std::to_string(n) + ".";
    rows.emplace_back(overrides_input + "kind", "overrides");
    rows.emplace_back(overrides_input + "file", base_name(options.overrides_path));
    rows.emplace_back(overrides_input + "sha256", hashes.overrides);
  }
  return rows;
}

/// `streamed_rows`: the segment rows' writer when they were written during the sight stage
/// (it waited for `segment_index`); null: they are written here.
void write_stage(const BuildOptions& options, Pipeline& p, const InputHashes& hashes,
                 GeoPackageWriter& writer, std::future<void>& segment_index,
                 std::future<void>* streamed_rows, const AtomicOutput& output, Progress& progress) {
  DatabaseContents contents;
  contents.graph = &p.graph;
  contents.crossings = &p.context.crossings;
  contents.last_change = p.last_change;
  contents.metadata = metadata_rows(options, p, hashes);
  progress.start_stage("spatial index");
  if (!streamed_rows) naming_the_output(options, [&] { segment_index.get(); });
  progress.finish_stage("R*Tree of " + std::to_string(p.graph.segments.size()) +
                        " segments (written during the cost stages)");
  naming_the_output(options, [&] {
    writer.finish(contents, progress, streamed_rows);
    if (!options.elevation.sources.empty()) {
      progress.start_stage("writing the terrain grid");
      write_terrain_coverage(output.temp_path(), std::move(p.terrain_grid), contents.last_change);
      progress.finish_stage(std::string("table ") + kTerrainTable);
    }
    // The tables are complete: the disk writes them while the identity is computed (it only
    // reads them), so that the fsync before the rename has little left to wait for.
    output.start_writeback();
    // Last: the identity covers every table written above. The segments' digests come from
    // the rows the writer inserted; the other (small) tables are read back, each thread a share
    // of their columns.
    progress.start_stage("map identity");
    try {
      const std::string map_id = mapcheck::stamp_map_id(
          output.temp_path(), std::min(core_count(), 4u), writer.segment_digest());
      progress.finish_stage("map_id " + map_id);
    } catch (const std::exception& e) {
      throw OutputError(std::string("cannot write the map_id: ") + e.what());
    }
  });
}

/// The sight stage on both cores, with the segment rows written beside it on a third thread as
/// the segments become final (DonePrefix), then the rest of the GeoPackage. The rows' CPU time
/// then fills the cores during the stage instead of running after it. The rows need their rank
/// (with the sight's penalty): set by the writer's thread just before a batch, from the same
/// per-segment functions as compute_ranks and apply_sight_rank_penalty.
void sight_and_segment_rows(const BuildOptions& options, Pipeline& p, GeoPackageWriter& writer,
                            std::future<void>& segment_index, std::future<Obstacles>& obstacles,
                            std::future<InputHashes>& input_hashes, const AtomicOutput& output,
                            Progress& progress) {
  // Rows a batch: the writer wakes once a batch, and the batch's pages (≈ 5 MiB) are the page
  // cache it keeps beside the sight stage's memory.
  constexpr std::size_t kRowBatch = 16384;
  DonePrefix final_segments(p.graph.segments.size());
  final_segments.after_done_for_tests = options.test_hooks.after_sight_chunk;
  const auto before_batch = [&](std::size_t begin, std::size_t end) {
    if (options.test_hooks.before_row_batch) options.test_hooks.before_row_batch(begin, end);
    // The rows written so far go to the disk while the sight stage runs, not at the fsync
    // before the rename (at 200x the file is 1.4 GB: a second and more of waiting at the end).
    if (begin > 0) output.start_writeback();
    for (std::size_t i = begin; i < end; ++i) {
      Segment& s = p.graph.segments[i];
      compute_rank(p.graph, s, options.parameters.rank);
      apply_sight_rank_penalty(s, options.parameters.sight);
    }
  };
  // Declared after final_segments: an exception below waits for the writer before the prefix it
  // reads is destroyed.
  std::future<void> rows = std::async(std::launch::async, [&] {
    try {
      // The same connection: the rows come after the index (written during the cost stages; a
      // tiny map's sight stage can end before it).
      segment_index.get();
      writer.write_segment_rows_as_final(
          p.graph, p.parameters.as_metadata(), final_segments, before_batch,
          options.test_hooks.row_batch ? options.test_hooks.row_batch : kRowBatch);
    } catch (...) {
      final_segments.stop();  // the sight threads end at their next chunk
      throw;
    }
  });
  try {
    p.sight_notes = run_sight_stage(options, p.graph,
                                    options.elevation.sources.empty() ? nullptr : &p.terrain_grid,
                                    obstacles, &final_segments, progress);
  } catch (const DonePrefix::Stopped&) {
    // The writer failed (a full disk): its error is the build's.
    naming_the_output(options, [&] { rows.get(); });
    throw std::logic_error("the sight stage was stopped by a segment-row writer that did not fail");
  } catch (...) {
    final_segments.abandon();  // the writer's wait throws: it ends before the error is reported
    rows.wait();
    throw;
  }
  write_stage(options, p, input_hashes.get(), writer, segment_index, &rows, output, progress);
}

BuildSummary summarize(const BuildOptions& options, const Pipeline& p, Progress& progress) {
  const RoadGraph& graph = p.graph;
  const bool has_elevation = !options.elevation.sources.empty();
  BuildSummary summary;
  summary.zone = graph.zone;
  summary.road_ways = p.road_ways;
  summary.pieces = graph.pieces.size();
  summary.segments = graph.segments.size();
  summary.junctions = p.junctions;
  for (const Segment& s : graph.segments) summary.total_length_m += graph.length_m(s);
  summary.missing_node_refs = graph.dropped_node_refs;
  summary.crossings = p.context.crossings.size();
  summary.notes = p.context.summary_lines();
  summary.notes.insert(summary.notes.end(), p.sight_notes.begin(), p.sight_notes.end());
  summary.has_elevation = has_elevation;
  summary.terrain = p.terrain;
  if (has_elevation) {
    const TerrainReport& terrain = p.terrain;
    summary.notes.push_back("terrain grid cell size: " + format_number(p.cell.cell_m) + " m (" +
                            p.cell.source + ")");
    summary.notes.push_back(std::to_string(terrain.segments_without_elevation) + " of " +
                            std::to_string(graph.segments.size()) +
                            " segments have no elevation (NO_ELEVATION; rank without the term)");
    if (terrain.structure_segments > 0) {
      summary.notes.push_back(std::to_string(terrain.structure_segments) +
                              " bridge/tunnel segments take their elevation from the structure's "
                              "ends");
    }
    for (const auto& [path, cells] : terrain.cells_per_source) {
      if (cells == 0) summary.notes.push_back("elevation input " + path + " covers no road");
    }
  } else {
    summary.notes.push_back("no elevation input (--elevation): every segment is NO_ELEVATION");
  }
  summary.stages = progress.stages();
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) == 0) summary.peak_rss_kib = usage.ru_maxrss;
  return summary;
}

}  // namespace

BuildSummary run_build(const BuildOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  check_options(options);
  Pipeline p;
  // Overrides are read before the long work so that a bad file fails at once.
  if (!options.overrides_path.empty()) p.overrides = read_overrides(options.overrides_path);
  // What builds killed in this folder left (SIGKILL cannot be caught): their temporary files
  // are locked by no process any more.
  const std::vector<std::string> removed_temporaries =
      files::remove_dead_temporaries(folder_of(options.output_path));
  // Create the temporary output first: an unwritable target fails before minutes of work.
  AtomicOutput output(options.output_path);
  Progress progress(options.show_progress);

  // The sight stage's buildings and walls are read in the same two passes as the roads.
  const bool with_sight = options.parameters.sight.enabled != 0.0;
  ObstacleReader obstacle_reader(options.parameters.sight);
  p.network =
      read_road_network(osm_inputs(options), progress, with_sight ? &obstacle_reader : nullptr);
  // Hashing the inputs runs on the second core while the single-threaded stages run on the
  // first. (A std::async future waits for the hash if a stage throws.)
  std::future<InputHashes> input_hashes =
      std::async(std::launch::async, hash_inputs, std::cref(options));
  segment_stage(options, p, progress);
  // The obstacles' projection and compaction run beside the stages up to the sight stage, on
  // the core that segmenting and context leave idle. (Declared after the reader and the
  // pipeline: a stage's exception waits for it first.)
  std::future<Obstacles> obstacles;
  if (with_sight) obstacles = take_obstacles_aside(obstacle_reader, p.graph, p.roads);
  context_tags_stage(options, p, progress);

  // The segments' spatial index needs only their lines, which are final from here on: it is
  // written on the second core while the cost stages run. Started only now, with the network
  // freed: its working set and SQLite's page cache would otherwise add to the network's memory.
  // Declared after the pipeline and the writer, so that a stage's exception waits for it first.
  std::optional<GeoPackageWriter> writer;
  naming_the_output(options,
                    [&] { writer.emplace(output.temp_path(), p.graph.zone, p.last_change); });
  std::future<void> segment_index =
      std::async(std::launch::async, [&] { writer->write_segment_index(p.graph); });

  // The crossing distances' search is serial and needs only the pieces' ends and lengths (final
  // from here on); it writes only the segments' crossing distances, which no cost stage reads:
  // it runs beside the geometry stage, on the core its own serial parts leave idle.
  std::future<void> crossing_distances = std::async(
      std::launch::async, [&] { assign_crossing_distances(p.graph, p.context.crossings); });

  // The cost stages, in this order; each fills its Segment fields and appends its reasons.
  geometry_stage(options, p, progress);
  terrain_stage(options, p, segment_index, progress);
  context_scores_stage(options, p, crossing_distances, progress);
  if (with_sight) {
    sight_and_segment_rows(options, p, *writer, segment_index, obstacles, input_hashes, output,
                           progress);
  } else {
    compute_ranks(p.graph, options.parameters.rank);
    apply_sight_rank_penalty(p.graph, options.parameters.sight);
    write_stage(options, p, input_hashes.get(), *writer, segment_index, nullptr, output, progress);
  }
  output.commit();

  BuildSummary summary = summarize(options, p, progress);
  for (const std::string& path : removed_temporaries) {
    summary.notes.push_back("removed " + path + ", left by a build that was killed");
  }
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

}  // namespace roadcross::preprocess
