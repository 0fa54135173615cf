// The terrain analysis of one grid: slope (Horn), TPI annuli from row prefix sums, landforms
// (Weiss 2001), and the per-segment terms and windowed elevation cost. The stage that runs it
// tile by tile over a map is in terrain_tiles.cpp.
#include "roadcross/preprocess/terrain/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/graph/strokes.hpp"

namespace roadcross::preprocess {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

constexpr std::array<std::string_view, kLandformCount> kLandformNames = {
    "canyon",     "midslope_drainage", "upland_drainage", "u_shaped_valley", "plains",
    "open_slope", "upper_slope",       "local_ridge",     "midslope_ridge",  "mountain_top"};
}  // namespace

LandformLabel::LandformLabel(Landform landform) noexcept
    : code_(static_cast<std::uint8_t>(1 + static_cast<std::uint8_t>(landform))) {}

LandformLabel LandformLabel::structure(bool tunnel) noexcept {
  LandformLabel label;
  label.code_ = tunnel ? kTunnel : kBridge;
  return label;
}

const char* LandformLabel::text() const noexcept {
  static_assert(kTunnel == 1 + kLandformCount);
  if (code_ == kNone) return nullptr;
  if (code_ == kTunnel) return "tunnel";
  if (code_ == kBridge) return "bridge";
  return kLandformNames[code_ - 1u].data();  // the names are literals: NUL-terminated
}

std::string_view landform_name(Landform landform) noexcept {
  return kLandformNames[static_cast<std::size_t>(landform)];
}

bool is_crest_or_dip(Landform landform) noexcept {
  switch (landform) {
    case Landform::canyon:
    case Landform::midslope_drainage:
    case Landform::upland_drainage:
    case Landform::local_ridge:
    case Landform::midslope_ridge:
    case Landform::mountain_top:
      return true;
    default:
      return false;
  }
}

void TerrainParameters::describe(std::vector<ParameterSpec>& out) {
  const std::string s = "terrain";
  out.push_back({s, "cell_size_m", &cell_size_m, 0, 100, false,
                 "terrain grid cell size in the DB's UTM zone, metres (0.5..100); 0: from the "
                 "elevation input (the finest raster's pixel, whole metres in [5, "
                 "tpi_small_outer_m / 2]; 5 with XYZ points)"});
  out.push_back({s, "tile_size_m", &tile_size_m, 100, 1000000, false,
                 "the grid is analysed in tiles of this size (+ a halo), metres"});
  out.push_back({s, "tpi_small_inner_m", &tpi_small_inner_m, 0, 10000, false,
                 "small TPI annulus: inner radius, metres"});
  out.push_back({s, "tpi_small_outer_m", &tpi_small_outer_m, 1, 10000, false,
                 "small TPI annulus: outer radius, metres"});
  out.push_back({s, "tpi_large_inner_m", &tpi_large_inner_m, 0, 10000, false,
                 "large TPI annulus: inner radius, metres"});
  out.push_back({s, "tpi_large_outer_m", &tpi_large_outer_m, 1, 10000, false,
                 "large TPI annulus: outer radius, metres"});
  out.push_back({s, "tpi_min_valid_fraction", &tpi_min_valid_fraction, 0.01, 1, false,
                 "TPI only where at least this share of the annulus has elevation"});
  out.push_back({s, "tpi_statistics_step_m", &tpi_statistics_step_m, 0.5, 10000, false,
                 "TPI mean and SD from the cells of a lattice this far apart, metres"});
  out.push_back({s, "standard_deviations", &standard_deviations, 0.1, 10, false,
                 "standardised TPI beyond +-this is high/low (Weiss 2001: 1)"});
  out.push_back({s, "tpi_small_min_sd_m", &tpi_small_min_sd_m, 0.01, 1000, false,
                 "smallest standard deviation used to standardise the small TPI, metres"});
  out.push_back({s, "tpi_large_min_sd_m", &tpi_large_min_sd_m, 0.01, 1000, false,
                 "smallest standard deviation used to standardise the large TPI, metres"});
  out.push_back({s, "flat_slope_deg", &flat_slope_deg, 0, 90, false,
                 "plains up to this slope, open slopes above, degrees (Weiss 2001: 5)"});
  out.push_back({s, "tin_max_edge_m", &tin_max_edge_m, 1, 100000, false,
                 "XYZ points: TIN triangles with a longer edge span a gap, metres"});
  out.push_back({s, "xyz_memory_mib", &xyz_memory_mib, 0.01, 1048576, false,
                 "XYZ points held in memory before spilling to a temporary file, MiB"});
  out.push_back({s, "void_fill_max_m", &void_fill_max_m, 0, 10000, false,
                 "DEM voids are filled from valid cells at most this far away, metres"});
  out.push_back({s, "window_half_length_m", &window_half_length_m, 0, 10000, false,
                 "elevation cost window: this far along the road each way, metres"});
  out.push_back({s, "own_segment_weight", &own_segment_weight, 0, 1000, false,
                 "the segment itself counts this many times in its window"});
  for (std::size_t i = 0; i < kLandformCount; ++i) {
    out.push_back({s, "cost_" + std::string(kLandformNames[i]), &landform_cost[i], 0, 15, false,
                   "landform cost of " + std::string(kLandformNames[i]) + " (0..15)"});
  }
}

