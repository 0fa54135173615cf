#include "roadcross/preprocess/sight/sight.hpp"

#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/sight/fan.hpp"
#include "roadcross/preprocess/sight/road.hpp"
#include "roadcross/preprocess/sight/shadow.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <span>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace roadcross::preprocess {

void SightParameters::describe(std::vector<ParameterSpec>& out) {
  const std::string s = "sight";
  out.push_back({s, "enabled", &enabled, 0, 1, true,
                 "1: compute sight distances; 0: skip the stage (columns NULL)"});
  out.push_back({s, "sensor_height_m", &sensor_height_m, 0, 1000, false,
                 "robot's sensor above the ground at the kerb, metres"});
  out.push_back({s, "object_height_m", &object_height_m, 0, 100, false,
                 "height of the part of an approaching vehicle that must be seen, metres"});
  out.push_back({s, "range_m", &range_m, 1, 5000, false,
                 "sight is looked for up to this far along the road, metres"});
  out.push_back({s, "step_m", &step_m, 0.1, 100, false,
                 "vehicle positions are tried every step_m along the road (then bisected)"});
  out.push_back({s, "default_width_m", &default_width_m, 0, 100, false,
                 "carriageway width when the context stage gives none, metres"});
  out.push_back({s, "default_speed_kmh", &default_speed_kmh, 1, 300, false,
                 "road speed when the context stage gives none, km/h"});
  out.push_back({s, "crossing_speed_mps", &crossing_speed_mps, 0.05, 20, false,
                 "robot's speed while crossing, m/s"});
  out.push_back({s, "startup_time_s", &startup_time_s, 0, 600, false,
                 "from the decision to cross to moving, seconds"});
  out.push_back({s, "margin_s", &margin_s, 0, 600, false,
                 "safety margin added to the crossing time, seconds"});
  out.push_back({s, "building_height_m", &building_height_m, 0, 1000, false,
                 "building without height or building:levels, metres"});
  out.push_back({s, "level_height_m", &level_height_m, 0.5, 20, false,
                 "height of one building:levels level, metres"});
  out.push_back({s, "wall_height_m", &wall_height_m, 0, 100, false,
                 "barrier=wall without a height tag, metres"});
  out.push_back({s, "fence_height_m", &fence_height_m, 0, 100, false,
                 "barrier=fence without a height tag, metres"});
  out.push_back({s, "limited_visibility_unsuitable", &limited_visibility_unsuitable, 0, 1, true,
                 "1: LIMITED_VISIBILITY makes a segment unsuitable; 0: it adds rank_penalty"});
  out.push_back({s, "rank_penalty", &rank_penalty, 0, 14, true,
                 "rank added to a LIMITED_VISIBILITY segment when it is only a cost"});
}

namespace {

using sight_detail::crossing_parameter;
using sight_detail::cumulative_m;
using sight_detail::distance_m;
using sight_detail::EdgeGrid;
using sight_detail::end_nodes;
using sight_detail::Fan;
using sight_detail::leaving_directions;
using sight_detail::leg_at;
using sight_detail::LegLengths;
using sight_detail::lerp;
using sight_detail::Path;
using sight_detail::PlanLine;
using sight_detail::RoadFollower;

struct Point3 {
  double x = 0.0, y = 0.0, z = 0.0;
  double ground_m = 0.0;  ///< the ground under the point (z minus the sensor/object height)
};

/// The point at d_m along a path, for positions asked mostly near the last one (the steps go
/// outwards, the bisection stays between two of them): the leg is found by walking from the
/// last one instead of a binary search each time; the same leg and point either way.
class PathCursor {
 public:
  explicit PathCursor(const Path& path) : path_(path) {}

  PlanePoint at(double d_m) {
    const std::vector<double>& at_m = path_.at_m;
    // next_: the first vertex beyond d_m (std::upper_bound's answer; at_m increases).
    while (next_ < at_m.size() && at_m[next_] <= d_m) ++next_;
    while (next_ > 0 && at_m[next_ - 1] > d_m) --next_;
    if (next_ == 0) return path_.points.front();
    if (next_ == at_m.size()) return path_.points.back();
    const std::size_t i = next_;
    return lerp(path_.points[i - 1], path_.points[i],
                (d_m - at_m[i - 1]) / (at_m[i] - at_m[i - 1]));
  }

  /// Appends the path's vertices strictly between d0_m and d1_m. The points at(d) for d in
  /// [d0_m, d1_m] lie on the legs between at(d0_m), these vertices and at(d1_m), each within
  /// the rounding of lerp (~2e-9 m at UTM's 1e7 m) of its leg: inside the hull of those points
  /// to 1e-8 m.
  void vertices_between(double d0_m, double d1_m, std::vector<PlanePoint>& out) const {
    const std::vector<double>& at_m = path_.at_m;
    for (auto i = std::size_t(std::upper_bound(at_m.begin(), at_m.end(), d0_m) - at_m.begin());
         i < at_m.size() && at_m[i] < d1_m; ++i) {
      out.push_back(path_.points[i]);
    }
  }

 private:
  const Path& path_;
  std::size_t next_ = 0;
};

/// What blocks a line of sight: the terrain and the obstacle prisms.
class Scene {
 public:
  Scene(const Grid* terrain, const ObstacleEdges& edges)
      : terrain_(terrain), edges_(edges), grid_(edges) {}

