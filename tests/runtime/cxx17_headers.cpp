// Build check, not a test program: the runtime's public headers compile as C++17, because ROS1
// code must (its message headers use std::allocator<void>::rebind, which C++20 removed).
// tests/CMakeLists.txt builds this file with CXX_STANDARD 17 in every configuration.
#include "roadcross/gap.hpp"
#include "roadcross/geo.hpp"
#include "roadcross/monitor.hpp"
#include "roadcross/runtime.hpp"

#if __cplusplus >= 202002L
#error "this file must be compiled as C++17"
#endif

namespace {

[[maybe_unused]] bool c17_callers_compile(roadcross::Map& map) {
  const auto crossing = roadcross::gap_crossing(map, roadcross::Position::wgs84(50.0, 14.4));
  if (!crossing.ok()) return false;
  const roadcross::TrackedVehicle vehicles[1]{};
  const auto ours = roadcross::gap_decision(*crossing, {}, vehicles, 1, 0.0);
  const auto hcm = roadcross::hcm_gap_decision(*crossing, {}, nullptr, 0, 0.0);
  return ours.ok() && hcm.ok() && map.info().zone == roadcross::geo::UtmZone{33, true};
}

}  // namespace
#include "roadcross/map_set.hpp"
