// Opens a roadcross DB with the installed runtime and prints the crossing heading at a UTM
// position: "segment <id> crossing_heading_rad <yaw>".
#include <roadcross/runtime.hpp>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer DB EASTING NORTHING\n");
    return 2;
  }
  auto map = roadcross::Map::open(argv[1]);
  if (!map.ok()) {
    std::fprintf(stderr, "%s\n", map.status.message.c_str());
    return 1;
  }
  const auto heading = map->road_heading(
      roadcross::Position::utm(std::strtod(argv[2], nullptr), std::strtod(argv[3], nullptr)));
  if (!heading.ok()) {
    std::fprintf(stderr, "%s\n", heading.status.message.c_str());
    return 1;
  }
  std::printf("segment %lld crossing_heading_rad %.6f\n",
              static_cast<long long>(heading->road.segment_id), heading->crossing_heading_rad);
  return 0;
}