void TerrainParameters::validate_relations() const {
  if (tpi_small_inner_m >= tpi_small_outer_m) {
    throw ParameterError("terrain.tpi_small_inner_m must be below terrain.tpi_small_outer_m");
  }
  if (tpi_large_inner_m >= tpi_large_outer_m) {
    throw ParameterError("terrain.tpi_large_inner_m must be below terrain.tpi_large_outer_m");
  }
  if (cell_size_m != 0.0 && cell_size_m < 0.5) {
    throw ParameterError("terrain.cell_size_m must be 0 (automatic) or in [0.5, 100], got " +
                         format_number(cell_size_m));
  }
  if (tpi_small_outer_m < cell_size_m || tpi_large_outer_m < cell_size_m) {
    throw ParameterError("the TPI outer radii must be at least terrain.cell_size_m (" +
                         format_number(cell_size_m) + " m)");
  }
}

double automatic_cell_size_m(const std::vector<double>& raster_pixel_sides_m, bool has_xyz,
                             double tpi_small_outer_m) {
  double finest = std::numeric_limits<double>::infinity();
  for (const double side : raster_pixel_sides_m) {
    if (std::isfinite(side) && side > 0.0) finest = std::min(finest, side);
  }
  if (has_xyz || !std::isfinite(finest)) return kFinestAutomaticCellM;
  // Whole metres keep the grid's edges on round coordinates; a ceiling below the floor (a
  // small annulus under 10 m) leaves the floor, which validation then checks as any value.
  const double ceiling = std::max(kFinestAutomaticCellM, std::floor(tpi_small_outer_m / 2.0));
  return std::clamp(std::floor(finest), kFinestAutomaticCellM, ceiling);
}

float slope_at(const Grid& elevation, std::size_t col, std::size_t row) {
  const GridSpec& s = elevation.spec;
  if (col == 0 || row == 0 || col + 1 >= s.cols || row + 1 >= s.rows) {
    return std::numeric_limits<float>::quiet_NaN();
  }
  // Horn (1981): rows south to north, so "north" is row + 1.
  const double a = elevation.at(col - 1, row + 1), b = elevation.at(col, row + 1),
               c = elevation.at(col + 1, row + 1);
  const double d = elevation.at(col - 1, row), f = elevation.at(col + 1, row);
  const double g = elevation.at(col - 1, row - 1), h = elevation.at(col, row - 1),
               i = elevation.at(col + 1, row - 1);
  const double dz_de = ((c + 2 * f + i) - (a + 2 * d + g)) / (8 * s.cell_m);
  const double dz_dn = ((a + 2 * b + c) - (g + 2 * h + i)) / (8 * s.cell_m);
  return static_cast<float>(std::atan(std::hypot(dz_de, dz_dn)) * kRadToDeg);  // NaN propagates
}

Grid slope_degrees(const Grid& elevation) {
  Grid slope(elevation.spec);
  for (std::size_t row = 0; row < slope.spec.rows; ++row) {
    for (std::size_t col = 0; col < slope.spec.cols; ++col) {
      slope.at(col, row) = slope_at(elevation, col, row);
    }
  }
  return slope;
}

namespace {

/// Per-row prefix sums of the sums and valid-cell counts of blocks of factor x factor cells
/// (factor 1: the cells): block row r, block columns [a, b) sum to row_sums(r)[b] -
/// row_sums(r)[a]. 12 bytes per block, held for a band of rows only: a disc query at block row
/// r reads rows r - R .. r + R, and the build asks row by row, so ensure() computes rows as the
/// queries move north and drops those left behind (a 10 km tile's sums took ~54 MB per
/// thread; its band ~5 MB). A row's sums depend only on that row's cells and are computed by
/// the same arithmetic whenever computed: a row dropped and computed again has the same bits,
/// so any order of queries gives the same answers (only slower when it goes back south).
struct RowPrefixSums {
  /// The band holds this many query windows: when it moves north, the last ~2 windows' rows
  /// are copied to its start, so a larger band copies less often (8: a row is copied ~0.3
  /// times on average; 3: ~1.7 times).
  static constexpr std::size_t kBandWindows = 8;