  /// Ground elevation at p: the terrain, or `fallback` where it has none (or without it).
  double ground(const PlanePoint& p, double fallback) const {
    if (!terrain_) return fallback;
    const double z = terrain_->sample(p.x, p.y);
    return std::isnan(z) ? fallback : z;
  }

  bool has_terrain() const { return terrain_ != nullptr; }

  /// Edge i's two ends, for fan_candidates.
  auto ends() const {
    return [this](std::uint32_t i) { return std::pair{edges_.a(i), edges_.b(i)}; };
  }

  /// The obstacle edges that may block a line from `eye` to a target within the hull of `eye`
  /// and `outline` (fan_candidates), into `out`; empty: no obstacle blocks any of them.
  void candidates(Fan& fan, const Point3& eye, const std::vector<PlanePoint>& outline,
                  std::vector<sight_detail::CandidateEdge>& out) const {
    fan.reset({eye.x, eye.y}, outline);
    sight_detail::fan_candidates(grid_, fan, ends(), out);
  }

  /// On flat ground, true only when no obstacle edge can cast a shadow (leg_shadow) from either
  /// kerb on a point in the hull of the kerbs and `outline`: none comes within Fan::kMarginM of
  /// that hull (flat_candidates). Such a direction needs no search: every position of both kerbs
  /// is seen. `outline` is left as it was.
  bool open_on_flat_ground(Fan& fan, const Point3& left, const Point3& right,
                           std::vector<PlanePoint>& outline) const {
    return !flat_candidates(fan, left, right, outline, nullptr);
  }

  /// The obstacle edges that may cast a shadow from either eye, `left` or `right`, on a point in
  /// the hull of both eyes and `outline` on flat ground, into `out`; `outline` is left as it
  /// was. (True when there is one; with out = nullptr it stops there.)
  ///
  /// The edges EdgeGrid::any_in_polygon offers for the hull that Fan::edge_apart does not set
  /// apart: every other edge is at least 1 mm from the hull, so from every line between two of
  /// its points, and leg_shadow's side and fraction tests (linear in the edge's points, rounded
  /// to ~1e-11 of the values they compare, a millimetre's worth here) find no part of it in
  /// a leg's wedge. No crossing_parameter is computed on flat ground, so the eyes' own tests of
  /// Fan::edge_clear (for its rounding) are not needed.
  bool flat_candidates(Fan& fan, const Point3& left, const Point3& right,
                       std::vector<PlanePoint>& outline,
                       std::vector<sight_detail::CandidateEdge>* out) const {
    if (out) out->clear();
    outline.push_back({right.x, right.y});
    fan.reset({left.x, left.y}, outline);
    outline.pop_back();
    std::array<std::uint32_t, 64> judged;  // most edges judged once, as in fan_candidates
    judged.fill(std::numeric_limits<std::uint32_t>::max());
    const auto offered = [&](auto apart) ROADCROSS_INLINE {
      return grid_.any_in_polygon(fan.hull(), Fan::kMarginM, [&](std::uint32_t i) {
        std::uint32_t& slot = judged[i & 63];
        if (slot == i) return false;
        slot = i;
        const PlanePoint a = edges_.a(i), b = edges_.b(i);
        if (apart(a, b)) return false;
        if (!out) return true;
        out->push_back({a, b, i, {}});
        return false;
      });
    };
    // Almost always: every edge offered is within reach (edge_apart's own tests, not repeated).
    if (fan.reaches_all_of(grid_.longest_edge_m(), EdgeGrid::kCellM)) {
      return offered([&](const PlanePoint& a, const PlanePoint& b)
                         ROADCROSS_INLINE { return fan.separated_from(a, b); });
    }
    return offered([&](const PlanePoint& a, const PlanePoint& b)
                       ROADCROSS_INLINE { return fan.edge_apart(a, b); });
  }

  /// Edge i's opaque band above the ground.
  std::pair<float, float> band(std::uint32_t i) const {
    const ObstacleEdge edge = edges_[i];
    return {edge.bottom_m, edge.top_m};
  }

  /// Whether the vehicle at `target` is seen from `eye`, for a target of the fan that gave
  /// `candidates`: the same answer as testing the line against every edge of the cells along it
  /// (blocked_among).
  bool visible(const Point3& eye, const Point3& target,
               const std::vector<sight_detail::CandidateEdge>& candidates) const {
    if (terrain_blocks(eye, target)) return false;
    if (candidates.empty()) return true;
    const PlanLine line({eye.x, eye.y}, {target.x, target.y});
    return !sight_detail::blocked_among(
        candidates, {eye.x, eye.y}, {target.x, target.y},
        [&](const sight_detail::CandidateEdge& c) { return edge_blocks(c, line, eye, target); });
  }

  /// The terrain, sampled every cell along the line (bilinear), rises to the line.
  bool terrain_blocks(const Point3& eye, const Point3& target) const {
    if (!terrain_) return false;
    const double length = std::hypot(target.x - eye.x, target.y - eye.y);
    const auto n = static_cast<std::size_t>(std::ceil(length / terrain_->spec.cell_m));
    for (std::size_t k = 1; k < n; ++k) {
      const double t = double(k) / double(n);
      const double z =
          terrain_->sample(eye.x + t * (target.x - eye.x), eye.y + t * (target.y - eye.y));
      if (!std::isnan(z) && z >= eye.z + t * (target.z - eye.z)) return true;
    }
    return false;
  }

