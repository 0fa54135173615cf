// The terrain stage (compute_terrain): the terrain grid built and analysed tile by tile, two
// tiles at a time, each with a halo of the large TPI radius, so that memory follows the tile and
// not the map; XYZ points binned by tile (spilled past a budget); the TPI statistics summed in
// tile order; the tiles' own cells copied into the grid stored in the DB. The per-grid analysis
// (slope, TPI annuli, landforms, per-segment terms) is in terrain.cpp.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <mutex>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"
#include "roadcross/preprocess/terrain/xyz_tiles.hpp"

namespace roadcross::preprocess {

namespace {

/// Every XYZ point of every file, in UTM, read chunk by chunk into the bins of the tiles that
/// need them (one TIN per tile is made from each bin).
void read_xyz_files(const std::vector<const ElevationSource*>& files, const std::string& crs_given,
                    const geo::UtmZone& zone, XyzTileBins& bins, TerrainReport& report,
                    Progress& progress) {
  constexpr std::size_t kChunkPoints = std::size_t(1) << 16;  // 1.5 MB
  for (const ElevationSource* source : files) {
    std::unique_ptr<CrsTransform> transform;
    std::vector<double> x, y;
    read_xyz_chunks(source->path, kChunkPoints, [&](std::vector<ElevationPoint>& chunk) {
      // Without --elevation-crs every chunk must look like the detected CRS.
      const std::string crs = crs_given.empty() ? detect_xyz_crs(source->path, chunk) : crs_given;
      if (!transform) {
        if (!report.xyz_crs.empty() && report.xyz_crs != crs) {
          throw InputError(source->path, "its points look like " + crs +
                                             " but an earlier XYZ file's like " + report.xyz_crs +
                                             "; give --elevation-crs");
        }
        report.xyz_crs = crs;
        transform = std::make_unique<CrsTransform>(crs, zone);
      }
      x.resize(chunk.size()), y.resize(chunk.size());
      for (std::size_t i = 0; i < chunk.size(); ++i) x[i] = chunk[i].x, y[i] = chunk[i].y;
      transform->to_utm(x, y);
      for (std::size_t i = 0; i < chunk.size(); ++i) {
        chunk[i].x = x[i], chunk[i].y = y[i];
        report.xyz_points += std::isnan(x[i]) ? 0 : 1;
      }
      bins.add(chunk);
      progress.update(report.xyz_points, 0);
    });
  }
}

/// Running sums for the TPI statistics over the tiles' core cells.
struct RunningStatistics {
  double sum = 0.0, sum_sq = 0.0;
  std::size_t count = 0;
  void add(float v) {
    if (std::isnan(v)) return;
    sum += v, sum_sq += double(v) * v, ++count;
  }
  GridStatistics result() const {
    GridStatistics out;
    out.count = count;
    if (count == 0) return out;
    out.mean = sum / double(count);
    out.standard_deviation = std::sqrt(std::max(0.0, sum_sq / double(count) - out.mean * out.mean));
    return out;
  }
};

/// The terrain grid is worked on in square tiles of the road network's bounding box, each with a
/// halo of one large TPI radius, so memory follows the tile, not the map.
struct TileLayout {
  double west_m = 0.0, south_m = 0.0, size_m = 0.0;
  std::size_t cols = 1, rows = 1;
  std::size_t tile_col(double easting_m) const {
    return std::min(cols - 1,
                    static_cast<std::size_t>(std::max(0.0, (easting_m - west_m) / size_m)));
  }
  std::size_t tile_row(double northing_m) const {
    return std::min(rows - 1,
                    static_cast<std::size_t>(std::max(0.0, (northing_m - south_m) / size_m)));
  }
  std::size_t tile_of(const PlanePoint& p) const { return tile_row(p.y) * cols + tile_col(p.x); }
};

/// Copies the cells of `stored` that the tile owns from the tile's grid (bilinear: exact where
/// the cells coincide, i.e. when stored at full resolution). Only the stored cells over the
/// tile's grid are visited (the others would sample NaN, which they hold already): visiting
/// whole rows of the map for every tile made this the slowest part of a tile at 10x Monaco.
template <typename Owns>
void copy_owned(const Grid& tile, const Owns& owns, Grid& stored) {
  const GridSpec& g = stored.spec;
  // Stored columns around the tile's grid, with one column to spare each side for rounding.
  const double first = std::floor((tile.spec.west_m - g.west_m) / g.cell_m) - 1.0;
  const double last = std::ceil((tile.spec.east_m() - g.west_m) / g.cell_m) + 1.0;
  const auto col_begin = static_cast<std::size_t>(std::clamp(first, 0.0, double(g.cols)));
  const auto col_end = static_cast<std::size_t>(std::clamp(last, 0.0, double(g.cols)));
  for (std::size_t row = 0; row < g.rows; ++row) {
    const double y = g.centre_northing(row);
    if (y < tile.spec.south_m || y > tile.spec.north_m()) continue;
    for (std::size_t col = col_begin; col < col_end; ++col) {
      const double x = g.centre_easting(col);
      if (x < tile.spec.west_m || x > tile.spec.east_m()) continue;
      if (owns(x, y)) stored.at(col, row) = static_cast<float>(tile.sample(x, y));
    }
  }
}

/// TPI of one annulus on one tile, computed only where it is needed: at the cells of the
/// statistics' lattice that the tile owns (their values appended to `lattice_tpi_m`, row by
/// row, NaN left out) and at the four cells around each segment's midpoint (bilinear, exactly
/// as sampling a whole TPI grid). The cells are visited in one sweep south to north, lattice
/// and segments' cells together, so that the annulus' prefix sums need only a band of rows.
struct TileTpi {
  const Grid& elevation;
  const std::vector<char>& col_owned;
  const std::vector<char>& row_owned;
  long long col0, row0;  ///< the tile's cell (0, 0) in the whole grid
  long long step, offset;