  const Grid& grid;
  std::size_t factor, cols, rows, stride;
  bool all_rows;                ///< every row computed at construction: ensure() only reads
  std::size_t capacity_rows;    ///< rows the band holds
  std::size_t keep_below_rows;  ///< rows kept south of a query when the band moves north
  std::size_t first_row = 0;    ///< the band's first row
  std::size_t filled_rows = 0;  ///< rows [first_row, first_row + filled_rows) are computed
  std::vector<double> sum;
  std::vector<std::uint32_t> count;
  std::vector<double> block_sum;  ///< factor > 1: one block row's sums before the prefix
  std::vector<std::uint32_t> block_count;

  /// `window_rows`: the most rows one query reads (0: hold every row, computed here; then
  /// ensure() never writes and queries may run on several threads).
  RowPrefixSums(const Grid& g, std::size_t block_factor, std::size_t window_rows)
      : grid(g),
        factor(block_factor),
        cols((g.spec.cols + block_factor - 1) / block_factor),
        rows((g.spec.rows + block_factor - 1) / block_factor),
        stride(cols + 1),
        all_rows(window_rows == 0),
        capacity_rows(window_rows == 0 ? rows : std::min(rows, kBandWindows * window_rows)),
        keep_below_rows(window_rows) {
    sum.resize(capacity_rows * stride);  // every element read is written first
    count.resize(capacity_rows * stride);
    if (factor > 1) block_sum.resize(cols), block_count.resize(cols);
    if (window_rows == 0 && rows > 0) ensure(0, long(rows) - 1);
  }

  const double* row_sums(std::size_t row) const { return sum.data() + (row - first_row) * stride; }
  const std::uint32_t* row_counts(std::size_t row) const {
    return count.data() + (row - first_row) * stride;
  }

  /// Makes rows lo..hi (clipped to the grid) available.
  void ensure(long lo, long hi) {
    const std::size_t first = static_cast<std::size_t>(std::max(0L, lo));
    const std::size_t last = static_cast<std::size_t>(std::min(long(rows) - 1, hi));
    if (hi < 0 || first > last) return;
    std::size_t end = first_row + filled_rows;
    if (first >= first_row && last < end) return;  // the usual case: all there
    if (last - first + 1 > capacity_rows) {        // a query wider than planned (not the build)
      capacity_rows = last - first + 1;
      sum.resize(capacity_rows * stride), count.resize(capacity_rows * stride);
    }
    if (first < first_row || first > end) {
      // Back south, or a jump north past the band: start a new band (a few rows below, for
      // the neighbours that interpolation asks next).
      first_row =
          first - std::min(first, std::min(keep_below_rows, capacity_rows - (last - first + 1)));
      filled_rows = 0;
      end = first_row;
    } else if (last >= first_row + capacity_rows) {
      // Moving north: keep up to keep_below_rows rows south of `first`, move them to the start.
      const std::size_t new_first = std::max(first_row, first - std::min(first, keep_below_rows));
      const std::size_t keep_first =
          std::max(new_first, last + 1 - std::min(last + 1, capacity_rows));
      const std::size_t kept = end - keep_first;
      std::copy_n(sum.data() + (keep_first - first_row) * stride, kept * stride, sum.data());
      std::copy_n(count.data() + (keep_first - first_row) * stride, kept * stride, count.data());
      first_row = keep_first;
      filled_rows = kept;
    }
    for (std::size_t row = end; row <= last; ++row) compute_row(row);
    filled_rows = last + 1 - first_row;
  }