 private:
  /// Edge i's band is looked up only once the line crosses it in plan (rarely).
  bool edge_blocks(const sight_detail::CandidateEdge& c, const PlanLine& line, const Point3& eye,
                   const Point3& target) const {
    const double t = crossing_parameter(line.rx, line.ry, c.from_eye);  // (line's eye: the fan's)
    if (std::isnan(t)) return false;
    const double z = eye.z + t * (target.z - eye.z);
    const PlanePoint p{eye.x + t * (target.x - eye.x), eye.y + t * (target.y - eye.y)};
    const double base = ground(p, eye.ground_m + t * (target.ground_m - eye.ground_m));
    const ObstacleEdge edge = edges_[c.id];
    return z >= base + edge.bottom_m && z <= base + edge.top_m;
  }

  const Grid* terrain_;
  const ObstacleEdges& edges_;
  EdgeGrid grid_;
};

/// Counts of the work done, for the report.
struct SightWork {
  std::size_t lines = 0;          ///< lines of sight tested (against their fan's candidates)
  std::size_t fans = 0;           ///< fans tried
  std::size_t clear_fans = 0;     ///< of them without a candidate edge
  std::size_t fan_positions = 0;  ///< positions settled by clear fans without testing a line
  std::size_t candidates = 0;     ///< candidate edges of all the fans
  std::size_t open_tried = 0;     ///< directions tried as open to both kerbs (OpenDirections)
  std::size_t open = 0;           ///< of them found open (no search)
};

/// When to try a road direction as open to both kerbs at once (Scene::open_on_flat_ground) before
/// searching it kerb by kerb. The check costs about two fans and settles a direction whose
/// whole path, seen from the kerbs, has no obstacle near it (most directions on open
/// rural roads, fewer in dense towns); where it fails it is wasted. A thread works
/// through consecutive segments, mostly of one piece, whose views are alike: the check is tried
/// when the same direction of the segment before reached the range, and not for the next
/// kWaitAfterFailure segments after it failed. Only the time depends on this: the answers are
/// the search's either way.
class OpenDirections {
 public:
  bool worth_trying(int direction) {
    if (wait_[direction] > 0) {
      --wait_[direction];
      return false;
    }
    return reached_range_[direction];
  }
  void tried(int direction, bool open) {
    if (!open) wait_[direction] = kWaitAfterFailure;
  }
  void answered(int direction, bool reached_range) { reached_range_[direction] = reached_range; }

 private:
  static constexpr int kWaitAfterFailure = 8;
  std::array<bool, 2> reached_range_{true, true};
  std::array<int, 2> wait_{0, 0};
};

/// How far along `path` a vehicle stays continuously visible from `eye`: stepping out by
/// step_m until the first hidden position, then bisecting between it and the last visible one.
/// A road that ends (dead end) before the range hides no vehicle beyond: the answer is then the
/// range.
///
/// The positions are tried in fans: the next few positions at once. The fan is the hull of the
/// eye and the path from the last position seen (seen_m_) to the fan's last one; its candidate
/// edges (Scene::candidates) are the only ones that can block a line to a point of the path in
/// between, so each position's line, and each line of the bisection (its positions lie between
/// seen_m_ and the first hidden one), is tested against them alone, with the answer of a test
/// against every edge along the line. A fan without candidates settles all its positions at
/// once when there is no terrain (with a terrain their lines are still tested for it). So the
/// first hidden position and the bisection are the same as one line at a time, without the
/// walk through the grid per line.
class KerbSearch {
 public:
  KerbSearch(const Scene& scene, const Path& path, const Point3& eye, const SightParameters& p,
             SightWork& work, Fan& fan, std::vector<sight_detail::CandidateEdge>& candidates,
             std::vector<PlanePoint>& outline)
      : scene_(scene),
        cursor_(path),
        eye_(eye),
        p_(p),
        work_(work),
        fan_(fan),
        candidates_(candidates),
        outline_(outline),
        end_m_(std::min(p.range_m, path.length_m())),
        done_(!(seen_m_ < end_m_)),
        answer_m_(p.range_m) {}

  bool done() const { return done_; }
  double answer_m() const { return answer_m_; }  ///< once done()