  void run(AnnulusTpi& annulus, std::vector<float>& lattice_tpi_m,
           const std::vector<PlanePoint>& midpoints, std::vector<TerrainSample>& samples,
           float TerrainSample::*field) const {
    const GridSpec& g = elevation.spec;
    // The cells that each midpoint's bilinear sample reads (which ones does not depend on the
    // values), in its order of reading, then their row by row order (a counting sort).
    const std::size_t n = midpoints.size();
    std::vector<std::uint32_t> corner_col(4 * n), corner_row(4 * n);
    std::vector<std::uint32_t> rows_start(g.rows + 1, 0);
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t j = 4 * k;
      bilinear(g, midpoints[k].x, midpoints[k].y, [&](std::size_t c, std::size_t r) {
        corner_col[j] = static_cast<std::uint32_t>(c);
        corner_row[j] = static_cast<std::uint32_t>(r);
        ++rows_start[r + 1];
        ++j;
        return 0.0;
      });
      // Outside the grid it reads none: marked as rows past the last.
      for (; j < 4 * (k + 1); ++j) corner_row[j] = static_cast<std::uint32_t>(g.rows);
    }
    std::partial_sum(rows_start.begin(), rows_start.end(), rows_start.begin());
    std::vector<std::uint32_t> by_row(rows_start.back());
    {
      std::vector<std::uint32_t> next(rows_start.begin(), rows_start.end() - 1);
      for (std::size_t j = 0; j < 4 * n; ++j) {
        if (corner_row[j] < g.rows) by_row[next[corner_row[j]]++] = static_cast<std::uint32_t>(j);
      }
    }
    std::vector<float> corner_tpi_m(4 * n);
    for (std::size_t row = 0; row < g.rows; ++row) {
      if (row_owned[row] && (static_cast<long long>(row) + row0) % step == offset) {
        for (std::size_t col = 0; col < g.cols; ++col) {
          if (col_owned[col] && (static_cast<long long>(col) + col0) % step == offset) {
            const float tpi_m = annulus.at(col, row);
            if (!std::isnan(tpi_m)) lattice_tpi_m.push_back(tpi_m);
          }
        }
      }
      for (std::uint32_t i = rows_start[row]; i < rows_start[row + 1]; ++i) {
        const std::uint32_t j = by_row[i];
        corner_tpi_m[j] = annulus.at(corner_col[j], row);
      }
    }
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t j = 4 * k;
      samples[k].*field = static_cast<float>(
          bilinear(g, midpoints[k].x, midpoints[k].y, [&](std::size_t c, std::size_t r) {
            // The same reads in the same order as above.
            if (c != corner_col[j] || r != corner_row[j]) {
              throw std::logic_error("TileTpi: bilinear read another cell");
            }
            return corner_tpi_m[j++];
          }));
    }
  }
};

