#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"

namespace roadcross::cli {

SimulateCommand::SimulateCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "simulate",
      "simulate traffic and a robot crossing with each policy; metrics per volume and policy.\n"
      "The road comes from a DB place (--db with --utm or --lat/--lon) or is synthetic.");
  app_->add_option("--db", db_path_, "roadcross GeoPackage: take the road at the position");
  auto* utm = app_->add_option("--utm", utm_, "UTM easting and northing of the place, metres")
                  ->expected(2)
                  ->type_name("E N");
  auto* lat = app_->add_option("--lat", lat_deg_, "WGS84 latitude of the place, degrees");
  auto* lon = app_->add_option("--lon", lon_deg_, "WGS84 longitude of the place, degrees");
  lat->needs(lon);
  lon->needs(lat);
  utm->excludes(lat)->excludes(lon);
  app_->add_option("--lanes", lanes_, "lanes (default: the DB's, else 2)");
  app_->add_option("--width", width_m_, "carriageway width, m (default: the DB's, else 7)");
  app_->add_option("--maxspeed", maxspeed_kmh_, "speed limit, km/h (default: the DB's, else 50)");
  app_->add_option("--sight", sight_m_,
                   "road visible each way, m (default: sensor range, cut by bend and junction)");
  app_->add_option("--sensor-range", sensor_range_m_, "sensor range, m")->capture_default_str();
  app_->add_flag("--island", island_,
                 "a refuge island: cross in two stages, near lanes then far lanes (default: the "
                 "DB's crossing_island at the place, else none)");
  app_->add_option("--policy", policies_, "policies: ours, hcm, naive (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"ours", "hcm", "naive"}))
      ->capture_default_str();
  app_->add_option("--volume", volumes_, "vehicles per hour per lane (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app_->add_option("--naive-distance", naive_distances_m_,
                   "naive policy: GO when the nearest vehicle is farther, m (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app_->add_option("--runs", runs_, "runs per volume and policy")->capture_default_str();
  app_->add_option("--seed", seed_, "random seed (same seed, same numbers)")->capture_default_str();
  app_->add_option("--speed", scenario_.robot.speed_mps, "robot crossing speed, m/s")
      ->capture_default_str();
  app_->add_option("--startup", scenario_.robot.startup_s, "robot start-up time, s")
      ->capture_default_str();
  app_->add_option("--max-wait", scenario_.max_wait_s, "robot gives up after, s")
      ->capture_default_str();
  app_->add_option("--conflict-pet", scenario_.conflict_pet_s, "conflict when PET below, s")
      ->capture_default_str();
  app_->add_option("--min-pet", scenario_.gap.min_pet_s, "ours: required PET margin, s")
      ->capture_default_str();
  app_->add_option("--speed-uncertainty", scenario_.gap.speed_uncertainty_fraction,
                   "ours: vehicle speeds known to +- this fraction")
      ->capture_default_str();
  app_->add_option("--label", label_, "name of the place in the output");
  app_->add_flag("--json", json_, "print JSON instead of a table");
  app_->add_flag("--per-run", per_run_,
                 "print every run's metrics, one JSON object per line, instead of the summary");
}

namespace {

struct Row {
  std::string policy;
  double volume = 0.0;
  sim::Aggregate a;
};

nlohmann::ordered_json row_json(const Row& r) {
  nlohmann::ordered_json out;
  out["policy"] = r.policy;
  out["volume_veh_h_per_lane"] = r.volume;
  out["runs"] = r.a.runs;
  out["crossed"] = r.a.crossed;
  out["collisions"] = r.a.collisions;
  out["conflicts"] = r.a.conflicts;
  out["mean_wait_s"] = r.a.mean_wait_s;
  out["p95_wait_s"] = r.a.p95_wait_s;
  out["mean_crossing_s"] = r.a.mean_crossing_s;
  out["acceptable_gap_share"] = r.a.acceptable_gap_share;
  out["min_pet_s"] = or_null(r.a.min_pet_s);
  return out;
}

/// One JSON line per run, with the same seeds as the summary uses.
bool print_runs(const sim::Scenario& s, const std::string& policy, double volume, int runs,
                std::uint64_t seed) {
  for (int i = 0; i < runs; ++i) {
    const Result<sim::RunMetrics> r = sim::simulate_run(s, sim::run_seed(seed, i));
    if (!r.ok()) {
      report_error(r.status);
      return false;
    }
    nlohmann::ordered_json out;
    out["policy"] = policy;
    out["volume_veh_h_per_lane"] = volume;
    out["run"] = i;
    out["crossed"] = r->crossed;
    out["collision"] = r->collision;
    out["conflict"] = r->conflict;
    out["min_pet_s"] = or_null(r->min_pet_s);
    out["waiting_s"] = r->waiting_s;
    out["island_wait_s"] = r->island_wait_s;
    out["crossing_s"] = r->crossing_s;
    out["acceptable_gaps_offered"] = r->acceptable_gaps_offered;
    out["used_acceptable_gap"] = r->used_acceptable_gap;
    std::cout << json_text(out) << "\n";
  }
  return true;
}

}  // namespace

int SimulateCommand::run() {
  if (runs_ < 1 || runs_ > sim::kMaxRuns) {
    std::cerr << "roadcross simulate: --runs is " << runs_ << ", must be in [1, " << sim::kMaxRuns
              << "]\n";
    return 2;
  }
  sim::Road road;
  road.sight_m = sensor_range_m_;
  std::string place = label_.empty() ? "synthetic" : label_;
  if (!db_path_.empty()) {
    if (utm_.empty() && !lat_deg_) {
      print_error("roadcross simulate", "--db needs a place: --utm E N or --lat/--lon", "usage");
      return kUsageExitStatus;
    }
    std::optional<Map> map = open_map_or_report(db_path_);
    if (!map) return 1;
    const Position position =
        utm_.empty() ? Position::wgs84(*lat_deg_, *lon_deg_) : Position::utm(utm_[0], utm_[1]);
    const Result<GapCrossing> crossing = gap_crossing(*map, position);
    const Result<Assessment> assessment = map->assess(position);
    if (!crossing.ok() || !assessment.ok()) {
      return report_error(crossing.ok() ? assessment.status : crossing.status);
    }
    road.lanes = crossing->lanes;
    road.width_m = crossing->road_width_m;
    road.maxspeed_kmh = crossing->maxspeed_kmh;
    road.sight_m = sight_distance_m(*assessment, sensor_range_m_);
    road.junction_distance_m = crossing->junction_distance_m;
    road.refuge_island = crossing->refuge_island;
    if (label_.empty()) place = assessment->road.name.empty() ? "db" : assessment->road.name;
  }
  if (lanes_) road.lanes = *lanes_;
  if (width_m_) road.width_m = *width_m_;
  if (maxspeed_kmh_) road.maxspeed_kmh = *maxspeed_kmh_;
  if (sight_m_) road.sight_m = *sight_m_;
  if (island_) road.refuge_island = true;
  scenario_.road = road;

  std::vector<Row> rows;
  for (double volume : volumes_) {
    for (const std::string& name : policies_) {
      sim::Scenario s = scenario_;
      s.volume_veh_h_per_lane = volume;
      sim::parse_policy(name, s.policy);
      const std::vector<double> distances =
          s.policy == sim::Policy::naive ? naive_distances_m_ : std::vector<double>{0.0};
      for (double distance : distances) {
        if (s.policy == sim::Policy::naive) s.naive_distance_m = distance;
        const std::string label =
            s.policy == sim::Policy::naive
                ? "naive" + std::to_string(static_cast<int>(std::lround(distance)))
                : name;
        if (per_run_) {
          if (!print_runs(s, label, volume, runs_, seed_)) return 1;
          continue;
        }
        const Result<sim::Aggregate> a = sim::simulate(s, runs_, seed_);
        if (!a.ok()) {
          return report_error(a.status);
        }
        rows.push_back({label, volume, *a});
      }
    }
  }
  if (per_run_) return 0;
  if (json_) {
    nlohmann::ordered_json out;
    out["place"] = place;
    out["road"] = {{"lanes", road.lanes},
                   {"width_m", road.width_m},
                   {"maxspeed_kmh", road.maxspeed_kmh},
                   {"sight_m", road.sight_m},
                   {"junction_distance_m", or_null(road.junction_distance_m)},
                   {"refuge_island", road.refuge_island}};
    out["robot"] = {{"speed_mps", scenario_.robot.speed_mps},
                    {"startup_s", scenario_.robot.startup_s}};
    out["runs"] = runs_;
    out["seed"] = seed_;
    out["rows"] = nlohmann::ordered_json::array();
    for (const Row& r : rows) out["rows"].push_back(row_json(r));
    std::cout << json_text(out, 2) << "\n";
    return 0;
  }
  std::printf(
      "place %s: %d lane(s), %.1f m, %.0f km/h, sight %.0f m, junction %s m; %d runs each, seed "
      "%llu\n",
      place.c_str(), road.lanes, road.width_m, road.maxspeed_kmh, road.sight_m,
      road.junction_distance_m ? std::to_string(std::lround(*road.junction_distance_m)).c_str()
                               : "-",
      runs_, static_cast<unsigned long long>(seed_));
  if (road.refuge_island && road.lanes >= 2) {
    std::printf(
        "refuge island: two stages (%d near lane(s), then %d far), waits include the "
        "island's\n",
        road.lanes / 2, road.lanes - road.lanes / 2);
  }
  std::printf("%-9s %7s %8s %10s %9s %10s %9s %9s %8s %8s\n", "policy", "veh/h/l", "crossed",
              "collisions", "conflicts", "mean wait", "p95 wait", "crossing", "gaps", "min PET");
  for (const Row& r : rows) {
    const sim::Aggregate& a = r.a;
    char pet[16] = "-";
    if (a.min_pet_s) std::snprintf(pet, sizeof pet, "%.1fs", *a.min_pet_s);
    std::printf("%-9s %7.0f %8d %10d %9d %9.1fs %8.1fs %8.1fs %7.0f%% %8s\n", r.policy.c_str(),
                r.volume, a.crossed, a.collisions, a.conflicts, a.mean_wait_s, a.p95_wait_s,
                a.mean_crossing_s, 100.0 * a.acceptable_gap_share, pet);
  }
  return 0;
}

}  // namespace roadcross::cli
