// What blocks a line of sight (issue 11): the edges of obstacles' footprints. Its own header,
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
#include <type_traits>
#include <utility>
#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

/// One edge of an obstacle's footprint (a building outline or a wall line), UTM metres, with
/// the opaque band above the local ground: from bottom_m (0, or min_height for a building on
/// pillars or over a passage) to top_m (metres above the ground, bottom_m <= top_m).
struct ObstacleEdge {
  PlanePoint a, b;
  float bottom_m = 0.0f, top_m = 0.0f;
};

/// A point without default member initialisers, so that an array of them can be allocated
/// without touching its pages (they cost no memory until written).
struct RawPoint {
  double x, y;
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
/// takes k + 2 slots of 16 bytes (a header with its band, then its k + 1 vertices, the first
/// repeated at the end) instead of k edges of 40 bytes (issue 8: 1.3 GB of edges at 200x
/// Monaco). An edge is named by the slot of its first end (its id, < slots()); its second end
/// is the next slot. The vertices are the same doubles as the edges they replace, so every
/// computation on them is unchanged.
///
/// A header is a slot whose x is NaN (a vertex never is) and whose y holds the run's two band
/// floats bit for bit. The band of an edge is found by walking back to its run's header, which
/// is at most kMaxRunEdges slots away (longer runs are cut in two, the cut vertex repeated: the
/// same edges); only an edge that crosses a line in plan needs it.
class ObstacleEdges {
 public:
  static constexpr std::size_t kMaxRunEdges = 64;

  ObstacleEdges() = default;
  /// Each edge, in order, continuing the run before it when it starts where that one ends with
  /// the same band (tests, small inputs).
  ObstacleEdges(std::initializer_list<ObstacleEdge> edges) {
    add_edges(edges.begin(), edges.end());
  }
  ObstacleEdges(const std::vector<ObstacleEdge>& edges) { add_edges(edges.begin(), edges.end()); }

  /// Starts a new run with the band [bottom_m, top_m]; its vertices follow with add_vertex().
  void begin_run(float bottom_m, float top_m) {
    slots_.push_back(header(bottom_m, top_m));
    run_header_ = slots_.size() - 1;
  }
  /// The run's next vertex (not NaN): the run's previous vertex to it is an edge.
  void add_vertex(const PlanePoint& p) {
    if (slots_.size() - run_header_ > kMaxRunEdges + 1) {  // kMaxRunEdges edges already
      const RawPoint last = slots_.back();
      const RawPoint band = slots_[run_header_];
      slots_.push_back(band);
      run_header_ = slots_.size() - 1;
      slots_.push_back(last);
    }
    slots_.push_back({p.x, p.y});
  }

  using Slots = std::vector<RawPoint, UninitialisedAllocator<RawPoint>>;

  /// Takes slots laid out as above (made by a reader that writes its runs in place, with
  /// header() and at most kMaxRunEdges edges a run); throws std::logic_error when they are not.
  static ObstacleEdges adopt(Slots slots) {
    ObstacleEdges out;
    out.slots_ = std::move(slots);
    std::size_t edges = 0;
    for (std::size_t i = 0; i < out.slots_.size(); ++i) {
      const bool is_header = std::isnan(out.slots_[i].x);
      if (i == 0 && !is_header) throw std::logic_error("obstacle edges: no header first");
      if (is_header)
        out.run_header_ = i, edges = 0;
      else if (i > out.run_header_ + 1 && ++edges > kMaxRunEdges)
        throw std::logic_error("obstacle edges: a run longer than kMaxRunEdges");
    }
    return out;
  }
  /// A run's header slot.
  static RawPoint header(float bottom_m, float top_m) {
    const std::uint64_t bits = std::uint64_t{std::bit_cast<std::uint32_t>(bottom_m)} |
                               (std::uint64_t{std::bit_cast<std::uint32_t>(top_m)} << 32);
    return {std::numeric_limits<double>::quiet_NaN(), std::bit_cast<double>(bits)};
  }
  /// Slots taken by a chain of `edges` edges (> 0) once cut into runs.
  static std::size_t slots_for_chain(std::size_t edges) {
    return edges + 2 + 2 * ((edges - 1) / kMaxRunEdges);
  }
  /// Writes a chain of vertices [first, last] (> 1 of them, none NaN) with the band
  /// [bottom_m, top_m] as runs at `out` (not overlapping them); returns the end.
  static RawPoint* write_chain(RawPoint* out, float bottom_m, float top_m, const RawPoint* first,
                               const RawPoint* last) {
    const RawPoint band = header(bottom_m, top_m);
    for (const RawPoint* v = first; v < last;) {
      const std::size_t n = std::min<std::size_t>(kMaxRunEdges, static_cast<std::size_t>(last - v));
      *out++ = band;
      for (std::size_t k = 0; k <= n; ++k) *out++ = v[k];  // the run's n + 1 vertices
      v += n;
    }
    return out;
  }

  /// Edge ids are below this.
  std::size_t slots() const { return slots_.size(); }
  /// Whether id i names an edge (slot i and the next one are vertices).
  bool is_edge(std::size_t i) const {
    return i + 1 < slots_.size() && !std::isnan(slots_[i].x) && !std::isnan(slots_[i + 1].x);
  }
  std::size_t edges() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 1 < slots_.size(); ++i) n += is_edge(i) ? 1 : 0;
    return n;
  }

  PlanePoint a(std::uint32_t i) const { return {slots_[i].x, slots_[i].y}; }
  PlanePoint b(std::uint32_t i) const {
    const RawPoint& q = slots_[std::size_t{i} + 1];
    return {q.x, q.y};
  }
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
    while (!std::isnan(slots_[at].x)) --at;  // slot 0 is a header
    return at;
  }
  Band band_of(std::size_t header_slot) const {
    const auto bits = std::bit_cast<std::uint64_t>(slots_[header_slot].y);
    return {std::bit_cast<float>(static_cast<std::uint32_t>(bits)),
            std::bit_cast<float>(static_cast<std::uint32_t>(bits >> 32))};
  }
  template <typename It>
  void add_edges(It begin, It end) {
    for (It e = begin; e != end; ++e) {
      const bool continues = !slots_.empty() && !std::isnan(slots_.back().x) &&
                             slots_.back().x == e->a.x && slots_.back().y == e->a.y &&
                             slots_[run_header_].y == header(e->bottom_m, e->top_m).y;
      if (!continues) {
        begin_run(e->bottom_m, e->top_m);
        add_vertex(e->a);
      }
      add_vertex(e->b);
    }
  }

  Slots slots_;
  std::size_t run_header_ = 0;
};

}  // namespace roadcross::preprocess
