// Terrain cost: slope and topographic position index (TPI) on the terrain grid, Weiss (2001)
// landform classes, and per segment elevation_m, slope_deg, grade_percent, tpi_small_m,
// tpi_large_m, landform, elevation_cost (0..9, windowed along the road) and the reasons
// CREST_OR_DIP / NO_ELEVATION. docs/cost-model.md explains the method and its deviations.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"
#include "roadcross/preprocess/terrain/terrain_grid.hpp"

namespace roadcross::preprocess {

class Progress;

/// The ten landform classes of Weiss (2001), in his numbering order.
enum class Landform : std::uint8_t {
  canyon,             ///< small TPI low, large TPI low: canyons, deeply incised streams
  midslope_drainage,  ///< small low, large normal: midslope drainages, shallow valleys
  upland_drainage,    ///< small low, large high: upland drainages, headwaters
  u_shaped_valley,    ///< small normal, large low
  plains,             ///< small normal, large normal, slope <= flat_slope_deg
  open_slope,         ///< small normal, large normal, slope > flat_slope_deg
  upper_slope,        ///< small normal, large high: upper slopes, mesas
  local_ridge,        ///< small high, large low: local ridges, hills in valleys
  midslope_ridge,     ///< small high, large normal: midslope ridges, small hills in plains
  mountain_top,       ///< small high, large high: mountain tops, high ridges
};
constexpr std::size_t kLandformCount = 10;

/// snake_case name stored in the DB ("mountain_top", ...).
std::string_view landform_name(Landform landform) noexcept;

/// Ridges, tops, canyons and drainages: places where the road's profile bends enough to hide
/// an approaching car (reason CREST_OR_DIP).
bool is_crest_or_dip(Landform landform) noexcept;

struct TerrainParameters {
  /// Terrain grid cell size, metres; 0 (the default): chosen from the elevation inputs by
  /// automatic_cell_size_m (a raster's pixel; 5 m for XYZ points), see choose_cell_size.
  double cell_size_m = 0.0;
  /// The grid is analysed in square tiles of this size (plus a halo of the large TPI radius),
  /// so that memory follows the tile, not the map; metres.
  double tile_size_m = 10000.0;
  /// TPI neighbourhoods: annuli between an inner and an outer radius, metres.
  double tpi_small_inner_m = 10.0, tpi_small_outer_m = 50.0;
  double tpi_large_inner_m = 100.0, tpi_large_outer_m = 300.0;
  /// TPI is computed only where at least this share of the annulus has elevation.
  double tpi_min_valid_fraction = 0.5;
  /// The TPI's mean and standard deviation (for standardising it) come from the cells on a
  /// regular lattice of this spacing, metres (rounded to whole cells; the cell size: every
  /// cell), or a finer one on grids too small to give 250 000 lattice cells. TPI itself is
  /// computed only at those cells and where segments sample it.
  double tpi_statistics_step_m = 20.0;
  /// Standardised TPI beyond +-this many standard deviations is "high" / "low" (Weiss: 1).
  double standard_deviations = 1.0;
  /// Smallest standard deviation used to standardise TPI, metres: in flat country the spread of
  /// TPI is tiny and one standard deviation would call a 30 cm bump a ridge.
  double tpi_small_min_sd_m = 1.0, tpi_large_min_sd_m = 3.0;
  /// Plains vs open slopes, degrees (Weiss: 5).
  double flat_slope_deg = 5.0;
  /// A TIN triangle with a longer edge spans a gap in the points and is not interpolated, m.
  double tin_max_edge_m = 100.0;
  /// XYZ points are binned by tile (with an overlap of tin_max_edge_m); past this much memory
  /// for the bins, MiB (24 bytes a point), they are spilled to a temporary file and each tile
  /// reads its own back, so files larger than memory can be used.
  double xyz_memory_mib = 1024.0;
  /// DEM voids are filled from valid cells at most this far away, metres.
  double void_fill_max_m = 100.0;
  /// Elevation cost window along the road (as curvature), metres, and own-segment weight.
  double window_half_length_m = 100.0;
  double own_segment_weight = 3.0;
  /// Cost of each landform class (the thesis, docs/cost-model.md), in Landform order; scaled to
  /// 0..9 by 9/15.
  std::array<double, kLandformCount> landform_cost = {8, 5, 6, 2, 1, 3, 6, 8, 10, 15};

