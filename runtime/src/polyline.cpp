#include "polyline.hpp"

#include <cmath>
#include <limits>

#include "roadcross/geo.hpp"

namespace roadcross::detail {

PolylineProjection project_onto_polyline(std::span<const PlanePoint> points,
                                         PlanePoint p) noexcept {
  PolylineProjection best;
  best.distance_m = std::numeric_limits<double>::infinity();
  best.closest = points.front();
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const PlanePoint a = points[i];
    const PlanePoint b = points[i + 1];
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double length_sq = dx * dx + dy * dy;
    double t = 0.0;
    if (length_sq > 0.0) {
      t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / length_sq;
      t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    }
    const PlanePoint c{a.x + t * dx, a.y + t * dy};
    const double d = std::hypot(p.x - c.x, p.y - c.y);
    if (d < best.distance_m) {
      best = {c, d, i, t};
    }
  }
  return best;
}

namespace {
double edge_yaw(std::span<const PlanePoint> points, std::size_t i) noexcept {
  return geo::grid_yaw_rad(points[i + 1].x - points[i].x, points[i + 1].y - points[i].y);
}
}  // namespace

double polyline_direction_rad(std::span<const PlanePoint> points,
                              const PolylineProjection& at) noexcept {
  const std::size_t last_edge = points.size() - 2;
  std::size_t before = at.edge_index, after = at.edge_index;
  if (at.edge_fraction <= 0.0 && at.edge_index > 0) before = at.edge_index - 1;
  if (at.edge_fraction >= 1.0 && at.edge_index < last_edge) after = at.edge_index + 1;
  const double yaw_before = edge_yaw(points, before);
  if (before == after) return yaw_before;
  const double yaw_after = edge_yaw(points, after);
  return geo::normalize_angle_rad(yaw_before +
                                  0.5 * geo::angle_difference_rad(yaw_after, yaw_before));
}

}  // namespace roadcross::detail