  /// Tries the next fan of positions (and bisects when one is hidden). Positions beyond the
  /// first one at or past limit_m are left for later (answer_up_to asks no further). Only
  /// while !done().
  void step(double limit_m = std::numeric_limits<double>::infinity()) {
    std::size_t n = 0;  // positions in the fan: k_, k_ + 1, ...
    for (double d_m = 0.0; n < fan_size_;) {
      d_m = position_m(k_ + n++);
      if (!(d_m < end_m_) || d_m >= limit_m) break;
    }
    // The points at(d) for d from seen_m_ (the position before k_) to the fan's last position
    // lie in the hull of at(seen_m_), the path's vertices between and at(last_m) (to 1e-8 m,
    // which the fan allows): a straight road gives a triangle with the eye.
    const double last_m = position_m(k_ + n - 1);
    outline_.clear();
    outline_.push_back(cursor_.at(seen_m_));
    cursor_.vertices_between(seen_m_, last_m, outline_);
    outline_.push_back(cursor_.at(last_m));
    scene_.candidates(fan_, eye_, outline_, candidates_);
    ++work_.fans;
    work_.candidates += candidates_.size();
    fan_size_ = std::min(2 * fan_size_, kMaxFan);
    if (candidates_.empty() && !scene_.has_terrain()) {
      ++work_.clear_fans;
      work_.fan_positions += n;
      k_ += n;
      seen_m_ = last_m;
      done_ = !(seen_m_ < end_m_);
      return;
    }
    work_.clear_fans += candidates_.empty() ? 1 : 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d_m = position_m(k_++);
      if (!visible(d_m)) {
        bisect(d_m);
        return;
      }
      seen_m_ = d_m;
    }
    done_ = !(seen_m_ < end_m_);  // answer_m_ stays the range
  }

  /// min(cap_m, the answer). Once the vehicle is seen as far as cap_m the answer cannot be
  /// smaller, so cap_m is returned without looking further.
  double answer_up_to(double cap_m) {
    while (!done_) {
      if (seen_m_ >= cap_m) return cap_m;
      step(cap_m);
    }
    return std::min(cap_m, answer_m_);
  }

 private:
  /// Fans of kFirstFan positions first, each next one twice as large up to kMaxFan: at the
  /// default 5 m step an open road's 60 positions take 3 fans (12, 24, 24). A fan costs ~4 000
  /// instructions (its hull, the edges under it), a line tested against candidates ~600.
  /// Monaco, callgrind, whole build (first-max): 12-48 6.30 G; 10-50 6.36; 8-32 6.58; 16-48
  /// 6.60; 20-40 6.98; 8-32 growing 4x 6.82, 12-48 growing 3x 7.00. Again with the cheaper
  /// fans (per-fan crossing terms, axis bounds when needed): 12-48 5.60 G, 8-48 5.77, 16-64
  /// 5.85.
  static constexpr std::size_t kFirstFan = 12, kMaxFan = 48;

  /// The position `index` steps out (clamped to the end).
  double position_m(std::size_t index) const { return std::min(double(index) * p_.step_m, end_m_); }

  Point3 target(double d_m) {
    const PlanePoint q = cursor_.at(d_m);
    const double g = scene_.ground(q, eye_.ground_m);
    return Point3{q.x, q.y, g + p_.object_height_m, g};
  }

  /// Bisects between seen_m_ and the first hidden position, hidden_m (both in the last fan).
  void bisect(double hidden_m) {
    for (int i = 0; i < 6; ++i) {  // step / 64: 8 cm at the default step
      const double mid_m = 0.5 * (seen_m_ + hidden_m);
      (visible(mid_m) ? seen_m_ : hidden_m) = mid_m;
    }
    answer_m_ = seen_m_, done_ = true;
  }

  /// For a position between seen_m_ and the last fan's last position.
  bool visible(double d_m) {
    ++work_.lines;
    return scene_.visible(eye_, target(d_m), candidates_);
  }

  const Scene& scene_;
  PathCursor cursor_;
  const Point3 eye_;
  const SightParameters& p_;
  SightWork& work_;
  Fan& fan_;
  std::vector<sight_detail::CandidateEdge>& candidates_;  ///< the last fan's
  std::vector<PlanePoint>& outline_;  ///< points whose hull holds the fan's targets (a buffer)
  std::size_t fan_size_ = kFirstFan;  ///< positions in the next fan
  const double end_m_;
  std::size_t k_ = 1;    ///< the next step
  double seen_m_ = 0.0;  ///< the vehicle is seen at every position tried up to here
  bool done_;
  double answer_m_;
};

/// The smaller of the two kerbs' answers along one road direction (the robot may arrive on
/// either side). The kerbs step out together, so that neither is followed further than the
/// other's answer: searching one kerb after the other followed the first as far as it saw
/// (300 m on an open road) even when the second stopped after 20 m. The answer is the same:
/// min(a, b) whatever the order, every position tried by the same arithmetic.
double worse_kerb_m(KerbSearch& a, KerbSearch& b) {
  while (!a.done() && !b.done()) {
    a.step();
    if (!a.done()) b.step();
  }
  KerbSearch& finished = a.done() ? a : b;
  KerbSearch& other = a.done() ? b : a;
  return other.answer_up_to(finished.answer_m());
}

/// Buffers of the flat-ground search (flat_worse_kerb_m), reused from segment to segment.
struct FlatBuffers {
  std::vector<PlanePoint> outline;   ///< the chunk's road: its start, vertices, end
  std::vector<double> outline_at_m;  ///< each outline point's distance along the path
  struct Shadow {
    double from_m, to_m;  ///< along the path
  };
  std::vector<Shadow> shadows;         ///< one kerb's, in the chunk
  std::vector<PlanePoint> relative;    ///< the outline relative to the eye
  std::vector<double> leg_sign;        ///< each leg's turn seen from the eye: 1, -1, 0 (in line)
  std::vector<double> side_a, side_b;  ///< an edge's ends against each outline point's ray
};