 private:
  void compute_row(std::size_t row) {
    double* sums = sum.data() + (row - first_row) * stride;
    std::uint32_t* counts = count.data() + (row - first_row) * stride;
    sums[0] = 0.0, counts[0] = 0;
    if (factor == 1) {
      // One pass a row. (0.0 + v is v: the same sums as the blocks' loop would give.)
      const float* cells = grid.values.data() + row * grid.spec.cols;
      for (std::size_t col = 0; col < cols; ++col) {
        const float v = cells[col];
        const bool valid = !std::isnan(v);
        sums[col + 1] = sums[col] + (valid ? 0.0 + v : 0.0);
        counts[col + 1] = counts[col] + (valid ? 1u : 0u);
      }
      return;
    }
    std::fill(block_sum.begin(), block_sum.end(), 0.0);
    std::fill(block_count.begin(), block_count.end(), 0);
    // Each block's cells are added row by row, west to east (block by block: no division of
    // the column by the factor per cell).
    for (std::size_t r = row * factor; r < std::min(grid.spec.rows, (row + 1) * factor); ++r) {
      const float* cells = grid.values.data() + r * grid.spec.cols;
      for (std::size_t block = 0; block < cols; ++block) {
        const std::size_t block_end = std::min(grid.spec.cols, (block + 1) * factor);
        for (std::size_t col = block * factor; col < block_end; ++col) {
          if (std::isnan(cells[col])) continue;
          block_sum[block] += cells[col];
          ++block_count[block];
        }
      }
    }
    for (std::size_t col = 0; col < cols; ++col) {
      sums[col + 1] = sums[col] + block_sum[col];
      counts[col + 1] = counts[col] + block_count[col];
    }
  }
};

/// Half-width in blocks of each row offset of a disc of radius `radius` (blocks whose centre
/// is within the radius; radius 0 still holds the centre block).
std::vector<long> disc_half_widths(double radius) {
  const auto r = static_cast<long>(std::floor(radius + 1e-9));
  std::vector<long> half(static_cast<std::size_t>(2 * r + 1));
  for (long dy = -r; dy <= r; ++dy) {
    const double w2 = radius * radius - double(dy * dy);
    half[static_cast<std::size_t>(dy + r)] = static_cast<long>(std::floor(std::sqrt(w2) + 1e-9));
  }
  return half;
}

/// Sum and count of valid cells in the disc around block (col, row); its rows must be in the
/// band (RowPrefixSums::ensure).
void disc_sum(const RowPrefixSums& p, const std::vector<long>& half, long col, long row,
              double& sum, std::uint64_t& count) {
  const long r = static_cast<long>(half.size() / 2);
  const long rows = static_cast<long>(p.rows), cols = static_cast<long>(p.cols);
  if (row - r >= 0 && row + r < rows && col - r >= 0 && col + r < cols) {
    // Inside the grid (the usual case): no clipping, the same sums in the same order.
    const double* sums = p.row_sums(static_cast<std::size_t>(row - r));
    const std::uint32_t* counts = p.row_counts(static_cast<std::size_t>(row - r));
    std::uint64_t n = 0;
    for (const long w : half) {
      sum += sums[col + w + 1] - sums[col - w];
      n += counts[col + w + 1] - counts[col - w];
      sums += p.stride, counts += p.stride;
    }
    count += n;
    return;
  }
  for (long dy = -r; dy <= r; ++dy) {
    const long y = row + dy;
    if (y < 0 || y >= rows) continue;
    const long w = half[static_cast<std::size_t>(dy + r)];
    const auto x0 = static_cast<std::size_t>(std::max(0L, col - w));
    const auto x1 = static_cast<std::size_t>(std::min(cols, col + w + 1));
    if (x1 <= x0) continue;
    const double* sums = p.row_sums(static_cast<std::size_t>(y));
    const std::uint32_t* counts = p.row_counts(static_cast<std::size_t>(y));
    sum += sums[x1] - sums[x0];
    count += counts[x1] - counts[x0];
  }
}

std::uint64_t disc_cell_count(const std::vector<long>& half) {
  std::uint64_t n = 0;
  for (const long w : half) n += static_cast<std::uint64_t>(2 * w + 1);
  return n;
}

}  // namespace

std::size_t block_factor(double outer_cells) {
  constexpr double kBlocksPerRadius = 20.0;
  return std::max<std::size_t>(1, static_cast<std::size_t>(outer_cells / kBlocksPerRadius));
}

