// read_obstacle_tags: one walk over a way's tag list gives what osmium's TagList::operator[]
// gives for each of the keys.
#include <gtest/gtest.h>

#include <cstring>
#include <osmium/builder/attr.hpp>
#include <osmium/memory/buffer.hpp>
#include <osmium/osm/way.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/preprocess/sight/sight.hpp"

namespace rp = roadcross::preprocess;

namespace {

/// The same pointer (the value inside the tag list), or both absent.
void expect_same(const char* got, const char* want, const char* key) {
  EXPECT_EQ(got, want) << key << ": got " << (got ? got : "(none)") << ", want "
                       << (want ? want : "(none)");
}

void expect_like_operator_brackets(const std::vector<std::pair<std::string, std::string>>& tags) {
  osmium::memory::Buffer buffer(1024, osmium::memory::Buffer::auto_grow::yes);
  {
    using namespace osmium::builder::attr;  // NOLINT(google-build-using-namespace)
    osmium::builder::add_way(buffer, _id(1), _tags(tags));
  }
  const osmium::TagList& list = buffer.get<osmium::Way>(0).tags();
  const rp::ObstacleTags got = rp::read_obstacle_tags(list);
  expect_same(got.building, list["building"], "building");
  expect_same(got.barrier, list["barrier"], "barrier");
  expect_same(got.height, list["height"], "height");
  expect_same(got.building_levels, list["building:levels"], "building:levels");
  expect_same(got.min_height, list["min_height"], "min_height");
  expect_same(got.building_min_level, list["building:min_level"], "building:min_level");
}

}  // namespace

TEST(ObstacleTags, EachKeyAsTheTagListFindsIt) {
  expect_like_operator_brackets({});
  expect_like_operator_brackets({{"highway", "residential"}, {"name", "Rue Grimaldi"}});
  expect_like_operator_brackets({{"building", "yes"},
                                 {"height", "12 m"},
                                 {"building:levels", "4"},
                                 {"min_height", "3"},
                                 {"building:min_level", "1"},
                                 {"barrier", "wall"}});
  // Keys that only begin like the wanted ones, or differ by case, are not them.
  expect_like_operator_brackets({{"buildings", "x"},
                                 {"building:levels:underground", "2"},
                                 {"heights", "3"},
                                 {"Height", "4"},
                                 {"min_height:note", "5"},
                                 {"b", "6"},
                                 {"barriers", "fence"},
                                 {"building:min_levels", "7"}});
}

TEST(ObstacleTags, RandomListsWithRepeatedKeysGiveTheFirstValue) {
  // A key twice is invalid OSM but can be read from a file: operator[] gives the first.
  const std::vector<std::string> keys = {
      "building",   "barrier", "height",    "building:levels", "min_height", "building:min_level",
      "highway",    "name",    "building:", "heigh",           "m",          "",
      "roof:height"};
  std::mt19937 random(27);
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::pair<std::string, std::string>> tags;
    const int n = static_cast<int>(random() % 9);
    for (int i = 0; i < n; ++i) {
      tags.emplace_back(keys[random() % keys.size()],
                        std::to_string(round) + "." + std::to_string(i));
    }
    expect_like_operator_brackets(tags);
  }
}