/// Cells of the grid kept in the DB: the terrain at the analysis resolution, or coarser by a
/// whole factor when that would exceed this many cells (a country at 5 m would be billions).
constexpr double kStoredGridMaxCells = 40e6;

/// The grid of each tile: the tile's core, clipped to the roads' box (its cells are the tile's
/// share of the statistics and of the stored grid), plus the halo.
struct TileGrids {
  geo::UtmZone zone;
  RoadBounds roads;
  TileLayout layout;
  double halo_m, cell_m, align_m;

  GridSpec operator()(std::size_t tile) const {
    const double tile_w = layout.west_m + double(tile % layout.cols) * layout.size_m;
    const double tile_s = layout.south_m + double(tile / layout.cols) * layout.size_m;
    const double core_w = std::max(tile_w, roads.min_e), core_s = std::max(tile_s, roads.min_n);
    const double core_e = std::min(tile_w + layout.size_m, roads.max_e);
    const double core_n = std::min(tile_s + layout.size_m, roads.max_n);
    return grid_covering(zone, core_w, core_s, core_e, core_n, halo_m, cell_m, align_m);
  }
};

/// What one tile adds to the whole map's totals. The TPI values at its statistics' lattice are
/// kept in order and summed in tile order (InOrderMerge), so that the TPI means and SDs, and so
/// the landforms, are the same bits whichever thread finishes a tile first.
struct TileResult {
  std::vector<float> small_lattice_tpi_m, large_lattice_tpi_m;
  std::vector<StructureEnds> structure_ends;  ///< the tile's bridge and tunnel segments'
  std::vector<std::size_t> cells_per_source;
  std::size_t voids_filled = 0, cells_with_elevation = 0;
};

/// Hands the tiles' results to `merge` in tile order (positions 0, 1, ...) whatever order they
/// arrive in; a result waits here until those before it came. Thread-safe.
class InOrderMerge {
 public:
  explicit InOrderMerge(std::size_t count) : pending_(count) {}