StatisticsLattice statistics_lattice(std::size_t grid_cells, const TerrainParameters& p) {
  constexpr double kMinStatisticsCells = 250e3;
  // Finer on small grids so that the lattice still holds kMinStatisticsCells; a grid under
  // that (a map of a few km) is then exact, every cell, and cheap.
  const auto grid_bound =
      static_cast<long long>(std::sqrt(double(grid_cells) / kMinStatisticsCells));
  StatisticsLattice out;
  out.small_step = std::max<long long>(
      1, std::min(std::llround(p.tpi_statistics_step_m / p.cell_size_m), grid_bound));
  if (grid_bound <= 1) {  // a small grid: every cell for both (exact)
    out.small_step = out.large_step = 1, out.large_offset = 0;
    return out;
  }
  // The large TPI varies on the scale of its 300 m annulus: its lattice is 3x coarser, on the
  // centres of its blocks, so that each lattice cell interpolates its annulus mean from few
  // blocks (every block would be computed otherwise). Also where the cells are as coarse as
  // the small lattice's step (25 m cells: a small step of 1 cell): every cell of a large grid
  // for the large TPI was ~2/3 of the terrain stage's TPI work.
  const auto factor = static_cast<long long>(block_factor(p.tpi_large_outer_m / p.cell_size_m));
  out.large_step = (3 * out.small_step + factor - 1) / factor * factor;
  out.large_offset = factor / 2;
  return out;
}

/// The prefix sums behind an AnnulusTpi (a named type for the header's forward declaration).
struct TpiPrefixSums : RowPrefixSums {
  using RowPrefixSums::RowPrefixSums;
};

AnnulusTpi::AnnulusTpi(const Grid& elevation, double inner_m, double outer_m,
                       double min_valid_fraction, TpiRows rows)
    : elevation_(elevation),
      factor_(block_factor(outer_m / elevation.spec.cell_m)),
      outer_(disc_half_widths(outer_m / (elevation.spec.cell_m * double(factor_)))),
      inner_(disc_half_widths(inner_m / (elevation.spec.cell_m * double(factor_)))),
      // A query reads the outer disc's rows; interpolating between block means (factor > 1)
      // reaches one block row further each way.
      prefix_(std::make_unique<TpiPrefixSums>(elevation, factor_,
                                              rows == TpiRows::all ? 0 : outer_.size() + 2)),
      min_valid_fraction_(min_valid_fraction),
      block_spec_(elevation.spec) {
  block_spec_.cell_m = elevation.spec.cell_m * double(factor_);
  block_spec_.cols = prefix_->cols;
  block_spec_.rows = prefix_->rows;
  full_annulus_ =
      double(disc_cell_count(outer_) - disc_cell_count(inner_)) * double(factor_ * factor_);
  // A block mean is interpolated into many cells: worth keeping. A cell's mean (factor 1) is
  // asked about once (a lattice cell, or one of a segment's four).
  if (factor_ > 1) allocate_cache();
}

AnnulusTpi::~AnnulusTpi() = default;

void AnnulusTpi::allocate_cache() {
  block_mean_.assign(block_spec_.size(), std::numeric_limits<float>::quiet_NaN());
  known_.assign(block_spec_.size(), 0);
}

float AnnulusTpi::compute_block_mean(std::size_t col, std::size_t row) const {
  double outer_sum = 0.0, inner_sum = 0.0;
  std::uint64_t outer_n = 0, inner_n = 0;
  const auto r = static_cast<long>(outer_.size() / 2);  // the inner disc is within it
  prefix_->ensure(long(row) - r, long(row) + r);
  disc_sum(*prefix_, outer_, long(col), long(row), outer_sum, outer_n);
  disc_sum(*prefix_, inner_, long(col), long(row), inner_sum, inner_n);
  const std::uint64_t n = outer_n - inner_n;
  if (n == 0 || double(n) < min_valid_fraction_ * full_annulus_) {
    return std::numeric_limits<float>::quiet_NaN();
  }
  return static_cast<float>((outer_sum - inner_sum) / double(n));
}

float AnnulusTpi::block_mean(std::size_t col, std::size_t row) {
  if (known_.empty()) return compute_block_mean(col, row);
  const std::size_t k = row * block_spec_.cols + col;
  if (!known_[k]) block_mean_[k] = compute_block_mean(col, row), known_[k] = 1;
  return block_mean_[k];
}

void AnnulusTpi::compute_all() {
  // Two threads on one band would each move it under the other.
  if (!prefix_->all_rows) throw std::logic_error("AnnulusTpi::compute_all needs TpiRows::all");
  if (known_.empty()) allocate_cache();
  const std::size_t cols = block_spec_.cols;
  parallel_for<NoState>(
      block_spec_.rows,
      [&](std::size_t row, NoState&) {
        for (std::size_t col = 0; col < cols; ++col) {
          block_mean_[row * cols + col] = compute_block_mean(col, row);
          known_[row * cols + col] = 1;
        }
      },
      1, 2);
}

