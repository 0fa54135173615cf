// roadcross-build as a library call: OSM and elevation in, one GeoPackage out.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/parameters.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"

namespace roadcross::preprocess {

struct BuildOptions {
  std::string osm_path;
  /// Further OSM extracts read with osm_path as one road network: merged by object id (an
  /// object several files hold is read once), each file sorted by type and id. The UTM zone
  /// is chosen for the merged network as for one file.
  std::vector<std::string> extra_osm_paths;
  std::string output_path;
  Parameters parameters;
  /// Elevation inputs (XYZ point files and rasters, in the order given) and the CRS of the XYZ
  /// files; no source: the build runs without terrain (NO_ELEVATION everywhere).
  TerrainInputs elevation;
  std::string overrides_path;  ///< operator overrides (GeoJSON), optional
  std::string country;         ///< ISO code for implicit speed limits; empty: detect
  bool show_progress = false;
  std::string tool_version;
  /// Tests only (the CLI sets none): where a test makes the build's threads fail, or wait.
  struct TestHooks {
    /// On a sight thread, after each chunk of segments it finished: how many segments are final
    /// (the prefix the segment rows are written from).
    std::function<void(std::size_t final_segments)> after_sight_chunk;
    /// On the thread writing the segment rows during the sight stage, before rows [begin, end).
    std::function<void(std::size_t begin, std::size_t end)> before_row_batch;
    /// Rows of such a batch; 0: the build's own.
    std::size_t row_batch = 0;
  } test_hooks;
};

struct BuildSummary {
  geo::UtmZone zone;
  std::uint64_t road_ways = 0;
  std::uint64_t pieces = 0;
  std::uint64_t segments = 0;
  std::uint64_t junctions = 0;
  double total_length_m = 0.0;
  std::uint64_t missing_node_refs = 0;
  double seconds = 0.0;
  std::vector<StageRecord> stages;  ///< name, seconds and summary of every stage, in order
  std::int64_t peak_rss_kib = 0;    ///< peak resident memory of the process, KiB
  std::uint64_t crossings = 0;
  bool has_elevation = false;
  TerrainReport terrain;  ///< filled when elevation inputs were given
  /// Lines for the user: defaults taken per tag, crossings, overrides that matched nothing.
  std::vector<std::string> notes;
};

/// Runs the whole build. The output appears only when everything succeeded: on any exception
/// (InputError, ParameterError, OutputError) no file is left at `output_path`.
BuildSummary run_build(const BuildOptions& options);

}  // namespace roadcross::preprocess