  template <typename Merge>
  void add(std::size_t position, TileResult result, const Merge& merge) {
    const std::lock_guard lock(mutex_);
    pending_[position] = std::move(result);
    for (; next_ < pending_.size() && pending_[next_]; ++next_) {
      merge(*pending_[next_]);
      pending_[next_].reset();
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::optional<TileResult>> pending_;
  std::size_t next_ = 0;
};

/// What a thread keeps from tile to tile: its rasters, opened at their first tile (GDAL datasets
/// are not thread-safe, and opening one per tile cost a GDALOpen and a PROJ set-up each time).
struct ThreadState {
  std::vector<std::unique_ptr<RasterElevation>> rasters;  ///< per source; null: not a raster
  // The last tile's elevation cells and void-fill flags: reused pages cost no page fault
  // (most tiles are the full tile size).
  std::vector<float> elevation_cells;
  std::vector<char> void_queued;
};

/// The segments of each tile (those whose midpoint it holds), in segment order, as one array
/// of 32-bit indices: 4 bytes a segment (a vector of 64-bit indices per tile, grown by
/// push_back, took ~12 at 200x Monaco).
class SegmentsByTile {
 public:
  SegmentsByTile(const RoadGraph& graph, const TileLayout& layout)
      : first_(layout.cols * layout.rows + 1, 0) {
    if (graph.segments.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw std::length_error("the terrain stage handles at most 2^32 - 1 segments, not " +
                              std::to_string(graph.segments.size()));
    }
    std::vector<std::uint32_t> tile_of(graph.segments.size());
    for (std::size_t i = 0; i < graph.segments.size(); ++i) {
      const auto tile =
          static_cast<std::uint32_t>(layout.tile_of(segment_midpoint(graph, graph.segments[i])));
      tile_of[i] = tile;
      ++first_[tile + 1];
    }
    std::partial_sum(first_.begin(), first_.end(), first_.begin());
    segments_.resize(graph.segments.size());
    std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t i = 0; i < tile_of.size(); ++i) {
      segments_[next[tile_of[i]]++] = static_cast<std::uint32_t>(i);
    }
  }
  std::size_t tiles() const { return first_.size() - 1; }
  std::span<const std::uint32_t> operator[](std::size_t tile) const {
    return {segments_.data() + first_[tile], first_[tile + 1] - first_[tile]};
  }

 private:
  std::vector<std::size_t> first_;  ///< tile t's segments: [first_[t], first_[t + 1])
  std::vector<std::uint32_t> segments_;
};

/// One tile's analysis, start to end on one thread: the tiles run two at a time, one per core,
/// so that no part of a tile (the void fill, the per-segment sampling, the copy into the stored
/// grid) leaves a core idle. Tiles write only their own segments' samples and their own cells
/// of the stored grid.
struct TileJob {
  RoadGraph& graph;  ///< each tile writes the terrain fields of its own segments only
  const TerrainInputs& inputs;
  const TerrainParameters& p;
  const GridSpec& whole;  ///< the whole terrain grid
  const TileGrids& grids;
  const SegmentsByTile& segments_of_tile;
  long long small_step, large_step, large_offset;  ///< the statistics' lattices, cells
  XyzTileBins& xyz_bins;
  std::mutex& xyz_mutex;
  Grid& stored;

  TileResult run(std::size_t tile, ThreadState& thread) const;

 private:
  void fill_elevation(std::size_t tile, Grid& elevation, ThreadState& thread,
                      TileResult& out) const;
  void sample_elevation(const Grid& elevation, std::span<const std::uint32_t> segments,
                        const std::vector<PlanePoint>& midpoints,
                        std::vector<TerrainSample>& samples) const;
  void store(std::size_t tile, const Grid& elevation, const std::vector<char>& col_owned,
             const std::vector<char>& row_owned) const;
};

void TileJob::fill_elevation(std::size_t tile, Grid& elevation, ThreadState& thread,
                             TileResult& out) const {
  // In the order given; all XYZ files form one TIN, filled at the place of the first of them.
  bool xyz_done = false;
  for (std::size_t k = 0; k < inputs.sources.size(); ++k) {
    const ElevationSource& source = inputs.sources[k];
    if (source.kind == ElevationKind::raster) {
      if (thread.rasters.size() <= k) thread.rasters.resize(inputs.sources.size());
      auto& raster = thread.rasters[k];
      if (!raster) raster = std::make_unique<RasterElevation>(source.path, graph.zone);
      out.cells_per_source[k] += raster->fill(elevation);
    } else if (!xyz_done) {
      std::vector<ElevationPoint> points;
      {
        const std::lock_guard lock(xyz_mutex);  // take() may read the shared spill file
        points = xyz_bins.take(tile);
      }
      out.cells_per_source[k] += fill_from_points(elevation, points, p.tin_max_edge_m);
      xyz_done = true;
    }
  }
}

void TileJob::sample_elevation(const Grid& elevation, std::span<const std::uint32_t> segments,
                               const std::vector<PlanePoint>& midpoints,
                               std::vector<TerrainSample>& samples) const {
  // Elevations and slope (Horn's, at the four cells around the midpoint).
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const Segment& s = graph.segments[segments[k]];
    const PlanePoint mid = midpoints[k];
    TerrainSample& t = samples[k];
    t.z_mid_m = static_cast<float>(elevation.sample(mid.x, mid.y));
    const std::span<const PlanePoint> line = graph.line(s);
    t.z_start_m = static_cast<float>(elevation.sample(line.front().x, line.front().y));
    t.z_end_m = static_cast<float>(elevation.sample(line.back().x, line.back().y));
    t.slope_deg = static_cast<float>(
        bilinear(elevation.spec, mid.x, mid.y,
                 [&](std::size_t c, std::size_t r) { return slope_at(elevation, c, r); }));
  }
}

