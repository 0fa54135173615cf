// The region of an uncertain position (docs/runtime.md, "Position uncertainty"): the ellipse
// that holds region_probability of the fix's Gaussian, sampled at points of equal probability,
// and the road segment nearest to each sample.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "map_impl.hpp"
#include "polyline.hpp"

namespace roadcross {
namespace {

// The samples: kRings rings of equal probability, each with kAngles points at equal angles
// (odd rings turned by half a step), in the whitened frame where the Gaussian is circular.
// Equal probability per sample makes the share on suitable places a plain count.
constexpr int kRings = 8;
constexpr int kAngles = 32;

struct UnitDirections {
  std::array<double, 2 * kAngles> cos_values{}, sin_values{};
  UnitDirections() {
    for (int i = 0; i < 2 * kAngles; ++i) {
      const double angle = geo::kPi * i / kAngles;  // half steps of 2 pi / kAngles
      cos_values[i] = std::cos(angle);
      sin_values[i] = std::sin(angle);
    }
  }
};

const UnitDirections& unit_directions() {
  static const UnitDirections directions;
  return directions;
}

/// A covariance in the map's grid, checked, with its Cholesky factor L (Sigma = L L^T).
struct GridCovariance {
  double ee = 0.0, en = 0.0, nn = 0.0;
  double l11 = 0.0, l21 = 0.0, l22 = 0.0;
};

Status invalid(const std::string& message) {
  return {StatusCode::invalid_argument, "position uncertainty: " + message};
}

}  // namespace

namespace detail {

Status uncertainty_in_grid(const PositionUncertainty& u, const geo::UtmZone& zone,
                           const schema::PlanePoint& fix, PositionUncertainty& grid) {
  if (!std::isfinite(u.east_east_m2) || !std::isfinite(u.east_north_m2) ||
      !std::isfinite(u.north_north_m2)) {
    return invalid("the covariance (or sigma) has a NaN or infinite value");
  }
  if (!(u.east_east_m2 > 0.0) || !(u.north_north_m2 > 0.0) ||
      !(u.east_east_m2 * u.north_north_m2 - u.east_north_m2 * u.east_north_m2 > 0.0)) {
    return invalid(
        "sigma must be > 0 and the covariance positive definite (an exact position has no "
        "uncertainty: leave it unset)");
  }
  if (!(u.region_probability > 0.0 && u.region_probability < 1.0)) {
    return invalid("region_probability must be in (0, 1)");
  }
  grid = u;
  if (u.frame == PositionUncertainty::Frame::enu) {
    // true_yaw = grid_yaw + convergence: a vector in true ENU turns by -convergence into the
    // grid, Sigma_grid = R Sigma_enu R^T with R the rotation by -convergence.
    const geo::LatLon ll = geo::utm_to_wgs84(fix.x, fix.y, zone);
    const double c = geo::wgs84_to_utm(ll.lat_deg, ll.lon_deg, zone).convergence_rad;
    const double cs = std::cos(c), sn = std::sin(c);
    // R = [[cs, sn], [-sn, cs]]
    grid.frame = PositionUncertainty::Frame::grid;
    grid.east_east_m2 =
        cs * cs * u.east_east_m2 + 2.0 * cs * sn * u.east_north_m2 + sn * sn * u.north_north_m2;
    grid.north_north_m2 =
        sn * sn * u.east_east_m2 - 2.0 * cs * sn * u.east_north_m2 + cs * cs * u.north_north_m2;
    grid.east_north_m2 = -cs * sn * u.east_east_m2 + (cs * cs - sn * sn) * u.east_north_m2 +
                         cs * sn * u.north_north_m2;
  }
  return {};
}

}  // namespace detail

namespace {

Status grid_covariance(const PositionUncertainty& u, const geo::UtmZone& zone,
                       const schema::PlanePoint& fix, GridCovariance& out) {
  PositionUncertainty grid;
  Status status = detail::uncertainty_in_grid(u, zone, fix, grid);
  if (!status.ok()) return status;
  out.ee = grid.east_east_m2;
  out.en = grid.east_north_m2;
  out.nn = grid.north_north_m2;
  out.l11 = std::sqrt(out.ee);
  out.l21 = out.en / out.l11;
  out.l22 = std::sqrt(std::max(out.nn - out.l21 * out.l21, 0.0));
  if (!(out.l22 > 0.0)) return invalid("the covariance is not positive definite");
  return {};
}

/// The bounding box of the segment's points.
void set_box(detail::RegionSegment& s) {
  s.min_x = s.max_x = s.points.front().x;
  s.min_y = s.max_y = s.points.front().y;
  for (const schema::PlanePoint& q : s.points) {
    s.min_x = std::min(s.min_x, q.x);
    s.max_x = std::max(s.max_x, q.x);
    s.min_y = std::min(s.min_y, q.y);
    s.max_y = std::max(s.max_y, q.y);
  }
}

/// Lower bound of the squared distance from `p` to anything inside the box `b`, m^2.
double box_distance_sq_m2(const detail::BoxCandidate& b, const schema::PlanePoint& p) {
  const double dx = std::max(std::max(b.min_x - p.x, 0.0), p.x - b.max_x);
  const double dy = std::max(std::max(b.min_y - p.y, 0.0), p.y - b.max_y);
  return dx * dx + dy * dy;
}

double box_distance_sq_m2(const detail::RegionSegment& s, const schema::PlanePoint& p) {
  return box_distance_sq_m2(detail::BoxCandidate{0.0, s.min_x, s.min_y, s.max_x, s.max_y, 0}, p);
}

/// The segment's edges (start, vector, squared length).
void set_edges(detail::RegionSegment& s) {
  s.edges.resize(s.points.size() - 1);
  for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
    const schema::PlanePoint a = s.points[i], b = s.points[i + 1];
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double length_sq_m2 = dx * dx + dy * dy;
    s.edges[i] = {a.x, a.y, dx, dy, length_sq_m2 > 0.0 ? 1.0 / length_sq_m2 : 0.0};
  }
}

/// One ring's sample places in the grid, metres (arrays, so that the loops over them vectorise).
struct RingPlaces {
  std::array<double, kAngles> x{}, y{};
};

/// Squared distance (m^2) from each of the ring's places to the polyline of `edges`, and the
/// edge it is nearest to (the first of equals). Squares, not hypot, and a product with the
/// edge's inverse squared length, not a division: this runs for every sample and candidate.
void ring_distances_sq_m2(const std::vector<detail::RegionEdge>& edges, const RingPlaces& ring,
                          double* distance_sq_m2, std::uint32_t* nearest_edge) {
  std::array<double, kAngles> edge_sq{};
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const detail::RegionEdge e = edges[i];
    for (int j = 0; j < kAngles; ++j) {
      const double along = ((ring.x[j] - e.start_x) * e.dx + (ring.y[j] - e.start_y) * e.dy) *
                           e.inverse_length_sq_per_m2;
      const double t = std::min(std::max(along, 0.0), 1.0);  // min/max: vector instructions
      const double ex = e.start_x + t * e.dx - ring.x[j], ey = e.start_y + t * e.dy - ring.y[j];
      edge_sq[j] = ex * ex + ey * ey;
    }
    if (i == 0) {
      std::copy(edge_sq.begin(), edge_sq.end(), distance_sq_m2);
      std::fill(nearest_edge, nearest_edge + kAngles, 0u);
      continue;
    }
    for (int j = 0; j < kAngles; ++j) {
      if (edge_sq[j] < distance_sq_m2[j]) {
        distance_sq_m2[j] = edge_sq[j];
        nearest_edge[j] = static_cast<std::uint32_t>(i);
      }
    }
  }
}