  void describe(std::vector<ParameterSpec>& out);
  /// Throws ParameterError when an inner radius is not below its outer radius, or an outer
  /// radius is below a given cell size (an automatic one is checked once chosen).
  void validate_relations() const;
};

/// The finest cell size the automatic choice takes, metres: XYZ points (DMR 5G is a TIN of
/// points a few metres apart, whose spacing is not known before they are read), and the floor
/// for fine rasters (the method's own grid).
constexpr double kFinestAutomaticCellM = 5.0;

/// The automatic terrain cell size, metres: the smallest pixel side of the raster inputs
/// (`raster_pixel_sides_m`, in UTM metres at the roads; a finer grid would only interpolate
/// the DEM bilinearly between its pixels), floored to whole metres and clamped to
/// [kFinestAutomaticCellM, floor(tpi_small_outer_m / 2)] (the small TPI annulus keeps a few
/// cells across); kFinestAutomaticCellM when there is an XYZ input or no raster side.
double automatic_cell_size_m(const std::vector<double>& raster_pixel_sides_m, bool has_xyz,
                             double tpi_small_outer_m);

/// The cell size a build uses and where it came from (for the summary).
struct CellSizeChoice {
  double cell_m = 0.0;
  /// e.g. "given (terrain.cell_size_m)", "automatic: XYZ points", "automatic: finest raster
  /// N50E014.hgt: 59.64 x 92.70 m pixels at the roads, whole metres in [5, 25] (...)"
  std::string source;
};

/// Slope in degrees at every cell (Horn's 3x3 finite differences, as gdaldem); NaN where a
/// neighbour has no elevation and at the grid's edge.
Grid slope_degrees(const Grid& elevation);
/// The same at one cell.
float slope_at(const Grid& elevation, std::size_t col, std::size_t row);

struct TpiPrefixSums;

/// Which rows' prefix sums an AnnulusTpi holds.
enum class TpiRows {
  /// A band of rows around the rows last asked about (~8 annulus diameters, ~5 MB for a 10 km
  /// tile), computed as the queries move north: at() is cheapest called row by row, south to
  /// north (any order gives the same values; going back south recomputes rows). Not
  /// thread-safe.
  band,
  /// Every row, computed at once (12 bytes a cell or block): compute_all() and then at() may
  /// run on several threads.
  all,
};

/// Cells per block for an annulus of outer radius `outer_cells` (> 0, cells): the annulus mean
/// is a smooth function of position, so beyond ~20 cells of radius it is computed on blocks of
/// cells and interpolated, which keeps the cost per cell bounded whatever the radius. 1: none.
std::size_t block_factor(double outer_cells);

/// The lattices of cells whose TPI gives the mean and SD that standardise it (the whole grid's
/// cells (col, row) with col % step == offset and row % step == offset).
struct StatisticsLattice {
  long long small_step = 1;    ///< small TPI: every small_step-th cell each way (offset 0)
  long long large_step = 1;    ///< large TPI: every large_step-th cell, ...
  long long large_offset = 0;  ///< ... starting here (the centres of its blocks)
};

/// The lattices for a whole grid of `grid_cells` cells of `parameters.cell_size_m` (resolved,
/// > 0): terrain.tpi_statistics_step_m for the small TPI, about three times that for the
/// large; every cell of a grid under 1 M cells (exact).
StatisticsLattice statistics_lattice(std::size_t grid_cells, const TerrainParameters& parameters);

/// TPI of single cells, computed where asked: the cell's elevation minus the mean elevation of
/// the cells whose centres lie in the annulus inner_m < d <= outer_m (metres). Sums come from
/// per-row prefix sums (12 bytes a cell, or a block of cells for large radii), so a cell costs
/// O(outer_m / cell) and not O(area). Beyond ~20 cells of radius the annulus mean is computed
/// at the centres of blocks of cells and interpolated (it is smooth); block means are kept once
/// computed (cell means, for small radii, are not: a cell is rarely asked twice). NaN where the
/// cell has no elevation or less than `min_valid_fraction` of the annulus has. at() is not
/// thread-safe unless the rows are TpiRows::all and compute_all() ran first.
class AnnulusTpi {
 public:
  AnnulusTpi(const Grid& elevation, double inner_m, double outer_m, double min_valid_fraction,
             TpiRows rows = TpiRows::band);
  ~AnnulusTpi();
  AnnulusTpi(const AnnulusTpi&) = delete;
  AnnulusTpi& operator=(const AnnulusTpi&) = delete;