void TileJob::store(std::size_t tile, const Grid& elevation, const std::vector<char>& col_owned,
                    const std::vector<char>& row_owned) const {
  const GridSpec& g = elevation.spec;
  if (stored.spec.cell_m != g.cell_m) {
    const auto owns = [&](double e, double n) {
      return e >= whole.west_m && e < whole.east_m() && n >= whole.south_m && n < whole.north_m() &&
             grids.layout.tile_of({e, n}) == tile;
    };
    copy_owned(elevation, owns, stored);
    return;
  }
  // Same cells: copied as they are.
  const auto stored_col0 = std::llround((g.west_m - stored.spec.west_m) / g.cell_m);
  const auto stored_row0 = std::llround((g.south_m - stored.spec.south_m) / g.cell_m);
  for (std::size_t row = 0; row < g.rows; ++row) {
    if (!row_owned[row]) continue;
    for (std::size_t col = 0; col < g.cols; ++col) {
      if (!col_owned[col]) continue;
      stored.at(static_cast<std::size_t>(static_cast<long long>(col) + stored_col0),
                static_cast<std::size_t>(static_cast<long long>(row) + stored_row0)) =
          elevation.at(col, row);
    }
  }
}

TileResult TileJob::run(std::size_t tile, ThreadState& thread) const {
  TileResult out;
  out.cells_per_source.assign(inputs.sources.size(), 0);
  Grid elevation(grids(tile), std::move(thread.elevation_cells));
  fill_elevation(tile, elevation, thread, out);
  out.voids_filled = fill_voids(elevation, p.void_fill_max_m, &thread.void_queued);
  // The tile's own cells: those of the whole grid whose centres fall in this tile (the outer
  // tiles reach to the whole grid's edge). Each cell counts once in the statistics and is
  // stored once. Ownership is by column and by row.
  const GridSpec& g = elevation.spec;
  const std::size_t tile_col = tile % grids.layout.cols, tile_row = tile / grids.layout.cols;
  std::vector<char> col_owned(g.cols), row_owned(g.rows);
  for (std::size_t col = 0; col < g.cols; ++col) {
    const double e = g.centre_easting(col);
    col_owned[col] =
        e >= whole.west_m && e < whole.east_m() && grids.layout.tile_col(e) == tile_col;
  }
  for (std::size_t row = 0; row < g.rows; ++row) {
    const double n = g.centre_northing(row);
    row_owned[row] =
        n >= whole.south_m && n < whole.north_m() && grids.layout.tile_row(n) == tile_row;
  }
  // The tile's cell (col, row) is the whole grid's (col + col0, row + row0): both grids start
  // on multiples of align_m.
  const auto col0 = std::llround((g.west_m - whole.west_m) / g.cell_m);
  const auto row0 = std::llround((g.south_m - whole.south_m) / g.cell_m);
  const std::span<const std::uint32_t> segments = segments_of_tile[tile];
  // The tile's segments' samples, written into the segments at the end of the tile (the whole
  // map's samples took 24 bytes a segment through the stage).
  std::vector<TerrainSample> samples(segments.size());
  std::vector<PlanePoint> midpoints(segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) {
    midpoints[k] = segment_midpoint(graph, graph.segments[segments[k]]);
  }
  {  // one annulus at a time: each has its own prefix sums and block means
    AnnulusTpi small(elevation, p.tpi_small_inner_m, p.tpi_small_outer_m, p.tpi_min_valid_fraction);
    TileTpi{elevation, col_owned, row_owned, col0, row0, small_step, 0}.run(
        small, out.small_lattice_tpi_m, midpoints, samples, &TerrainSample::tpi_small_m);
  }
  {
    AnnulusTpi large(elevation, p.tpi_large_inner_m, p.tpi_large_outer_m, p.tpi_min_valid_fraction);
    TileTpi{elevation, col_owned, row_owned, col0, row0, large_step, large_offset}.run(
        large, out.large_lattice_tpi_m, midpoints, samples, &TerrainSample::tpi_large_m);
  }
  for (std::size_t row = 0; row < g.rows; ++row) {
    if (!row_owned[row]) continue;
    for (std::size_t col = 0; col < g.cols; ++col) {
      if (col_owned[col]) out.cells_with_elevation += std::isnan(elevation.at(col, row)) ? 0 : 1;
    }
  }
  sample_elevation(elevation, segments, midpoints, samples);
  for (std::size_t k = 0; k < segments.size(); ++k) {
    Segment& s = graph.segments[segments[k]];
    store_terrain_sample(s, graph.length_m(s), samples[k]);
    if (s.bridge || s.tunnel) {
      out.structure_ends.push_back({segments[k], samples[k].z_start_m, samples[k].z_end_m});
    }
  }
  store(tile, elevation, col_owned, row_owned);
  thread.elevation_cells = std::move(elevation.values);
  return out;
}