bool AnnulusTpi::at_block_centre(std::size_t col, std::size_t row) const {
  // bilinear()'s own block coordinates. Whole numbers: the bilinear weights are exactly 1 for
  // the own block and 0 for the others (or, at the grid's last block, the own block's mean is
  // taken), so the result is the own block's mean whatever the neighbours hold (a NaN among
  // them falls back to it too): the neighbours need not be computed. The large TPI's lattice
  // cells all lie at block centres: this saves three of the four block means of each.
  const GridSpec& s = elevation_.spec;
  const double fx = (s.centre_easting(col) - block_spec_.west_m) / block_spec_.cell_m - 0.5;
  const double fy = (s.centre_northing(row) - block_spec_.south_m) / block_spec_.cell_m - 0.5;
  return fx == std::floor(fx) && fy == std::floor(fy);
}

float AnnulusTpi::at(std::size_t col, std::size_t row) {
  const GridSpec& s = elevation_.spec;
  const float z = elevation_.at(col, row);
  if (std::isnan(z)) return z;
  double mean = block_mean(col / factor_, row / factor_);
  if (factor_ > 1 && !at_block_centre(col, row)) {
    // Between block centres: bilinear; next to a block without a mean, the own block's.
    const double between =
        bilinear(block_spec_, s.centre_easting(col), s.centre_northing(row),
                 [this](std::size_t c, std::size_t r) { return block_mean(c, r); });
    if (!std::isnan(between)) mean = between;
  }
  return std::isnan(mean) ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(z - mean);
}

Grid topographic_position(const Grid& elevation, double inner_m, double outer_m,
                          double min_valid_fraction) {
  AnnulusTpi annulus(elevation, inner_m, outer_m, min_valid_fraction, TpiRows::all);
  annulus.compute_all();  // then at() only reads: safe on both cores
  Grid tpi(elevation.spec);
  parallel_for<NoState>(
      elevation.spec.rows,
      [&](std::size_t row, NoState&) {
        for (std::size_t col = 0; col < elevation.spec.cols; ++col)
          tpi.at(col, row) = annulus.at(col, row);
      },
      1, 2);
  return tpi;
}

GridStatistics statistics(const Grid& grid) {
  GridStatistics out;
  double sum = 0.0, sum_sq = 0.0;
  for (const float v : grid.values) {
    if (std::isnan(v)) continue;
    sum += v, sum_sq += double(v) * v, ++out.count;
  }
  if (out.count == 0) return out;
  out.mean = sum / double(out.count);
  out.standard_deviation =
      std::sqrt(std::max(0.0, sum_sq / double(out.count) - out.mean * out.mean));
  return out;
}

Landform classify_landform(double z_small, double z_large, double slope_deg,
                           const TerrainParameters& p) noexcept {
  const double k = p.standard_deviations;
  const int small = z_small <= -k ? 0 : (z_small >= k ? 2 : 1);
  const int large = z_large <= -k ? 0 : (z_large >= k ? 2 : 1);
  static constexpr Landform table[3][3] = {
      {Landform::canyon, Landform::midslope_drainage, Landform::upland_drainage},
      {Landform::u_shaped_valley, Landform::plains, Landform::upper_slope},
      {Landform::local_ridge, Landform::midslope_ridge, Landform::mountain_top}};
  const Landform landform = table[small][large];
  if (landform == Landform::plains && slope_deg > p.flat_slope_deg) return Landform::open_slope;
  return landform;
}

TerrainModel analyse_terrain(Grid elevation, const TerrainParameters& p) {
  TerrainModel m{
      std::move(elevation), Grid(GridSpec{}), Grid(GridSpec{}), Grid(GridSpec{}), {}, {}, 1.0, 1.0};
  m.slope = slope_degrees(m.elevation);
  m.tpi_small = topographic_position(m.elevation, p.tpi_small_inner_m, p.tpi_small_outer_m,
                                     p.tpi_min_valid_fraction);
  m.tpi_large = topographic_position(m.elevation, p.tpi_large_inner_m, p.tpi_large_outer_m,
                                     p.tpi_min_valid_fraction);
  m.small_stats = statistics(m.tpi_small);
  m.large_stats = statistics(m.tpi_large);
  m.small_sd_used = std::max(m.small_stats.standard_deviation, p.tpi_small_min_sd_m);
  m.large_sd_used = std::max(m.large_stats.standard_deviation, p.tpi_large_min_sd_m);
  return m;
}

