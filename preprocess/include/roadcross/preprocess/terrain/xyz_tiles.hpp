// XYZ point files larger than memory: the points are split by area into the terrain tiles that
// need them (each tile's grid grown by the TIN's longest edge, so neighbouring tiles overlap and
// a point near a border goes to both), held in memory up to a budget and spilled past it to a
// temporary file, so that each tile is triangulated from its own points only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace roadcross::preprocess {

/// An axis-aligned box in UTM metres, bounds included.
struct UtmBox {
  double min_e = 0.0, min_n = 0.0, max_e = 0.0, max_n = 0.0;
  bool contains(double e, double n) const {
    return e >= min_e && e <= max_e && n >= min_n && n <= max_n;
  }
};

/// Points binned by tile. Each tile's points keep the order in which they were added (file
/// order), spilled or not, so a split gives each tile exactly the points, in the same order, that
/// filtering all points held at once would.
///
/// The spill file is created in `spill_dir` and unlinked at once (O_TMPFILE where the file
/// system has it): it has no name, and the kernel frees it when the build ends however it ends
/// (success, error, Ctrl-C, kill -9).
class XyzTileBins {
 public:
  /// `boxes`: each tile's box (an empty vector of boxes for none); `memory_budget_bytes`: the
  /// points held in memory before spilling (24 bytes a point); `spill_dir`: where the spill
  /// file goes (empty: the system's temporary directory).
  XyzTileBins(std::vector<UtmBox> boxes, std::size_t memory_budget_bytes, std::string spill_dir);
  ~XyzTileBins();
  XyzTileBins(const XyzTileBins&) = delete;
  XyzTileBins& operator=(const XyzTileBins&) = delete;

  /// Adds the points (UTM; NaN x ones are skipped) to every tile whose box holds them; spills
  /// when over the budget. Throws OutputError when the spill file cannot be written.
  void add(const std::vector<ElevationPoint>& points_utm);
  /// The tile's points, spilled ones first (they came first), then the ones in memory; the bin
  /// is emptied.
  std::vector<ElevationPoint> take(std::size_t tile);

  std::size_t spilled_points() const { return spilled_points_; }
  std::size_t spills() const { return spills_; }

 private:
  struct Chunk {
    long long offset;
    std::size_t count;
  };
  void spill();
  void open_spill_file();

  std::vector<UtmBox> boxes_;
  // A uniform grid of buckets over the boxes, each listing the boxes that overlap it, so that
  // a point is tested against a few boxes, not all.
  UtmBox bounds_;
  double bucket_m_ = 1.0;
  std::size_t bucket_cols_ = 0, bucket_rows_ = 0;
  std::vector<std::vector<std::size_t>> buckets_;
  std::size_t budget_points_;
  std::string spill_dir_;
  std::vector<std::vector<ElevationPoint>> memory_;
  std::vector<std::vector<Chunk>> chunks_;
  std::size_t in_memory_ = 0, spilled_points_ = 0, spills_ = 0;
  long long file_end_ = 0;
  int fd_ = -1;
};

}  // namespace roadcross::preprocess
