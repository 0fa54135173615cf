// `roadcross gap --vehicles` lines on arbitrary bytes: a vehicle or an exception with a message
// (std::exception, caught by the command), and a decision (or an error status) for every
// vehicle accepted, in bounded time, never a crash.
#include <nlohmann/json.hpp>
#include <vector>

#include "fuzz_support.hpp"
#include "request_lines.hpp"
#include "roadcross/gap.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  roadcross::TrackedVehicle vehicle;
  try {
    vehicle = roadcross::cli::parse_vehicle(
        nlohmann::json::parse(roadcross::fuzz::as_text(data, size)), 0.0);
  } catch (const std::exception&) {
    return 0;  // the command reports the line and its message
  }
  roadcross::GapCrossing crossing;
  crossing.start = {0.0, -4.0};
  crossing.centre = {0.0, 0.0};
  crossing.heading_rad = 1.5707963267948966;
  const std::vector<roadcross::TrackedVehicle> vehicles{vehicle};
  (void)roadcross::gap_decision(crossing, roadcross::RobotMotion{}, vehicles, 0.0);
  (void)roadcross::hcm_gap_decision(crossing, roadcross::RobotMotion{}, vehicles, 0.0);
  return 0;
}
