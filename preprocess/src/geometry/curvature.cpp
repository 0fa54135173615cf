#include "roadcross/preprocess/geometry/curvature.hpp"

#include <algorithm>
#include <cmath>

namespace roadcross::preprocess {

double circumradius_m(PlanePoint a, PlanePoint b, PlanePoint c, double straight_radius_m) noexcept {
  const double p = std::hypot(b.x - a.x, b.y - a.y);
  const double q = std::hypot(c.x - b.x, c.y - b.y);
  const double s = std::hypot(a.x - c.x, a.y - c.y);
  // Heron's product, (p+q+s)(q+s-p)(p+s-q)(p+q-s) = 16 * area^2; cancellation makes it slightly
  // negative for collinear points, which the guard below treats as straight.
  const double sixteen_area_sq = (p + q + s) * (q + s - p) * (p + s - q) * (p + q - s);
  if (!(sixteen_area_sq > 0.0)) return straight_radius_m;
  return std::min(p * q * s / std::sqrt(sixteen_area_sq), straight_radius_m);
}

namespace {

/// Arc-length positions of the points of a line.
std::vector<double> cumulative_lengths(const std::vector<PlanePoint>& line) {
  std::vector<double> s(line.size(), 0.0);
  for (std::size_t i = 1; i < line.size(); ++i) {
    s[i] = s[i - 1] + std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
  }
  return s;
}

/// The point at arc position `at` (may be outside [0, total] on a ring: wrapped).
PlanePoint point_at(const std::vector<PlanePoint>& line, const std::vector<double>& s, double at) {
  const double total = s.back();
  const auto it = std::upper_bound(s.begin(), s.end(), at);
  if (it == s.begin()) return line.front();
  if (it == s.end()) return line.back();
  const std::size_t j = static_cast<std::size_t>(it - s.begin());  // s[j-1] <= at < s[j]
  const double edge = s[j] - s[j - 1];
  const double t = edge > 0.0 ? (at - s[j - 1]) / edge : 0.0;
  (void)total;
  return {line[j - 1].x + t * (line[j].x - line[j - 1].x),
          line[j - 1].y + t * (line[j].y - line[j - 1].y)};
}

/// Arm of the triangle at a vertex whose neighbour is `neighbour_m` away: at least the baseline
/// (jitter between dense vertices), at most the maximum arm (a single vertex between long
/// straight edges is a corner, not a curve as wide as the edges).
double arm_m(double neighbour_m, const CurvatureOptions& options) {
  return std::max(options.baseline_m, std::min(neighbour_m, options.max_arm_m));
}

double wrap(double at, double total) {
  double r = std::fmod(at, total);
  return r < 0.0 ? r + total : r;
}

}  // namespace

std::vector<double> vertex_radii_m(const std::vector<PlanePoint>& line,
                                   const CurvatureOptions& options) {
  const std::size_t n = line.size();
  std::vector<double> radii(n, options.straight_radius_m);
  if (n < 3) return radii;
  const std::vector<double> s = cumulative_lengths(line);
  const double total = s.back();
  const bool ring = options.closed && total > 4.0 * options.baseline_m;
  for (std::size_t i = 0; i < n; ++i) {
    const bool first = (i == 0), last = (i + 1 == n);
    if (!ring && (first || last)) continue;
    if (ring && last) {
      radii[i] = radii[0];  // the closing point is the first point
      continue;
    }
    const std::size_t prev = first ? n - 2 : i - 1;
    const std::size_t next = i + 1;
    const double back_m = arm_m(first ? total - s[prev] : s[i] - s[prev], options);
    const double ahead_m = arm_m(s[next] - s[i], options);
    double before_at = s[i] - back_m, after_at = s[i] + ahead_m;
    if (ring) {
      before_at = wrap(before_at, total);
      after_at = wrap(after_at, total);
    } else if (before_at < 0.0 || after_at > total) {
      // Too close to an open end for a full baseline: use what the line offers.
      before_at = std::max(before_at, 0.0);
      after_at = std::min(after_at, total);
    }
    radii[i] = circumradius_m(point_at(line, s, before_at), line[i], point_at(line, s, after_at),
                              options.straight_radius_m);
  }
  return radii;
}

RadiusProfile radius_profile(const std::vector<PlanePoint>& line, const CurvatureOptions& options,
                             double max_spacing_m) {
  RadiusProfile out;
  if (line.empty()) return out;
  const std::vector<double> vertex_radii = vertex_radii_m(line, options);
  out.position_m.push_back(0.0);
  out.radius_m.push_back(vertex_radii[0]);
  for (std::size_t i = 1; i < line.size(); ++i) {
    const double start_m = out.position_m.back();
    const double length_m = std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
    const auto parts = static_cast<int>(std::ceil(length_m / max_spacing_m - 1e-9));
    for (int k = 1; k < parts; ++k) {
      out.position_m.push_back(start_m + length_m * k / parts);
      out.radius_m.push_back(options.straight_radius_m);
    }
    out.position_m.push_back(start_m + length_m);
    out.radius_m.push_back(vertex_radii[i]);
  }
  return out;
}

}  // namespace roadcross::preprocess
