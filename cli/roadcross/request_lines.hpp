// The line formats of `roadcross batch` (one JSON request per line) and `roadcross gap
// --vehicles` (one JSON vehicle per line), as functions: the fuzz targets (tests/fuzz) feed them
// arbitrary bytes.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "roadcross/gap.hpp"
#include "roadcross/runtime.hpp"

namespace roadcross::cli {

/// The answer to one request line of `roadcross batch` (numbered `number` from 1), as one line
/// of JSON without the newline: {"line": N, "ok": true, "result": ...} or {"line": N, "ok":
/// false, "error": ...}. Never throws for a bad line; sets `failed` when ok is false.
std::string batch_answer(Map& map, const std::string& line, long number, bool& failed);

/// One vehicle from a JSON object: UTM ("easting", "northing") or robot ENU ("east_m",
/// "north_m"), velocity "vx_mps", "vy_mps", optional "length_m", "age_s",
/// "speed_uncertainty_mps". Throws with a message for the user.
TrackedVehicle parse_vehicle(const nlohmann::json& j, double now_s);

}  // namespace roadcross::cli