/// The shadows the `candidates` cast from `eye` on flat ground on the legs of b.outline, in
/// metres along the path, into b.shadows.
void cast_shadows(const Point3& eye, const std::vector<sight_detail::CandidateEdge>& candidates,
                  const Scene& scene, const SightParameters& p, FlatBuffers& b) {
  b.shadows.clear();
  // The outline relative to the eye, and each leg's orientation: an edge wholly outside one of
  // a leg's two rays from the eye casts no shadow on it, and those side tests share each
  // outline point between two legs (the same arithmetic as leg_shadow's own, so skipping a leg
  // here gives its answer).
  const std::size_t points = b.outline.size();
  b.relative.resize(points);
  for (std::size_t i = 0; i < points; ++i) {
    b.relative[i] = {b.outline[i].x - eye.x, b.outline[i].y - eye.y};
  }
  b.leg_sign.resize(points);
  for (std::size_t leg = 0; leg + 1 < points; ++leg) {
    const PlanePoint &e0 = b.relative[leg], &e1 = b.relative[leg + 1];
    const double d = e0.x * e1.y - e0.y * e1.x;
    const double scale =
        (std::abs(e0.x) + std::abs(e0.y)) * (std::abs(e1.x - e0.x) + std::abs(e1.y - e0.y));
    // 0 (never skipped) well before leg_shadow takes the leg as in line with the eye (1e-12).
    b.leg_sign[leg] = !(std::abs(d) > 1e-9 * scale) ? 0.0 : d > 0.0 ? 1.0 : -1.0;
  }
  b.side_a.resize(points);
  b.side_b.resize(points);
  for (const sight_detail::CandidateEdge& c : candidates) {
    const PlanePoint a{c.a.x - eye.x, c.a.y - eye.y}, bb{c.b.x - eye.x, c.b.y - eye.y};
    for (std::size_t i = 0; i < points; ++i) {
      const PlanePoint& r = b.relative[i];
      b.side_a[i] = r.x * a.y - r.y * a.x;
      b.side_b[i] = r.x * bb.y - r.y * bb.x;
    }
    bool band_read = false;
    sight_detail::BlockingFractions fractions;
    for (std::size_t leg = 0; leg + 1 < points; ++leg) {
      const double sign = b.leg_sign[leg];
      if (sign != 0.0) {
        if (sign * b.side_a[leg] < 0.0 && sign * b.side_b[leg] < 0.0) continue;
        if (sign * b.side_a[leg + 1] > 0.0 && sign * b.side_b[leg + 1] > 0.0) continue;
      }
      if (!band_read) {  // the band is read only for an edge in some leg's wedge
        const auto [bottom_m, top_m] = scene.band(c.id);
        fractions =
            sight_detail::blocking_fractions(bottom_m, top_m, p.sensor_height_m, p.object_height_m);
        band_read = true;
        if (fractions.empty()) break;
      }
      const sight_detail::LegShadow u = sight_detail::leg_shadow(
          {eye.x, eye.y}, b.outline[leg], b.outline[leg + 1], c.a, c.b, fractions);
      if (u.empty()) continue;
      const double from_m = b.outline_at_m[leg], length_m = b.outline_at_m[leg + 1] - from_m;
      b.shadows.push_back({from_m + u.from * length_m, from_m + u.to * length_m});
    }
  }
}

/// The first of the positions first..last (position_m(index): distance along the path, every
/// step_m) inside one of `shadows`, or last + 1.
template <typename PositionM>
std::size_t first_in_shadow(const std::vector<FlatBuffers::Shadow>& shadows, std::size_t first,
                            std::size_t last, const PositionM& position_m, double step_m) {
  std::size_t hidden = last + 1;
  for (const FlatBuffers::Shadow& shadow : shadows) {
    // The index of the first position at or after from_m, then corrected for the rounding of
    // the division and for the clamp at the end.
    const double index = std::ceil(shadow.from_m / step_m);
    std::size_t j = index <= double(first) ? first
                    : index > double(last) ? last + 1
                                           : static_cast<std::size_t>(index);
    while (j > first && position_m(j - 1) >= shadow.from_m) --j;
    while (j <= last && position_m(j) < shadow.from_m) ++j;
    if (j < hidden && j <= last && position_m(j) <= shadow.to_m) hidden = j;
  }
  return hidden;
}