/// The smaller angle between two road directions taken as axes, radians, [0, pi/2].
double axial_difference_rad(double a_rad, double b_rad) {
  const double d = std::abs(geo::angle_difference_rad(a_rad, b_rad));
  return d > geo::kPi / 2.0 ? geo::kPi - d : d;
}

}  // namespace

std::string detail::region_verdict_sql(int schema_version) {
  using C = schema::SegmentColumn;
  // What judge reads only to report, never to decide suitable (nor to tell the road): a
  // column missing from this list is read, so a column a verdict comes to need is never lost.
  // length_m, rank and highway stay read: the corrupt-map guard requires them (length_m
  // always, rank with score, highway against NOT_CROSSABLE_CLASS).
  static constexpr C kDescriptive[] = {C::class_cost,      C::junction_distance_m, C::radius_m,
                                       C::curvature_level, C::curvature_cost,      C::landform,
                                       C::elevation_cost,  C::maxspeed_kmh,        C::lanes,
                                       C::width_m,         C::crossing_distance_m, C::override_note,
                                       C::sight_forward_m, C::sight_backward_m,    C::sight_min_m,
                                       C::required_sight_m};
  std::vector<std::string> select;
  for (std::size_t e = 0; e < schema::kSegmentColumnCount; ++e) {
    const auto column = static_cast<C>(e);
    int position = -1;
    try {
      position = kAssessColumns[column];
    } catch (const std::logic_error&) {
      continue;  // not read by assess
    }
    if (select.size() <= static_cast<std::size_t>(position)) select.resize(position + 1);
    const bool descriptive = std::find(std::begin(kDescriptive), std::end(kDescriptive), column) !=
                             std::end(kDescriptive);
    select[position] =
        descriptive ? "NULL" : schema::SegmentSelection({column}).sql("", schema_version);
  }
  std::string sql = "SELECT ";
  for (std::size_t i = 0; i < select.size(); ++i) sql += (i ? ", " : "") + select[i];
  return sql + " FROM " + std::string(schema::kSegmentsTable) + " WHERE fid = ?1";
}