/// Gives the heap's free pages back to the system (glibc keeps them otherwise).
void return_free_heap_pages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace

CellSizeChoice choose_cell_size(const geo::UtmZone& zone, const RoadBounds& roads,
                                const TerrainInputs& inputs, const TerrainParameters& parameters) {
  if (parameters.cell_size_m > 0.0) return {parameters.cell_size_m, "given (terrain.cell_size_m)"};
  if (inputs.sources.empty()) return {kFinestAutomaticCellM, "no elevation input"};
  bool has_xyz = false;
  std::vector<double> sides_m;
  std::string finest;  // the raster with the smallest side, as "file: a x b m"
  const double centre_e = 0.5 * (roads.min_e + roads.max_e);
  const double centre_n = 0.5 * (roads.min_n + roads.max_n);
  for (const ElevationSource& source : inputs.sources) {
    if (source.kind == ElevationKind::xyz) {
      has_xyz = true;
      continue;
    }
    const RasterElevation::PixelSize pixel =
        RasterElevation(source.path, zone).pixel_size_at(centre_e, centre_n);
    const double side = std::min(pixel.column_m, pixel.row_m);  // NaN when either is
    if (!std::isfinite(side)) continue;
    if (sides_m.empty() || side < *std::min_element(sides_m.begin(), sides_m.end())) {
      char text[96];
      std::snprintf(text, sizeof text, ": %.2f x %.2f m pixels at the roads", pixel.column_m,
                    pixel.row_m);
      finest = std::filesystem::path(source.path).filename().string() + text;
    }
    sides_m.push_back(side);
  }
  const double cell_m = automatic_cell_size_m(sides_m, has_xyz, parameters.tpi_small_outer_m);
  std::string source;
  if (has_xyz) {
    source = "automatic: XYZ points";
  } else if (sides_m.empty()) {
    source = "automatic: no raster pixel measurable at the roads";
  } else {
    source = "automatic: finest raster " + finest + ", whole metres in [" +
             format_number(kFinestAutomaticCellM) + ", " +
             format_number(
                 std::max(kFinestAutomaticCellM, std::floor(parameters.tpi_small_outer_m / 2.0))) +
             "] (tpi_small_outer_m / 2)";
  }
  return {cell_m, source};
}

void mark_without_elevation(RoadGraph& graph) {
  for (Segment& s : graph.segments) s.reasons.add("NO_ELEVATION");
}

