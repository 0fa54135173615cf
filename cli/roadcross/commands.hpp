// One class per subcommand of `roadcross`, each owning its options (osmium-tool style).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "cli_conventions.hpp"
#include "position_options.hpp"
#include "roadcross/gap.hpp"
#include "roadcross/simulate.hpp"

namespace roadcross::cli {

class Command {
 public:
  virtual ~Command() = default;
  /// Runs after parsing; returns the process exit code.
  virtual int run() = 0;
  CLI::App* app() const noexcept { return app_; }

 protected:
  CLI::App* app_ = nullptr;
};

/// roadcross info --db DB: zone, counts, extent, parameters and inputs.
class InfoCommand : public Command {
 public:
  explicit InfoCommand(CLI::App& parent);
  int run() override;

 private:
  std::string db_path_;
  std::string positional_path_;
  bool json_ = false;
};

/// roadcross verify --db MAP [--expect-id ID]: is the file whole and the map ID names?
class VerifyCommand : public Command {
 public:
  explicit VerifyCommand(CLI::App& parent);
  int run() override;

 private:
  std::string db_path_;
  std::string expected_id_;
  bool json_ = false;
};

/// roadcross install NEW TARGET: verify NEW, then put it in TARGET's place by rename.
class InstallCommand : public Command {
 public:
  explicit InstallCommand(CLI::App& parent);
  int run() override;

 private:
  std::string new_path_;
  std::string target_path_;
  std::string expected_id_;
};

/// roadcross nearest: the nearest road segment and point on its centreline.
class NearestCommand : public Command {
 public:
  explicit NearestCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  double max_distance_m_ = 1000.0;
};

/// roadcross heading: the road's direction and the heading that crosses it.
class HeadingCommand : public Command {
 public:
  explicit HeadingCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  double max_distance_m_ = 1000.0;
};

/// roadcross assess: is this a suitable place to cross, every cost term, and why not.
class AssessCommand : public Command {
 public:
  explicit AssessCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  AssessOptions options_;
};

/// roadcross better: better places to cross nearby, by walking along the road.
class BetterCommand : public Command {
 public:
  explicit BetterCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  BetterPlaceOptions options_;
};

/// roadcross monitor: progress of a crossing planned from a start position, at a given pose.
class MonitorCommand : public Command {
 public:
  explicit MonitorCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  std::vector<double> at_utm_;
  double yaw_rad_ = 0.0;
};

/// roadcross batch: one JSON request per line on stdin, one JSON answer per line on stdout.
class BatchCommand : public Command {
 public:
  explicit BatchCommand(CLI::App& parent);
  int run() override;

 private:
  std::vector<std::string> db_paths_;
};

/// roadcross gap: GO or WAIT for tracked vehicles read from stdin (one JSON object per line).
class GapCommand : public Command {
 public:
  explicit GapCommand(CLI::App& parent);
  int run() override;

 private:
  QueryOptions query_;
  RobotMotion robot_;
  GapOptions options_;
  HcmOptions hcm_;
  std::string policy_ = "ours";
};

/// roadcross simulate: traffic, a robot running a policy, and safety/efficiency metrics.
class SimulateCommand : public Command {
 public:
  explicit SimulateCommand(CLI::App& parent);
  int run() override;

 private:
  std::string db_path_;
  std::vector<double> utm_;
  std::optional<double> lat_deg_, lon_deg_;
  std::optional<double> width_m_, maxspeed_kmh_, sight_m_;
  std::optional<int> lanes_;
  bool island_ = false;
  double sensor_range_m_ = 200.0;
  std::vector<std::string> policies_{"ours", "hcm", "naive"};
  std::vector<double> volumes_{300.0};
  std::vector<double> naive_distances_m_{50.0};
  int runs_ = 1000;
  std::uint64_t seed_ = 1;
  std::string label_;
  bool json_ = false;
  bool per_run_ = false;
  sim::Scenario scenario_;
};

}  // namespace roadcross::cli
