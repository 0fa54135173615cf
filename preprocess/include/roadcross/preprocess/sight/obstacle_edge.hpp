// What blocks a line of sight: the edges of obstacles' footprints. Its own header,
// below both the sight stage (sight.hpp) and its edge grid (edge_grid.hpp), so that the grid
// needs nothing of the stage.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

/// Forces a small function of the sight stage's inner loops inline (GCC otherwise leaves some out
/// of line as their callers grow; docs/performance-log.md, issue 27).
#if defined(__GNUC__)
#define ROADCROSS_INLINE __attribute__((always_inline))
#else
#define ROADCROSS_INLINE
#endif

namespace roadcross::preprocess {

using schema::PlanePoint;

/// One edge of an obstacle's footprint (a building outline or a wall line), UTM metres, with
/// the opaque band above the local ground: from bottom_m (0, or min_height for a building on
/// pillars or over a passage) to top_m (metres above the ground, bottom_m <= top_m).
struct ObstacleEdge {
  PlanePoint a, b;
  float bottom_m = 0.0f, top_m = 0.0f;
};

/// An 8-byte slot of ObstacleEdges: a vertex in fixed point (x >= 0) or a run's header (x < 0).
/// No default member initialisers, so that an array of them can be allocated without touching
/// its pages (they cost no memory until written).
struct FixedSlot {
  std::int32_t x, y;
};

/// Where fixed-point vertices lie: the point of slot (x, y) is origin + (x, y) * unit, with
/// 0 <= x, y <= 2^31 - 1 (8 bytes a vertex instead of two doubles' 16). The unit is
/// the finest power of two from 2^-10 m (~1 mm, far below OSM's 1e-7 degrees, ~1.1 cm) to
/// 2^-7 m (~8 mm) with which the frame's extent fits: 2^-10 m up to 2 097 km, 2^-7 m up to
/// 16 777 km (beyond any UTM zone's northings). The origin is a whole number of metres, so a
/// decoded coordinate, origin + x * unit, is a multiple of the unit below 2^42 of it in size:
/// exact as a double. Encoding rounds to the nearest unit; every computation on the decoded
/// doubles is then exact arithmetic on them, as before on the projected ones.
class VertexFrame {
 public:
  static constexpr int kFinestUnitExponent = -10;
  static constexpr int kCoarsestUnitExponent = -7;
  static constexpr std::int32_t kMaxUnits = std::numeric_limits<std::int32_t>::max();

  /// Origin (0, 0), unit 2^-10 m (tests; points from 0 to 2 097 km).
  VertexFrame() = default;
  /// The frame holding every point of the box [min, max] (UTM metres, finite, min <= max,
  /// |min| < 2^31 m); throws std::length_error naming the extent when it is wider than 2^31
  /// units of 2^-7 m (16 777 km), std::invalid_argument when the box is not finite.
  static VertexFrame covering(const PlanePoint& min, const PlanePoint& max) {
    if (!(std::isfinite(min.x) && std::isfinite(min.y) && std::isfinite(max.x) &&
          std::isfinite(max.y) && min.x <= max.x && min.y <= max.y && std::abs(min.x) < 0x1p31 &&
          std::abs(min.y) < 0x1p31)) {
      throw std::invalid_argument("sight: obstacle vertices' box is not a finite box below 2^31 m");
    }
    VertexFrame f;
    f.origin_x_ = std::floor(min.x), f.origin_y_ = std::floor(min.y);
    const double extent_m = std::max(max.x - f.origin_x_, max.y - f.origin_y_);
    for (int e = kFinestUnitExponent; e <= kCoarsestUnitExponent; ++e) {
      // + 1: rounding to the nearest unit may go half a unit past the box.
      if (std::ldexp(extent_m, -e) + 1.0 <= double(kMaxUnits)) {
        f.unit_m_ = std::ldexp(1.0, e);
        return f;
      }
    }
    throw std::length_error(
        "sight: the obstacles' extent of " + std::to_string(std::llround((max.x - min.x) / 1e3)) +
        " km x " + std::to_string(std::llround((max.y - min.y) / 1e3)) +
        " km (the roads' box plus the nodes' reach) is wider than fixed-point vertices allow "
        "(16 777 km: 2^31 units of 2^-7 m)");
  }

  double unit_m() const { return unit_m_; }
  PlanePoint origin() const { return {origin_x_, origin_y_}; }