/// The smaller of the two kerbs' sight distances along one road direction on flat ground (no
/// terrain): the answer of the stepping search (KerbSearch, worse_kerb_m) with each line of
/// sight's fate read from the shadows the obstacle edges cast on the road instead of testing the
/// line. The road is taken in chunks of positions (4, then 8 steps); one hull of both eyes and
/// the chunk's road gives the candidate edges of both kerbs (an edge that may block no line from
/// either is dropped: Scene::flat_candidates); each candidate casts on each leg of the chunk the
/// interval of the leg whose lines it blocks (sight_detail::leg_shadow, closed form). A position
/// is hidden when it lies in a shadow; the first hidden one is bisected six times against the
/// shadows, as the search bisects with lines. So the answer is the stepping search's (a vehicle
/// hidden only between two positions stays unseen, as before), up to the rounding of a line
/// grazing an obstacle corner. A chunk's hull and its walk through the grid serve both kerbs,
/// and no line is tested: small chunks cost less than the fans' 12-48 positions, whose lines
/// were what made a large fan pay. But every chunk's hull reaches back to the eyes, so the cells
/// near them are walked once per chunk: where guess_m (the view of the segment before, moved by
/// the distance between the two) says the view goes on, the first chunk takes every position up
/// to kGuessMarginM short of it at once, and the small chunks start from there. The chunks only
/// share out the work: a shadow is the set of a leg's points whose lines the edge crosses, the
/// same whichever chunk the leg is in, so the answer does not depend on them (nor on the guess)
/// beyond the rounding of a projected point.
double flat_worse_kerb_m(const Scene& scene, RoadFollower& road, const std::array<Point3, 2>& eyes,
                         const SightParameters& p, double guess_m, SightWork& work, Fan& fan,
                         std::vector<sight_detail::CandidateEdge>& candidates, FlatBuffers& b) {
  // Positions a chunk (docs/performance-log.md, issue 27: the sizes tried).
  static constexpr std::size_t kFirstChunk = 4, kMaxChunk = 8;
  constexpr double kGuessMarginM = 10.0;
  const Path& path = road.path();
  // The road is followed a chunk at a time (RoadFollower), each time beyond the chunk's last
  // position: up to there, end_m = min(range, the path's length so far) answers every use as the
  // whole road's end would (the path is longer than what is asked unless it is at its end or at
  // the range, where its end is the road's).
  double end_m = 0.0;
  const auto follow_beyond = [&](double limit_m) {
    road.extend_beyond(limit_m);
    end_m = std::min(p.range_m, path.length_m());
  };
  follow_beyond(0.0);
  const auto position_m = [&](std::size_t index) {
    return std::min(double(index) * p.step_m, end_m);
  };
  PathCursor cursor(path);
  // The chunk's road from seen_m to to_m: its points and their distances along the path.
  const auto outline_between = [&](double seen_m, double to_m) {
    b.outline.clear();
    b.outline_at_m.clear();
    b.outline.push_back(cursor.at(seen_m));
    b.outline_at_m.push_back(seen_m);
    for (auto i = std::size_t(std::upper_bound(path.at_m.begin(), path.at_m.end(), seen_m) -
                              path.at_m.begin());
         i < path.at_m.size() && path.at_m[i] < to_m; ++i) {
      b.outline.push_back(path.points[i]);
      b.outline_at_m.push_back(path.at_m[i]);
    }
    b.outline.push_back(cursor.at(to_m));
    b.outline_at_m.push_back(to_m);
  };
  std::size_t next = 1;  // the next position's index
  double seen_m = 0.0;   // every position up to here is seen from both kerbs
  // Where the view probably ends (guess_m, from the segment before) the first chunk stops
  // short of it: one hull instead of the small ones on the way; the small ones follow.
  const double guessed = std::floor((guess_m - kGuessMarginM) / p.step_m);
  const bool big_first = guessed > double(kFirstChunk);
  const auto next_size = [](std::size_t chunk) {
    return chunk > kMaxChunk ? kFirstChunk : std::min(2 * chunk, kMaxChunk);
  };
  for (std::size_t chunk = big_first ? std::size_t(guessed) : kFirstChunk; seen_m < end_m;
       chunk = next_size(chunk)) {
    follow_beyond(double(next + chunk - 1) * p.step_m);
    std::size_t n = 1;  // positions in the chunk: up to `chunk`, the last one at end_m at most
    while (n < chunk && position_m(next + n - 1) < end_m) ++n;
    const std::size_t first = next;
    std::size_t last = next + n - 1;  // this chunk's positions; the second kerb may stop short
    next += n;
    outline_between(seen_m, position_m(last));
    scene.flat_candidates(fan, eyes[0], eyes[1], b.outline, &candidates);
    ++work.fans;
    work.candidates += candidates.size();
    if (candidates.empty()) {
      ++work.clear_fans;
      seen_m = position_m(last);
      continue;
    }
    bool hidden_somewhere = false;
    double answer_m = std::numeric_limits<double>::infinity();
    for (const Point3& eye : eyes) {
      cast_shadows(eye, candidates, scene, p, b);
      const std::size_t hidden = first_in_shadow(b.shadows, first, last, position_m, p.step_m);
      if (hidden > last) continue;
      const auto visible = [&](double d_m) {
        return std::none_of(b.shadows.begin(), b.shadows.end(), [&](const auto& shadow) {
          return shadow.from_m <= d_m && d_m <= shadow.to_m;
        });
      };
      double lo_m = position_m(hidden - 1), hi_m = position_m(hidden);
      for (int i = 0; i < 6; ++i) {  // as KerbSearch::bisect
        const double mid_m = 0.5 * (lo_m + hi_m);
        (visible(mid_m) ? lo_m : hi_m) = mid_m;
      }
      answer_m = std::min(answer_m, lo_m);
      hidden_somewhere = true;
      // The other kerb matters only before this position: seen as far as the one before it, it
      // cannot be the worse kerb.
      last = hidden;
    }
    // A kerb seen through the chunk sees at least its last position, more than the other's
    // answer.
    if (hidden_somewhere) return answer_m;
    seen_m = position_m(last);
  }
  return p.range_m;  // seen to the range, or to a dead end (which hides nothing beyond)
}