namespace {

PlanePoint point_along(std::span<const PlanePoint> line, double distance_m) {
  for (std::size_t i = 1; i < line.size(); ++i) {
    const double d = std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
    if (distance_m <= d || i + 1 == line.size()) {
      const double t = d > 0.0 ? std::clamp(distance_m / d, 0.0, 1.0) : 0.0;
      return {line[i - 1].x + t * (line[i].x - line[i - 1].x),
              line[i - 1].y + t * (line[i].y - line[i - 1].y)};
    }
    distance_m -= d;
  }
  return line.front();
}

std::optional<double> finite(double v) {
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

/// The DEM elevations at a structure segment's ends (NaN, NaN if it has none).
StructureEnds ends_of(const std::vector<StructureEnds>& structure_ends, std::size_t segment) {
  const auto it =
      std::lower_bound(structure_ends.begin(), structure_ends.end(), segment,
                       [](const StructureEnds& e, std::size_t i) { return e.segment < i; });
  return it != structure_ends.end() && it->segment == segment ? *it : StructureEnds{segment};
}

/// Elevation along a run of bridge/tunnel segments of a stroke, interpolated between the
/// run's two ends (the structure's abutments or portals, which are on the ground), whose DEM
/// elevations are the end segments' start/end elevations.
void assign_structure_run(RoadGraph& graph, const Stroke& stroke, std::size_t first,
                          std::size_t last, const std::vector<StructureEnds>& structure_ends) {
  const StrokeSegment& a = stroke.segments[first];
  const StrokeSegment& b = stroke.segments[last];
  const StructureEnds ends_a = ends_of(structure_ends, a.segment);
  const StructureEnds ends_b = ends_of(structure_ends, b.segment);
  double z0 = a.reversed ? ends_a.z_end_m : ends_a.z_start_m;
  double z1 = b.reversed ? ends_b.z_start_m : ends_b.z_end_m;
  if (std::isnan(z0)) z0 = z1;
  if (std::isnan(z1)) z1 = z0;
  if (std::isnan(z0)) return;  // neither end has elevation: NO_ELEVATION
  const double run_length = b.end_m - a.start_m;
  const double grade_along_stroke = run_length > 0.0 ? (z1 - z0) / run_length : 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    const StrokeSegment& ss = stroke.segments[i];
    Segment& s = graph.segments[ss.segment];
    const double t =
        run_length > 0.0 ? (0.5 * (ss.start_m + ss.end_m) - a.start_m) / run_length : 0.5;
    s.elevation_m = z0 + t * (z1 - z0);
    s.grade_percent = 100.0 * (ss.reversed ? -grade_along_stroke : grade_along_stroke);
    s.slope_deg = std::atan(std::abs(grade_along_stroke)) * kRadToDeg;
    s.landform = LandformLabel::structure(s.tunnel);
  }
}

}  // namespace

PlanePoint segment_midpoint(const RoadGraph& graph, const Segment& s) {
  return point_along(graph.line(s), 0.5 * graph.length_m(s));
}

void sample_terrain(const RoadGraph& graph, const TerrainModel& m,
                    const std::vector<std::size_t>& segments, std::vector<TerrainSample>& samples) {
  for (const std::size_t i : segments) {
    const Segment& s = graph.segments[i];
    const PlanePoint mid = segment_midpoint(graph, s);
    TerrainSample& t = samples[i];
    t.z_mid_m = static_cast<float>(m.elevation.sample(mid.x, mid.y));
    const std::span<const PlanePoint> line = graph.line(s);
    t.z_start_m = static_cast<float>(m.elevation.sample(line.front().x, line.front().y));
    t.z_end_m = static_cast<float>(m.elevation.sample(line.back().x, line.back().y));
    t.slope_deg = static_cast<float>(m.slope.sample(mid.x, mid.y));
    t.tpi_small_m = static_cast<float>(m.tpi_small.sample(mid.x, mid.y));
    t.tpi_large_m = static_cast<float>(m.tpi_large.sample(mid.x, mid.y));
  }
}

TpiStandardisation standardisation(const GridStatistics& small, const GridStatistics& large,
                                   const TerrainParameters& p) {
  return {small, large, std::max(small.standard_deviation, p.tpi_small_min_sd_m),
          std::max(large.standard_deviation, p.tpi_large_min_sd_m)};
}

/// `length_m`: the segment's (RoadGraph::length_m), metres.
void store_terrain_sample(Segment& s, double length_m, const TerrainSample& t) {
  if (s.bridge || s.tunnel) return;  // elevation from the structure's ends (assign_terrain)
  s.elevation_m = finite(t.z_mid_m);
  if (!s.elevation_m) return;
  s.slope_deg = finite(t.slope_deg);
  if (length_m > 0.0) s.grade_percent = finite(100.0 * (t.z_end_m - t.z_start_m) / length_m);
  s.tpi_small_m = finite(t.tpi_small_m);
  s.tpi_large_m = finite(t.tpi_large_m);
}