  float at(std::size_t col, std::size_t row);
  /// Every block mean, on both cores (TpiRows::all only).
  void compute_all();

 private:
  float block_mean(std::size_t col, std::size_t row);
  float compute_block_mean(std::size_t col, std::size_t row) const;
  bool at_block_centre(std::size_t col, std::size_t row) const;
  void allocate_cache();

  const Grid& elevation_;
  std::size_t factor_;
  std::vector<long> outer_, inner_;  ///< the discs' half-widths per row offset, blocks
  std::unique_ptr<TpiPrefixSums> prefix_;
  double min_valid_fraction_;
  double full_annulus_ = 0.0;
  GridSpec block_spec_;            ///< the blocks' grid (the cells' at factor 1)
  std::vector<float> block_mean_;  ///< per block, once known_; empty: no cache
  std::vector<std::uint8_t> known_;
};

/// TPI at every cell: its elevation minus the mean elevation of the cells whose centres lie in
/// the annulus inner_m < d <= outer_m (metres). Sums come from per-row prefix sums, so a cell
/// costs O(outer_m / cell) and not O(area). NaN where the cell has no elevation or less than
/// `min_valid_fraction` of the annulus has. Uses both cores.
Grid topographic_position(const Grid& elevation, double inner_m, double outer_m,
                          double min_valid_fraction);

struct GridStatistics {
  double mean = 0.0, standard_deviation = 0.0;
  std::size_t count = 0;
};
GridStatistics statistics(const Grid& grid);

/// Weiss's table: z_small and z_large are standardised TPI (in standard deviations).
Landform classify_landform(double z_small, double z_large, double slope_deg,
                           const TerrainParameters& parameters) noexcept;

/// The terrain measures over one grid, ready to be sampled at any UTM point.
struct TerrainModel {
  Grid elevation, slope, tpi_small, tpi_large;
  GridStatistics small_stats, large_stats;
  double small_sd_used = 1.0, large_sd_used = 1.0;  ///< after the minimum-SD floors
};
TerrainModel analyse_terrain(Grid elevation, const TerrainParameters& parameters);

/// What a segment samples from the terrain model of its tile (NaN: no value).
struct TerrainSample {
  float z_mid_m = NAN, z_start_m = NAN, z_end_m = NAN;
  float slope_deg = NAN, tpi_small_m = NAN, tpi_large_m = NAN;
};

/// The midpoint of a segment along its line (where it samples the terrain).
PlanePoint segment_midpoint(const RoadGraph& graph, const Segment& segment);

/// Samples the model at the segments listed (indices into graph.segments).
void sample_terrain(const RoadGraph& graph, const TerrainModel& model,
                    const std::vector<std::size_t>& segments, std::vector<TerrainSample>& samples);

/// TPI statistics over the whole map and the standard deviations used (after the floors).
struct TpiStandardisation {
  GridStatistics small, large;
  double small_sd_used = 1.0, large_sd_used = 1.0;
};
TpiStandardisation standardisation(const GridStatistics& small, const GridStatistics& large,
                                   const TerrainParameters& parameters);

/// A bridge or tunnel segment's DEM elevations at its start and end, metres (NaN: none): a
/// structure's elevation is interpolated between the ends of its run of segments.
struct StructureEnds {
  std::size_t segment = 0;  ///< index into RoadGraph::segments
  float z_start_m = NAN, z_end_m = NAN;
};

/// What a segment takes from its own sample: elevation, slope, grade and both TPI. Nothing for
/// a bridge or tunnel (assign_terrain: from the structure's ends), and only the (absent)
/// elevation where the midpoint has none.
/// `length_m`: the segment's length (RoadGraph::length_m), metres, for the grade.
void store_terrain_sample(Segment& segment, double length_m, const TerrainSample& sample);

/// From the fields store_terrain_sample wrote and the structure segments' ends (sorted by
/// segment): landform, CREST_OR_DIP, bridges and tunnels from their ends, the windowed
/// elevation cost, and NO_ELEVATION where there is none.
void assign_terrain(RoadGraph& graph, const std::vector<StructureEnds>& structure_ends,
                    const TpiStandardisation& standardisation, const TerrainParameters& parameters);

/// The same from every segment's sample (store_terrain_sample on each, then the above).
void assign_terrain(RoadGraph& graph, const std::vector<TerrainSample>& samples,
                    const TpiStandardisation& standardisation, const TerrainParameters& parameters);

struct TerrainInputs {
  std::vector<ElevationSource>
      sources;          ///< in the order given; earlier ones win where they overlap
  std::string xyz_crs;  ///< CRS of the XYZ files; empty: detect S-JTSK
  /// Where XYZ points are spilled past terrain.xyz_memory_mib (an unnamed temporary file);
  /// empty: the system's temporary directory.
  std::string spill_dir;
};

struct TerrainReport {
  GridSpec grid;  ///< the whole terrain grid (analysed tile by tile, never held at once)
  std::size_t tiles = 0;
  double stored_cell_m = 0.0;  ///< cell size of the grid stored in the DB
  std::size_t cells_with_elevation = 0;
  std::size_t voids_filled = 0;
  std::size_t xyz_points = 0;
  std::size_t xyz_spilled_points = 0;  ///< written to the temporary file (0: all in memory)
  std::string xyz_crs;                 ///< as used (given or detected)
  std::size_t segments_without_elevation = 0;
  std::size_t structure_segments = 0;  ///< bridges and tunnels, elevation from their ends
  std::vector<std::pair<std::string, std::size_t>> cells_per_source;
  std::string cell_size_source;  ///< CellSizeChoice::source
};

/// The one place the terrain grid's cell size is chosen: terrain.cell_size_m when given (> 0);
/// kFinestAutomaticCellM without elevation inputs; otherwise automatic_cell_size_m of the
/// inputs, each raster's pixel measured at the centre of the roads' box (`roads`, in `zone`).
/// Throws InputError when a raster cannot be opened.
CellSizeChoice choose_cell_size(const geo::UtmZone& zone, const RoadBounds& roads,
                                const TerrainInputs& inputs, const TerrainParameters& parameters);

/// Builds the terrain grid from the inputs (covering the roads plus the largest TPI radius) tile
/// by tile, analyses each tile, standardises TPI over the whole map and fills the terrain fields
/// of every segment. The elevation grid (voids filled; coarser when it would exceed 40 M cells)
/// is moved into `elevation_out` when given, for storing in the DB. Throws InputError
/// for an unreadable file or when no input overlaps the roads at all. `roads`: road_bounds of
/// the graph; `cell`: choose_cell_size's answer (its size replaces terrain.cell_size_m).
TerrainReport compute_terrain(RoadGraph& graph, const RoadBounds& roads,
                              const TerrainInputs& inputs, const CellSizeChoice& cell,
                              const TerrainParameters& parameters, Progress& progress,
                              Grid* elevation_out = nullptr);

/// The terrain stage without an elevation input: every segment is NO_ELEVATION.
void mark_without_elevation(RoadGraph& graph);

/// The per-segment part of compute_terrain on one model covering every segment (tests).
void assign_terrain(RoadGraph& graph, const TerrainModel& model,
                    const TerrainParameters& parameters);

}  // namespace roadcross::preprocess