double required_sight_m(const RoadGraph& graph, const Segment& s, const SightParameters& p) {
  const double speed_mps = graph.maxspeed_kmh(s).value_or(float(p.default_speed_kmh)) / 3.6;
  const double width_m = graph.width_m(s).value_or(float(p.default_width_m));
  return speed_mps * (width_m / p.crossing_speed_mps + p.startup_time_s + p.margin_s);
}

struct Context {
  const RoadGraph& graph;
  const Incidences incidences;
  const std::vector<std::array<std::uint32_t, 2>> nodes;  ///< end_nodes
  const std::vector<std::vector<double>> cumulative;
  const std::vector<std::array<PlanePoint, 2>> leaving;  ///< leaving_directions
  const Scene& scene;
  const SightParameters& p;
};

/// What a thread keeps from segment to segment (buffers, and when to try a direction open).
struct SightThread {
  SightWork work;
  Fan fan;
  std::vector<sight_detail::CandidateEdge> candidates;
  std::vector<PlanePoint> outline;
  OpenDirections open;
  Path ahead, behind;                                    ///< the segment's two directions
  LegLengths legs;                                       ///< of the pieces they follow
  std::array<std::vector<PlanePoint>, 2> kerb_outlines;  ///< KerbSearch's, per kerb
  FlatBuffers flat;
  /// The segment this thread did last (its index, its position in its piece) and its two
  /// answers: a guess for the next segment's when it is the next one of the same piece.
  std::size_t last_index = std::numeric_limits<std::size_t>::max();
  double last_pos_m = 0.0;
  std::array<double, 2> last_answer_m{0.0, 0.0};
};

/// The points whose hull holds every position along `path` up to the range (to 1e-8 m, see
/// PathCursor::vertices_between): its start, its vertices, its point at the range.
void outline_to_range(const Path& path, double range_m, std::vector<PlanePoint>& out) {
  PathCursor cursor(path);
  const double end_m = std::min(range_m, path.length_m());
  out.clear();
  out.push_back(cursor.at(0.0));
  cursor.vertices_between(0.0, end_m, out);
  out.push_back(cursor.at(end_m));
}

/// Both directions from both kerbs of segment s; each direction keeps its worse kerb (the
/// robot may arrive on either side).
void sight_of_segment(const Context& c, Segment& s, SightThread& t) {
  SightWork& work = t.work;
  Fan& fan = t.fan;
  std::vector<sight_detail::CandidateEdge>& candidates = t.candidates;
  const RoadPiece& piece = c.graph.pieces[s.piece_index];
  const std::vector<double>& cum = c.cumulative[s.piece_index];
  const double pos_m =
      std::clamp(c.graph.offset_in_piece_m(s) + 0.5 * c.graph.length_m(s), 0.0, cum.back());
  // The two directions, each followed as far as its search asks.
  std::array<RoadFollower, 2> roads{RoadFollower(c.graph, c.incidences, c.nodes, c.cumulative,
                                                 c.leaving, c.p.range_m, t.ahead, t.legs),
                                    RoadFollower(c.graph, c.incidences, c.nodes, c.cumulative,
                                                 c.leaving, c.p.range_m, t.behind, t.legs)};
  roads[0].start(s.piece_index, pos_m, true);
  roads[1].start(s.piece_index, pos_m, false);
  const Path& ahead = t.ahead;
  const std::size_t leg = leg_at(cum, pos_m);
  const PlanePoint& a = piece.points[leg];
  const PlanePoint& b = piece.points[leg + 1];
  const double len = std::max(1e-9, distance_m(a, b));
  const PlanePoint normal{-(b.y - a.y) / len, (b.x - a.x) / len};
  const double half_width_m = 0.5 * c.graph.width_m(s).value_or(float(c.p.default_width_m));
  std::array<Point3, 2> eyes;  // the left kerb, then the right one
  for (std::size_t i = 0; i < 2; ++i) {
    const double side = i == 0 ? 1.0 : -1.0;
    const PlanePoint kerb{ahead.points[0].x + side * half_width_m * normal.x,
                          ahead.points[0].y + side * half_width_m * normal.y};
    // On a bridge the ground under the kerb is the valley: the structure's elevation counts.
    const double fallback = s.elevation_m.value_or(0.0f);
    const double g = s.bridge ? fallback : c.scene.ground(kerb, fallback);
    eyes[i] = Point3{kerb.x, kerb.y, g + c.p.sensor_height_m, g};
  }
  // The view of the segment before on the piece ended about its offset further on ahead, and
  // nearer behind (only a guess: it sets the first chunk, not the answer).
  const std::size_t index = static_cast<std::size_t>(&s - c.graph.segments.data());
  std::array<double, 2> guess_m{0.0, 0.0};
  if (t.last_index + 1 == index && index > 0 &&
      c.graph.segments[index - 1].piece_index == s.piece_index) {
    const double moved_m = pos_m - t.last_pos_m;
    guess_m = {t.last_answer_m[0] - moved_m, t.last_answer_m[1] + moved_m};
  }
  const auto worse_m = [&](int direction) {
    RoadFollower& road = roads[static_cast<std::size_t>(direction)];
    const Path& path = road.path();
    if (!c.scene.has_terrain() && t.open.worth_trying(direction)) {
      road.extend_to_range();
      outline_to_range(path, c.p.range_m, t.outline);
      const bool open = c.scene.open_on_flat_ground(fan, eyes[0], eyes[1], t.outline);
      ++work.open_tried, work.open += open ? 1 : 0;
      t.open.tried(direction, open);
      // Every position of both kerbs is seen: the search's answer (a road that ends before
      // the range hides nothing beyond it).
      if (open) return c.p.range_m;
    }
    if (!c.scene.has_terrain()) {
      const double answer_m = flat_worse_kerb_m(c.scene, road, eyes, c.p, guess_m[direction], work,
                                                fan, candidates, t.flat);
      t.open.answered(direction, answer_m >= c.p.range_m);
      return answer_m;
    }
    // The kerbs take turns, each step computing its fan and candidates and using them before
    // it returns: the two share the buffers.
    road.extend_to_range();
    KerbSearch left(c.scene, path, eyes[0], c.p, work, fan, candidates, t.kerb_outlines[0]);
    KerbSearch right(c.scene, path, eyes[1], c.p, work, fan, candidates, t.kerb_outlines[1]);
    const double answer_m = worse_kerb_m(left, right);
    t.open.answered(direction, answer_m >= c.p.range_m);
    return answer_m;
  };
  const double forward_m = worse_m(0), backward_m = worse_m(1);
  t.last_index = index, t.last_pos_m = pos_m, t.last_answer_m = {forward_m, backward_m};
  s.sight_forward_m = forward_m;
  s.sight_backward_m = backward_m;
  s.sight_min_m = std::min(forward_m, backward_m);
  s.required_sight_m = required_sight_m(c.graph, s, c.p);
  if (*s.sight_min_m < *s.required_sight_m) s.reasons.add("LIMITED_VISIBILITY");
}

}  // namespace