double detail::region_reach_m(const PositionUncertainty& u) {
  // The covariance's largest eigenvalue does not change when it is turned from ENU into the
  // grid, so neither does the region's semi-major axis.
  const double half_trace = 0.5 * (u.east_east_m2 + u.north_north_m2);
  const double root = std::hypot(0.5 * (u.east_east_m2 - u.north_north_m2), u.east_north_m2);
  const double p = u.region_probability;
  const double semi_major_m = std::sqrt(-2.0 * std::log1p(-p) * (half_trace + root));
  // Invalid uncertainties widen nothing: region_geometry rejects them after the locate.
  return std::isfinite(semi_major_m) && semi_major_m > 0.0 ? 2.0 * semi_major_m : 0.0;
}

std::size_t Map::Impl::region_rows(const schema::PlanePoint& fix, double half_x_m,
                                   double half_y_m) {
  const bool located_here = located_rows > 0 && located_at.x == fix.x && located_at.y == fix.y;
  if (located_here && half_x_m <= located_half_m && half_y_m <= located_half_m) {
    // Locate's box holds the region's: keep its rows whose geometry meets the region's box.
    // Those the R*Tree would add besides (its boxes are rounded outwards to floats) neither
    // meet the ellipse nor are nearest to any place of it, and the order stays the R*Tree's.
    std::size_t count = 0;
    for (std::size_t row = 0; row < located_rows; ++row) {
      detail::RegionSegment& s = region_segments[row];
      set_box(s);
      if (s.max_x < fix.x - half_x_m || s.min_x > fix.x + half_x_m || s.max_y < fix.y - half_y_m ||
          s.min_y > fix.y + half_y_m) {
        continue;
      }
      if (row != count) std::swap(s, region_segments[count]);
      ++count;
    }
    located_rows = 0;  // region_segments now holds the region's rows
    return count;
  }
  located_rows = 0;
  sqlite::Statement& stmt = queries.candidates;
  stmt.bind(1, fix.x - half_x_m);
  stmt.bind(2, fix.x + half_x_m);
  stmt.bind(3, fix.y - half_y_m);
  stmt.bind(4, fix.y + half_y_m);
  std::size_t count = 0;
  while (stmt.step()) {
    if (count == region_segments.size()) region_segments.emplace_back();
    detail::RegionSegment& s = region_segments[count];
    s.id = stmt.column_int64(0);
    if (!schema::decode_linestring(stmt.column_blob(1), s.points)) {
      stmt.reset();
      throw detail::corrupt_segment_error(detail::segment_problem(s.id, "malformed geometry"));
    }
    set_box(s);
    ++count;
  }
  stmt.reset();
  return count;
}