  /// p to the nearest unit; throws std::out_of_range when it is outside the frame.
  FixedSlot encode(const PlanePoint& p) const {
    const double x = std::nearbyint((p.x - origin_x_) / unit_m_);
    const double y = std::nearbyint((p.y - origin_y_) / unit_m_);
    if (!(x >= 0.0 && x <= double(kMaxUnits) && y >= 0.0 && y <= double(kMaxUnits))) {
      throw std::out_of_range("sight: obstacle vertex (" + std::to_string(p.x) + ", " +
                              std::to_string(p.y) + ") outside its fixed-point frame");
    }
    return {static_cast<std::int32_t>(x), static_cast<std::int32_t>(y)};
  }
  /// encode(q) for every q within error_m (>= 0) of p in x and in y, when they all have that one
  /// answer; false when a coordinate lies within error_m of a half unit (and of the rounding of
  /// the subtraction below: half an ulp of |p| + |origin| each for p and q) or near the frame's
  /// edge. (For a p known only to error_m: sight/obstacles.cpp's interpolated projection.)
  bool encode_certain(const PlanePoint& p, double error_m, FixedSlot& out) const {
    const double x = (p.x - origin_x_) / unit_m_, y = (p.y - origin_y_) / unit_m_;
    const double slack_x = (error_m + (std::abs(p.x) + std::abs(origin_x_)) * 0x1p-52) / unit_m_;
    const double slack_y = (error_m + (std::abs(p.y) + std::abs(origin_y_)) * 0x1p-52) / unit_m_;
    const double rx = std::nearbyint(x), ry = std::nearbyint(y);
    if (!(std::abs(x - rx) < 0.5 - slack_x && std::abs(y - ry) < 0.5 - slack_y)) return false;
    if (!(rx >= 0.0 && rx <= double(kMaxUnits) && ry >= 0.0 && ry <= double(kMaxUnits))) {
      return false;
    }
    out = {static_cast<std::int32_t>(rx), static_cast<std::int32_t>(ry)};
    return true;
  }
  /// The exact double of a vertex slot (x >= 0).
  PlanePoint decode(FixedSlot s) const {
    return {origin_x_ + double(s.x) * unit_m_, origin_y_ + double(s.y) * unit_m_};
  }

 private:
  double origin_x_ = 0.0, origin_y_ = 0.0;
  double unit_m_ = 0x1p-10;
};

/// Allocates like std::allocator but leaves trivial elements uninitialised on resize().
template <typename T>
struct UninitialisedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <typename U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// Obstacle edges stored as runs (polylines) of shared vertices: a building ring of k edges
/// takes k + 2 slots of 8 bytes (a header with its band, then its k + 1 vertices, the first
/// repeated at the end) instead of k edges of 40 bytes (or 16-byte slots of doubles): at country
/// scale the edges are the build's largest table. An edge is named by the slot of its first end
/// (its id, < slots()); its second end is the next slot. A vertex is in fixed point in the store's
/// VertexFrame (within half a millimetre of the projected point) and read back as its exact double:
/// every reader (the grid, the line test, the fan test) gets the same doubles, so the rounding
/// analyses of edge_grid.hpp and fan.hpp (the cells' slack, Fan's proof), which are about the
/// doubles given to them, hold as before.
///
/// A header is a slot whose x is negative (a vertex's never is): x holds the run's bottom_m
/// with its sign bit set (a band's bottom is >= 0 or -0, never NaN; -0 is x = -1, a NaN's
/// pattern), y the bits of its top_m: both floats bit for bit. The band of an edge is found by
/// walking back to its run's header, which is at most kMaxRunEdges slots away (longer runs are
/// cut in two, the cut vertex repeated: the same edges); only an edge that crosses a line in
/// plan needs it.
class ObstacleEdges {
 public:
  static constexpr std::size_t kMaxRunEdges = 64;

  ObstacleEdges() = default;
  /// An empty store with vertices in `frame`.
  explicit ObstacleEdges(const VertexFrame& frame) : frame_(frame) {}
  /// Each edge, in order, continuing the run before it when it starts where that one ends with
  /// the same band (tests, small inputs); the frame covers their ends.
  ObstacleEdges(std::initializer_list<ObstacleEdge> edges) {
    add_edges(edges.begin(), edges.end());
  }
  ObstacleEdges(const std::vector<ObstacleEdge>& edges) { add_edges(edges.begin(), edges.end()); }

  /// Starts a new run with the band [bottom_m, top_m]; its vertices follow with add_vertex().
  void begin_run(float bottom_m, float top_m) {
    slots_.push_back(header(bottom_m, top_m));
    run_header_ = slots_.size() - 1;
  }
  /// The run's next vertex (in the frame): the run's previous vertex to it is an edge.
  void add_vertex(const PlanePoint& p) { add_slot(frame_.encode(p)); }

  using Slots = std::vector<FixedSlot, UninitialisedAllocator<FixedSlot>>;