SightReport compute_sight(RoadGraph& graph, const Grid* terrain, const ObstacleEdges& obstacles,
                          const SightParameters& p, DonePrefix* done) {
  // The roads' tables on a thread of their own while the grid is built: they are serial, and
  // so is the grid's first pass.
  struct RoadTables {
    std::vector<std::vector<double>> cumulative;
    Incidences incidences;
    std::vector<std::array<std::uint32_t, 2>> nodes;
    std::vector<std::array<PlanePoint, 2>> leaving;
  };
  std::future<RoadTables> road_tables = std::async(std::launch::async, [&graph] {
    std::vector<std::vector<double>> cumulative;
    cumulative.reserve(graph.pieces.size());
    for (const RoadPiece& piece : graph.pieces) cumulative.push_back(cumulative_m(piece.points));
    Incidences incidences = incidences_of(graph);
    std::vector<std::array<std::uint32_t, 2>> nodes = end_nodes(graph, incidences);
    return RoadTables{std::move(cumulative), std::move(incidences), std::move(nodes),
                      leaving_directions(graph)};
  });
  const Scene scene(terrain, obstacles);
  RoadTables tables = road_tables.get();
  const Context context{graph,
                        std::move(tables.incidences),
                        std::move(tables.nodes),
                        std::move(tables.cumulative),
                        std::move(tables.leaving),
                        scene,
                        p};

  // Dense streets take much longer than open roads: threads take small chunks in turn.
  constexpr std::size_t kChunk = 64;
  // Each thread's buffers are reused by every segment it does.
  const std::vector<SightThread> threads = parallel_for<SightThread>(
      graph.segments.size(),
      [&](std::size_t i, SightThread& thread) {
        Segment& s = graph.segments[i];
        // A tunnel is never crossed (TUNNEL) and the terrain above it would hide everything.
        if (!s.tunnel) sight_of_segment(context, s, thread);
      },
      kChunk, 16, done);
  std::size_t tests = 0, fans = 0, clear_fans = 0, fan_positions = 0, candidates = 0,
              open_tried = 0, open = 0;
  for (const SightThread& thread : threads) {
    const SightWork& w = thread.work;
    tests += w.lines, fans += w.fans, clear_fans += w.clear_fans;
    fan_positions += w.fan_positions, candidates += w.candidates;
    open_tried += w.open_tried, open += w.open;
  }

  SightReport report;

  report.lines_of_sight = tests;
  report.fans = fans;
  report.clear_fans = clear_fans;
  report.fan_positions = fan_positions;
  report.candidate_edges = candidates;
  report.open_directions_tried = open_tried;
  report.open_directions = open;
  for (const Segment& s : graph.segments) {
    report.skipped_tunnels += s.tunnel ? 1 : 0;
    report.segments += s.sight_min_m ? 1 : 0;
    report.limited += s.reasons.contains("LIMITED_VISIBILITY") ? 1 : 0;
  }
  return report;
}

void apply_sight_rank_penalty(Segment& s, const SightParameters& p) {
  if (p.limited_visibility_unsuitable != 0.0) return;
  if (!s.rank || !s.reasons.contains("LIMITED_VISIBILITY")) return;
  s.rank = std::min(14, *s.rank + static_cast<int>(p.rank_penalty));
}

void apply_sight_rank_penalty(RoadGraph& graph, const SightParameters& p) {
  for (Segment& s : graph.segments) apply_sight_rank_penalty(s, p);
}

}  // namespace roadcross::preprocess