void assign_terrain(RoadGraph& graph, const std::vector<TerrainSample>& samples,
                    const TpiStandardisation& z, const TerrainParameters& p) {
  std::vector<StructureEnds> structure_ends;
  for (std::size_t i = 0; i < graph.segments.size(); ++i) {
    Segment& s = graph.segments[i];
    store_terrain_sample(s, graph.length_m(s), samples[i]);
    if (s.bridge || s.tunnel)
      structure_ends.push_back({i, samples[i].z_start_m, samples[i].z_end_m});
  }
  assign_terrain(graph, structure_ends, z, p);
}

void assign_terrain(RoadGraph& graph, const std::vector<StructureEnds>& structure_ends,
                    const TpiStandardisation& z, const TerrainParameters& p) {
  // The landform at each segment for the windows' costs (kNoLandform: unknown or a structure;
  // a byte, not the cost itself: 1 byte a segment instead of 8 at the end of the stage).
  constexpr std::uint8_t kNoLandform = 255;
  std::vector<std::uint8_t> landform_of(graph.segments.size(), kNoLandform);
  for (std::size_t i = 0; i < graph.segments.size(); ++i) {
    Segment& s = graph.segments[i];
    if (s.bridge || s.tunnel || !s.elevation_m) continue;  // structures: from their ends, below
    if (!s.tpi_small_m || !s.tpi_large_m) continue;
    const Landform landform = classify_landform((*s.tpi_small_m - z.small.mean) / z.small_sd_used,
                                                (*s.tpi_large_m - z.large.mean) / z.large_sd_used,
                                                s.slope_deg.value_or(0.0), p);
    s.landform = LandformLabel(landform);
    landform_of[i] = static_cast<std::uint8_t>(landform);
    if (is_crest_or_dip(landform)) s.reasons.add("CREST_OR_DIP");
  }
  for_each_stroke(graph, [&](const Stroke& stroke) {
    // Bridges and tunnels: runs of consecutive structure segments along the stroke.
    for (std::size_t i = 0; i < stroke.segments.size();) {
      const auto is_structure = [&](std::size_t k) {
        const Segment& s = graph.segments[stroke.segments[k].segment];
        return s.bridge || s.tunnel;
      };
      if (!is_structure(i)) {
        ++i;
        continue;
      }
      std::size_t last = i;
      while (last + 1 < stroke.segments.size() && is_structure(last + 1)) ++last;
      assign_structure_run(graph, stroke, i, last, structure_ends);
      i = last + 1;
    }
    std::vector<double> costs;
    costs.reserve(stroke.segments.size());
    for (const StrokeSegment& ss : stroke.segments) {
      const std::uint8_t landform = landform_of[ss.segment];
      costs.push_back(landform == kNoLandform ? kNaN : p.landform_cost[landform]);
    }
    const std::vector<double> mean =
        windowed_mean(stroke, costs, p.window_half_length_m, p.own_segment_weight);
    for (std::size_t k = 0; k < stroke.segments.size(); ++k) {
      Segment& s = graph.segments[stroke.segments[k].segment];
      if (!s.elevation_m) continue;
      if (std::isnan(mean[k])) {
        // A structure with no ground in its window: its profile is a straight line between
        // its ends, which hides nothing (the cost of plains would floor to 0 as well).
        if (s.bridge || s.tunnel) s.elevation_cost = 0;
        continue;
      }
      // Landform costs run 0..15; the elevation cost 0..9 as in the thesis' rank formula.
      const double cost = std::floor(mean[k] * 9.0 / 15.0 + 1e-9);
      s.elevation_cost = static_cast<int>(std::clamp(cost, 0.0, 9.0));
    }
  });
  for (Segment& s : graph.segments) {
    if (!s.elevation_cost) s.reasons.add("NO_ELEVATION");
  }
}

void assign_terrain(RoadGraph& graph, const TerrainModel& m, const TerrainParameters& p) {
  std::vector<std::size_t> all(graph.segments.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  std::vector<TerrainSample> samples(graph.segments.size());
  sample_terrain(graph, m, all, samples);
  assign_terrain(graph, samples, standardisation(m.small_stats, m.large_stats, p), p);
}
}  // namespace roadcross::preprocess
