// XYZ points binned by tile with a memory budget: a split that spills to the temporary file
// gives every tile exactly the points (and order) that filtering all of them at once gives,
// leaves no file behind, and reading an XYZ file in chunks gives what reading it whole does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"
#include "roadcross/preprocess/terrain/xyz_tiles.hpp"

namespace rp = roadcross::preprocess;
using roadcross::testing::TempDir;

namespace {

std::vector<rp::ElevationPoint> random_points(std::size_t n) {
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> e(0.0, 3000.0), n_(0.0, 2000.0), z(200.0, 400.0);
  std::vector<rp::ElevationPoint> points(n);
  for (rp::ElevationPoint& p : points) p = {e(random), n_(random), z(random)};
  points[17].x = NAN;  // a point the CRS transformation could not map
  return points;
}

/// 3 x 2 tiles of 1000 m, each grown by 150 m (so they overlap by 300 m); tile 4 is unused.
std::vector<rp::UtmBox> overlapping_tiles() {
  std::vector<rp::UtmBox> boxes;
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 3; ++col) {
      boxes.push_back({col * 1000.0 - 150.0, row * 1000.0 - 150.0, col * 1000.0 + 1150.0,
                       row * 1000.0 + 1150.0});
    }
  }
  boxes[4] = {1.0, 1.0, 0.0, 0.0};  // empty: no roads there
  return boxes;
}

bool same(const std::vector<rp::ElevationPoint>& a, const std::vector<rp::ElevationPoint>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
  }
  return true;
}

std::size_t files_in(const std::string& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace

TEST(XyzTileBins, SplitWithASmallBudgetGivesEachTileItsPointsInOrder) {
  const std::vector<rp::ElevationPoint> points = random_points(20000);
  const std::vector<rp::UtmBox> boxes = overlapping_tiles();
  TempDir dir;
  // 10 000 points' worth of memory (the bins hold ~30 000 with the overlaps): several spills.
  rp::XyzTileBins bins(boxes, 10000 * sizeof(rp::ElevationPoint), dir.path());
  for (std::size_t start = 0; start < points.size(); start += 3000) {
    bins.add(std::vector<rp::ElevationPoint>(
        points.begin() + long(start),
        points.begin() + long(std::min(points.size(), start + 3000))));
  }
  EXPECT_GE(bins.spills(), 2u);
  EXPECT_GT(bins.spilled_points(), 10000u);
  EXPECT_EQ(files_in(dir.path()), 0u);  // the spill file has no name
  std::size_t binned = 0;
  for (std::size_t t = 0; t < boxes.size(); ++t) {
    std::vector<rp::ElevationPoint> expected;  // filtering all points, as without a split
    for (const rp::ElevationPoint& p : points) {
      if (p.x >= boxes[t].min_e && p.x <= boxes[t].max_e && p.y >= boxes[t].min_n &&
          p.y <= boxes[t].max_n) {
        expected.push_back(p);
      }
    }
    const std::vector<rp::ElevationPoint> got = bins.take(t);
    EXPECT_TRUE(same(got, expected))
        << "tile " << t << ": " << got.size() << " vs " << expected.size();
    if (t == 4) {
      EXPECT_TRUE(got.empty());
    } else {
      EXPECT_GT(got.size(), 2000u);
    }
    binned += got.size();
  }
  // The overlaps: a point near a border is in two or four tiles.
  EXPECT_GT(binned, points.size() - points.size() / 6);
  EXPECT_TRUE(bins.take(0).empty());  // taken once
}

TEST(XyzTileBins, WithoutSpillingNothingIsWritten) {
  const std::vector<rp::ElevationPoint> points = random_points(5000);
  TempDir dir;
  rp::XyzTileBins bins(overlapping_tiles(), 1 << 30, dir.path());
  bins.add(points);
  EXPECT_EQ(bins.spills(), 0u);
  EXPECT_EQ(bins.spilled_points(), 0u);
  EXPECT_FALSE(bins.take(0).empty());
}

TEST(Xyz, ChunkedReadingGivesTheWholeFile) {
  TempDir dir;
  std::ofstream out(dir.file("p.xyz"));
  out << "X Y Z\n";
  for (int i = 0; i < 1000; ++i) out << i << " " << 2 * i << " " << 300 + i % 7 << "\n";
  out.close();
  const std::vector<rp::ElevationPoint> whole = rp::read_xyz(dir.file("p.xyz"));
  std::vector<rp::ElevationPoint> chunked;
  std::vector<std::size_t> sizes;
  rp::read_xyz_chunks(dir.file("p.xyz"), 300, [&](std::vector<rp::ElevationPoint>& chunk) {
    sizes.push_back(chunk.size());
    chunked.insert(chunked.end(), chunk.begin(), chunk.end());
  });
  EXPECT_EQ(sizes, (std::vector<std::size_t>{300, 300, 300, 100}));
  ASSERT_EQ(whole.size(), 1000u);
  EXPECT_TRUE(same(whole, chunked));
  EXPECT_EQ(chunked[999].y, 1998.0);
}