TerrainReport compute_terrain(RoadGraph& graph, const RoadBounds& roads,
                              const TerrainInputs& inputs, const CellSizeChoice& cell,
                              const TerrainParameters& given, Progress& progress,
                              Grid* elevation_out) {
  TerrainReport report;
  TerrainParameters p = given;
  p.cell_size_m = cell.cell_m;
  report.cell_size_source = cell.source;
  p.validate_relations();
  // The whole grid reaches one large TPI radius beyond the roads so that road cells see whole
  // annuli; it is never held at once, only tile by tile.
  const double halo_m = p.tpi_large_outer_m + p.cell_size_m;
  // Tile grids start on multiples of the TPI blocks, so that a cell's blocks (and so its TPI)
  // are the same whichever tile computes it.
  const double align_m =
      p.cell_size_m * double(std::lcm(block_factor(p.tpi_small_outer_m / p.cell_size_m),
                                      block_factor(p.tpi_large_outer_m / p.cell_size_m)));
  report.grid = grid_covering(graph.zone, roads.min_e, roads.min_n, roads.max_e, roads.max_n,
                              halo_m, p.cell_size_m, align_m);
  TileLayout layout;
  layout.west_m = roads.min_e, layout.south_m = roads.min_n, layout.size_m = p.tile_size_m;
  layout.cols = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil((roads.max_e - roads.min_e) / p.tile_size_m)));
  layout.rows = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil((roads.max_n - roads.min_n) / p.tile_size_m)));
  const SegmentsByTile segments_of_tile(graph, layout);
  const TileGrids grids{graph.zone, roads, layout, halo_m, p.cell_size_m, align_m};

  const std::size_t factor = std::max<std::size_t>(
      1, static_cast<std::size_t>(
             std::ceil(std::sqrt(double(report.grid.size()) / kStoredGridMaxCells))));
  Grid stored(grid_covering(graph.zone, roads.min_e, roads.min_n, roads.max_e, roads.max_n, halo_m,
                            p.cell_size_m * double(factor), align_m));

  std::vector<const ElevationSource*> xyz_files;
  for (const ElevationSource& s : inputs.sources) {
    if (s.kind == ElevationKind::xyz) xyz_files.push_back(&s);
  }
  // XYZ points go to the tiles whose grid, grown by one longest TIN edge, holds them: exactly
  // the points fill_from_points would take from all of them.
  std::vector<UtmBox> xyz_boxes(segments_of_tile.tiles(), UtmBox{1.0, 1.0, 0.0, 0.0});
  for (std::size_t tile = 0; tile < segments_of_tile.tiles() && !xyz_files.empty(); ++tile) {
    if (segments_of_tile[tile].empty()) continue;
    const GridSpec g = grids(tile);
    xyz_boxes[tile] = {g.west_m - p.tin_max_edge_m, g.south_m - p.tin_max_edge_m,
                       g.east_m() + p.tin_max_edge_m, g.north_m() + p.tin_max_edge_m};
  }
  XyzTileBins xyz_bins(std::move(xyz_boxes),
                       static_cast<std::size_t>(p.xyz_memory_mib * 1024.0 * 1024.0),
                       inputs.spill_dir);
  if (!xyz_files.empty()) {
    progress.start_stage("reading XYZ points", "points");
    read_xyz_files(xyz_files, inputs.xyz_crs, graph.zone, xyz_bins, report, progress);
    report.xyz_spilled_points = xyz_bins.spilled_points();
    progress.finish_stage(std::to_string(report.xyz_points) + " points, " +
                          std::to_string(xyz_bins.spilled_points()) +
                          " spilled to a temporary file");
  }
  progress.start_stage("terrain", "tiles");
  std::vector<std::size_t> cells_per_source(inputs.sources.size(), 0);
  std::vector<StructureEnds> structure_ends;
  RunningStatistics small_stats, large_stats;
  const StatisticsLattice lattice = statistics_lattice(report.grid.size(), p);
  const long long small_step = lattice.small_step, large_step = lattice.large_step;
  const long long large_offset = lattice.large_offset;

  std::vector<std::size_t> tiles;  // those with segments, in tile order
  for (std::size_t tile = 0; tile < segments_of_tile.tiles(); ++tile) {
    if (!segments_of_tile[tile].empty()) tiles.push_back(tile);
  }
  // In tile order (rows south to north). The statistics are summed in tile order
  // (InOrderMerge): a tile finished before an earlier one waits with its lattice values, ~1 MB
  // a full tile. Largest tiles first (for the threads to finish together) ran the east column's
  // narrower tiles last, so that nearly every tile waited for the first of them: +160 MiB at
  // 200x Monaco by the end of the stage. In tile order the narrower last row still comes last.
  std::mutex xyz_mutex;
  const TileJob job{graph,        inputs,           p,          report.grid,
                    grids,        segments_of_tile, small_step, large_step,
                    large_offset, xyz_bins,         xyz_mutex,  stored};
  InOrderMerge merge(tiles.size());
  std::size_t tiles_done = 0;
  const auto add_to_totals = [&](const TileResult& r) {
    for (const float v : r.small_lattice_tpi_m) small_stats.add(v);
    for (const float v : r.large_lattice_tpi_m) large_stats.add(v);
    structure_ends.insert(structure_ends.end(), r.structure_ends.begin(), r.structure_ends.end());
    for (std::size_t k = 0; k < cells_per_source.size(); ++k) {
      cells_per_source[k] += r.cells_per_source[k];
    }
    report.voids_filled += r.voids_filled;
    report.cells_with_elevation += r.cells_with_elevation;
    progress.update(++tiles_done, tiles.size());
  };
  // Two tiles in flight at most: memory follows the tiles held, not the machine's cores.
  parallel_for<ThreadState>(
      tiles.size(),
      [&](std::size_t k, ThreadState& thread) {
        merge.add(k, job.run(tiles[k], thread), add_to_totals);
      },
      1, 2);
  // The tiles' freed grids and lattice values leave free pages in the threads' heaps; given
  // back, they do not add to the later stages' peak (the terrain grid's write at 200x).
  return_free_heap_pages();
  const std::size_t tiles_total = tiles.size();
  bool xyz_reported = false;  // the TIN of all XYZ files is counted at the first of them
  for (std::size_t k = 0; k < inputs.sources.size(); ++k) {
    if (inputs.sources[k].kind == ElevationKind::xyz) {
      if (xyz_reported) continue;
      xyz_reported = true;
    }
    report.cells_per_source.emplace_back(inputs.sources[k].path, cells_per_source[k]);
  }
  if (report.cells_with_elevation == 0) {
    std::string files;
    for (const ElevationSource& s : inputs.sources) files += (files.empty() ? "" : ", ") + s.path;
    throw InputError(files,
                     "the elevation data does not overlap the roads of the OSM extract at "
                     "all (wrong file, or wrong --elevation-crs?)");
  }
  const TpiStandardisation z = standardisation(small_stats.result(), large_stats.result(), p);
  std::sort(structure_ends.begin(), structure_ends.end(),
            [](const StructureEnds& a, const StructureEnds& b) { return a.segment < b.segment; });
  assign_terrain(graph, structure_ends, z, p);
  for (const Segment& s : graph.segments) {
    report.segments_without_elevation += s.elevation_cost ? 0 : 1;
    report.structure_segments += (s.bridge || s.tunnel) ? 1 : 0;
  }
  report.tiles = tiles_total;
  report.stored_cell_m = stored.spec.cell_m;
  if (elevation_out) *elevation_out = std::move(stored);
  progress.finish_stage(
      std::to_string(tiles_total) + " tiles of " + format_number(p.tile_size_m / 1000.0) + " km, " +
      std::to_string(graph.segments.size() - report.segments_without_elevation) +
      " segments with elevation, " + std::to_string(report.segments_without_elevation) +
      " without, " + std::to_string(report.voids_filled) + " void cells filled");
  return report;
}

}  // namespace roadcross::preprocess