Status Map::Impl::region_geometry(const PositionUncertainty& uncertainty, const NearestRoad& road,
                                  detail::RegionGeometry& out) {
  const schema::PlanePoint fix{road.query.easting_m, road.query.northing_m};
  GridCovariance cov;
  Status status;
  try {
    status = grid_covariance(uncertainty, info.zone, fix, cov);
  } catch (const std::exception& e) {
    return invalid(e.what());
  }
  if (!status.ok()) return status;

  // The region: Mahalanobis radius k with P(chi^2_2 <= k^2) = p, i.e. k^2 = -2 ln(1 - p).
  const double p = uncertainty.region_probability;
  const double k = std::sqrt(-2.0 * std::log1p(-p));
  const double half_trace = 0.5 * (cov.ee + cov.nn);
  const double root = std::hypot(0.5 * (cov.ee - cov.nn), cov.en);
  out.region_probability = p;
  out.semi_major_m = k * std::sqrt(half_trace + root);
  out.semi_minor_m = k * std::sqrt(std::max(half_trace - root, 0.0));
  out.major_axis_yaw_rad = 0.5 * std::atan2(2.0 * cov.en, cov.ee - cov.nn);

  // Every segment nearest to some place of the region is within the fix's distance plus the
  // region's largest radius of that place, so inside this box.
  const double reach_m = road.distance_m + out.semi_major_m;
  const double half_x = k * cov.l11 + reach_m;
  const double half_y = k * std::sqrt(cov.nn) + reach_m;
  const std::size_t count = region_rows(fix, half_x, half_y);
  out.fix_index = std::numeric_limits<std::size_t>::max();
  // A margin of a millionth keeps the shortcut off the rounding of the exact test below.
  const double beyond_ellipse_m = out.semi_major_m * (1.0 + 1e-6) + 1e-6;
  const double beyond_ellipse_sq_m2 = beyond_ellipse_m * beyond_ellipse_m;
  for (std::size_t row = 0; row < count; ++row) {
    detail::RegionSegment& s = region_segments[row];
    s.sample_count = 0;
    if (s.id == road.segment_id) out.fix_index = row;
    if (box_distance_sq_m2(s, fix) > beyond_ellipse_sq_m2) {
      s.centreline_in_region = false;  // the ellipse lies within semi_major_m of the fix
      continue;
    }
    // Does the centreline run through the ellipse? In the whitened frame (z = L^-1 (x - fix))
    // the ellipse is the disc of radius k, and a linear map keeps straight edges straight.
    scratch.resize(s.points.size());
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const double z1 = (s.points[i].x - fix.x) / cov.l11;
      scratch[i] = {z1, (s.points[i].y - fix.y - cov.l21 * z1) / cov.l22};
    }
    s.centreline_in_region = detail::project_onto_polyline(scratch, {0.0, 0.0}).distance_m <= k;
  }
  if (out.fix_index == std::numeric_limits<std::size_t>::max()) {
    throw std::runtime_error("segment " + std::to_string(road.segment_id) + " is not indexed");
  }
  out.segment_count = count;

  const detail::RegionSegment& own = region_segments[out.fix_index];
  const double fix_direction =
      detail::polyline_direction_rad(own.points, detail::project_onto_polyline(own.points, fix));
  // The road's direction at a sample is its nearest edge's: computed once per edge.
  by_box_distance.clear();
  for (std::size_t i = 0; i < count; ++i) {
    detail::RegionSegment& s = region_segments[i];
    s.edge_spread_rad.assign(s.points.size() - 1, -1.0);
    set_edges(s);
    detail::BoxCandidate box{0.0, s.min_x, s.min_y, s.max_x, s.max_y, i};
    box.from_fix_m = std::sqrt(box_distance_sq_m2(box, fix));
    by_box_distance.push_back(box);
  }
  std::sort(by_box_distance.begin(), by_box_distance.end(),
            [](const detail::BoxCandidate& a, const detail::BoxCandidate& b) {
              return a.from_fix_m < b.from_fix_m ||
                     (a.from_fix_m == b.from_fix_m && a.index < b.index);
            });
  const UnitDirections& unit = unit_directions();
  std::size_t previous = out.fix_index;
  out.heading_spread_rad = 0.0;
  out.sample_count = 0;
  RingPlaces places;
  for (int ring = 0; ring < kRings; ++ring) {
    // The ring's middle in probability: P(r <= radius) = p (ring + 1/2) / kRings.
    const double radius = std::sqrt(-2.0 * std::log1p(-p * (ring + 0.5) / kRings));
    for (int step = 0; step < kAngles; ++step) {
      const int half_steps = 2 * step + (ring % 2);
      const double z1 = radius * unit.cos_values[half_steps];
      const double z2 = radius * unit.sin_values[half_steps];
      places.x[step] = fix.x + cov.l11 * z1;
      places.y[step] = fix.y + cov.l21 * z1 + cov.l22 * z2;
    }
    // No place of the ring is farther from the fix than ring_reach_m (the ellipse's semi-major
    // axis scaled to the ring, with a margin for rounding), and the fix's segment is within
    // road.distance_m of the fix: a segment whose box is farther than both from the fix is
    // nearer to no place of the ring than the fix's segment. by_box_distance is sorted by that
    // distance, so the candidates are a prefix of it.
    const double ring_reach_m = out.semi_major_m * radius / k * (1.0 + 1e-9);
    const double candidate_within_m = 2.0 * ring_reach_m + road.distance_m + 1e-6;
    std::size_t candidates = 0;
    while (candidates < count && by_box_distance[candidates].from_fix_m <= candidate_within_m) {
      ++candidates;
    }
    ring_distance_sq_m2.resize(candidates * kAngles);
    ring_nearest_edge.resize(candidates * kAngles);
    std::size_t previous_rank = candidates;  // previous's place among the candidates, if any
    for (std::size_t c = 0; c < candidates; ++c) {
      const std::size_t i = by_box_distance[c].index;
      if (i == previous) previous_rank = c;
      ring_distances_sq_m2(region_segments[i].edges, places, &ring_distance_sq_m2[c * kAngles],
                           &ring_nearest_edge[c * kAngles]);
    }
    for (int step = 0; step < kAngles; ++step) {
      // The nearest segment; of equals the previous place's (neighbours usually share it),
      // else the first by box distance.
      std::size_t best_rank = 0;
      double best_sq = ring_distance_sq_m2[step];
      for (std::size_t c = 1; c < candidates; ++c) {
        const double d = ring_distance_sq_m2[c * kAngles + step];
        if (d < best_sq) {
          best_rank = c;
          best_sq = d;
        }
      }
      if (previous_rank < candidates &&
          ring_distance_sq_m2[previous_rank * kAngles + step] == best_sq) {
        best_rank = previous_rank;
      }
      const std::size_t best = by_box_distance[best_rank].index;
      const std::uint32_t best_edge = ring_nearest_edge[best_rank * kAngles + step];
      detail::RegionSegment& nearest = region_segments[best];
      ++nearest.sample_count;
      ++out.sample_count;
      if (best != previous) {
        previous = best;
        previous_rank = best_rank;
      }
      double& spread = nearest.edge_spread_rad[best_edge];
      if (spread < 0.0) {
        const schema::PlanePoint a = nearest.points[best_edge], b = nearest.points[best_edge + 1];
        spread = axial_difference_rad(geo::grid_yaw_rad(b.x - a.x, b.y - a.y), fix_direction);
      }
      out.heading_spread_rad = std::max(out.heading_spread_rad, spread);
    }
  }
  return {};
}

}  // namespace roadcross