  /// Takes slots laid out as above, vertices in `frame` (made by a reader that writes its runs
  /// in place, with header() and at most kMaxRunEdges edges a run); throws std::logic_error
  /// when they are not.
  static ObstacleEdges adopt(Slots slots, const VertexFrame& frame) {
    ObstacleEdges out(frame);
    out.slots_ = std::move(slots);
    std::size_t edges = 0;
    for (std::size_t i = 0; i < out.slots_.size(); ++i) {
      const bool header = is_header(out.slots_[i]);
      if (i == 0 && !header) throw std::logic_error("obstacle edges: no header first");
      if (header)
        out.run_header_ = i, edges = 0;
      else if (i > out.run_header_ + 1 && ++edges > kMaxRunEdges)
        throw std::logic_error("obstacle edges: a run longer than kMaxRunEdges");
    }
    return out;
  }
  /// A run's header slot for the band [bottom_m, top_m] (bottom_m >= 0 or -0; else throws
  /// std::invalid_argument).
  static FixedSlot header(float bottom_m, float top_m) {
    if (!(bottom_m >= 0.0f)) throw std::invalid_argument("obstacle band: bottom_m below 0 or NaN");
    const std::uint32_t bits = std::signbit(bottom_m)
                                   ? 0xFFFFFFFFu  // -0
                                   : std::bit_cast<std::uint32_t>(bottom_m) | 0x80000000u;
    return {std::bit_cast<std::int32_t>(bits), std::bit_cast<std::int32_t>(top_m)};
  }
  static bool is_header(FixedSlot s) { return s.x < 0; }
  /// Slots taken by a chain of `edges` edges (> 0) once cut into runs.
  static std::size_t slots_for_chain(std::size_t edges) {
    return edges + 2 + 2 * ((edges - 1) / kMaxRunEdges);
  }
  /// Writes a chain of vertex slots [first, last] (> 1 of them) with the band [bottom_m,
  /// top_m] as runs at `out` (not overlapping them); returns the end.
  static FixedSlot* write_chain(FixedSlot* out, float bottom_m, float top_m, const FixedSlot* first,
                                const FixedSlot* last) {
    const FixedSlot band = header(bottom_m, top_m);
    for (const FixedSlot* v = first; v < last;) {
      const std::size_t n = std::min<std::size_t>(kMaxRunEdges, static_cast<std::size_t>(last - v));
      *out++ = band;
      for (std::size_t k = 0; k <= n; ++k) *out++ = v[k];  // the run's n + 1 vertices
      v += n;
    }
    return out;
  }

  const VertexFrame& frame() const { return frame_; }
  /// Slot i as stored (tests).
  FixedSlot slot(std::size_t i) const { return slots_[i]; }
  /// Edge ids are below this.
  std::size_t slots() const { return slots_.size(); }
  /// Whether id i names an edge (slot i and the next one are vertices).
  bool is_edge(std::size_t i) const {
    return i + 1 < slots_.size() && !is_header(slots_[i]) && !is_header(slots_[i + 1]);
  }
  std::size_t edges() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 1 < slots_.size(); ++i) n += is_edge(i) ? 1 : 0;
    return n;
  }

  PlanePoint a(std::uint32_t i) const { return frame_.decode(slots_[i]); }
  PlanePoint b(std::uint32_t i) const { return frame_.decode(slots_[std::size_t{i} + 1]); }
  float bottom_m(std::uint32_t i) const { return band_of(run_header_of(i)).first; }
  float top_m(std::uint32_t i) const { return band_of(run_header_of(i)).second; }
  ObstacleEdge operator[](std::uint32_t i) const {
    const auto [bottom, top] = band_of(run_header_of(i));
    return {a(i), b(i), bottom, top};
  }

 private:
  struct Band {
    float first, second;
  };
  std::size_t run_header_of(std::uint32_t i) const {
    std::size_t at = i;
    while (!is_header(slots_[at])) --at;  // slot 0 is a header
    return at;
  }
  Band band_of(std::size_t header_slot) const {
    const auto x = std::bit_cast<std::uint32_t>(slots_[header_slot].x);
    return {x == 0xFFFFFFFFu ? -0.0f : std::bit_cast<float>(x & 0x7FFFFFFFu),
            std::bit_cast<float>(slots_[header_slot].y)};
  }
  void add_slot(FixedSlot s) {
    if (slots_.size() - run_header_ > kMaxRunEdges + 1) {  // kMaxRunEdges edges already
      const FixedSlot last = slots_.back();
      const FixedSlot band = slots_[run_header_];
      slots_.push_back(band);
      run_header_ = slots_.size() - 1;
      slots_.push_back(last);
    }
    slots_.push_back(s);
  }
  template <typename It>
  void add_edges(It begin, It end) {
    if (begin == end) return;
    PlanePoint min{begin->a}, max{begin->a};
    for (It e = begin; e != end; ++e) {
      for (const PlanePoint& p : {e->a, e->b}) {
        min = {std::min(min.x, p.x), std::min(min.y, p.y)};
        max = {std::max(max.x, p.x), std::max(max.y, p.y)};
      }
    }
    frame_ = VertexFrame::covering(min, max);
    for (It e = begin; e != end; ++e) {
      const FixedSlot a = frame_.encode(e->a), b = frame_.encode(e->b);
      const FixedSlot band = header(e->bottom_m, e->top_m);
      const bool continues = !slots_.empty() && !is_header(slots_.back()) &&
                             slots_.back().x == a.x && slots_.back().y == a.y &&
                             slots_[run_header_].x == band.x && slots_[run_header_].y == band.y;
      if (!continues) {
        begin_run(e->bottom_m, e->top_m);
        add_slot(a);
      }
      add_slot(b);
    }
  }

  VertexFrame frame_;
  Slots slots_;
  std::size_t run_header_ = 0;
};

}  // namespace roadcross::preprocess
