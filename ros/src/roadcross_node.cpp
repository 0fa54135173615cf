// roadcross_node: the roadcross runtime as a ROS1 node. It opens a roadcross GeoPackage, or a
// set of them (parameter ~db: a path, or a list of maps and directories), follows the robot's GPS
// fix (and optionally an odometry or pose topic for the yaw), publishes the assessment of every fix
// and offers one service per behaviour-tree node of the crossing method: assess, better place, road
// heading, gap decision, monitor. ~reload swaps the map (or set) between two queries;
// /diagnostics carries the identity (map_id) of the map in use once a second.
//
// Frames: the runtime works in the DB's UTM grid; every yaw this node publishes or accepts is a
// true ENU yaw (REP-103: 0 = east, counter-clockwise, radians), i.e. grid yaw + the meridian
// convergence at the place. UTM eastings/northings are in the zone of the map in use: with a set
// of maps, the map that answers the latest GPS fix or WGS84 request (MapSet::choose).
//
// Language: C++17, because ROS1's message headers do not compile as C++20 (they use
// std::allocator<void>::rebind); the runtime's public headers are C++17-clean for this.
//
// Threading: one roadcross::Map (or MapSet) is not thread-safe, so the node spins a single thread:
// callbacks and services run one after another.
#include <ros/ros.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/NavSatFix.h>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "roadcross/gap.hpp"
#include "roadcross/map_set.hpp"
#include "roadcross/monitor.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross_ros/Assess.h"
#include "roadcross_ros/Assessment.h"
#include "roadcross_ros/BetterPlace.h"
#include "roadcross_ros/GapDecision.h"
#include "roadcross_ros/Monitor.h"
#include "roadcross_ros/Reload.h"
#include "roadcross_ros/RoadHeading.h"
#include "roadcross_ros/VehicleList.h"

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double or_nan(const std::optional<double>& value) {
  return value ? *value : kNaN;
}

/// Yaw about +z of a quaternion (the robot's heading in its frame), radians.
double yaw_of(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

/// 1, 0, or -1 for unknown (the messages' int8 flags).
std::int8_t tri_state(const std::optional<bool>& value) {
  return value ? static_cast<std::int8_t>(*value ? 1 : 0) : static_cast<std::int8_t>(-1);
}

/// A parameter with a default and a check; exits through ROS_FATAL (returns nullopt) when the
/// value breaks the documented range.
template <typename T, typename Check>
std::optional<T> param(const ros::NodeHandle& nh, const std::string& name, T fallback, Check ok,
                       const char* range) {
  T value = fallback;
  nh.param(name, value, fallback);
  if (!ok(value)) {
    ROS_FATAL_STREAM("parameter ~" << name << " = " << value << " is out of range: " << range);
    return std::nullopt;
  }
  return value;
}

const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
const auto any_finite = [](double v) { return std::isfinite(v); };

struct Settings {
  std::vector<std::string> db_paths;  ///< map files and directories of maps
  std::string fix_topic, odom_topic, pose_topic, vehicles_topic, utm_frame_id;
  bool pose_is_utm = false;
  double yaw_offset_rad = 0.0;
  double max_fix_age_s = 2.0;
  double max_distance_m = 1000.0;
  roadcross::AssessOptions assess;
  roadcross::BetterPlaceOptions better;
  double default_width_m = 6.0, kerb_margin_m = 0.5;
  roadcross::MonitorOptions monitor;
  roadcross::RobotMotion robot;
  roadcross::GapOptions gap;
  roadcross::HcmOptions hcm;
  roadcross::GapCrossingDefaults gap_defaults;
  std::string policy = "ours";
  /// Position uncertainty: the fix's covariance when its type says it is known, else this
  /// sigma (metres; 0: positions are taken as exact).
  bool use_fix_covariance = true;
  double sigma_m = 0.0;
  double region_probability = 0.95;
};

/// "[a, b]" as the paths a and b (blanks around each trimmed); any other text as one path.
std::vector<std::string> split_path_list(const std::string& text) {
  if (text.size() < 2 || text.front() != '[' || text.back() != ']') return {text};
  std::vector<std::string> paths;
  std::stringstream items(text.substr(1, text.size() - 2));
  for (std::string item; std::getline(items, item, ',');) {
    const std::size_t first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    paths.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return paths;
}

/// Reads every parameter (units and ranges: config/roadcross.yaml). False after a ROS_FATAL.
bool read_settings(const ros::NodeHandle& nh, Settings& s) {
  // ~db: one path (a map or a directory of maps), or a list of them (a set of maps).
  // On the command line (_db:=[a.gpkg, b.gpkg]) roscpp keeps a list as the string itself.
  std::string one_path;
  if (nh.getParam("db", s.db_paths)) {
  } else if (nh.getParam("db", one_path) && !one_path.empty()) {
    s.db_paths = split_path_list(one_path);
  }
  if (s.db_paths.empty()) {
    ROS_FATAL(
        "parameter ~db is not set: give the roadcross GeoPackage built by roadcross-build "
        "(roslaunch roadcross_ros roadcross.launch db:=/path/map.gpkg), a directory of maps, "
        "or a list of them");
    return false;
  }
  nh.param<std::string>("fix_topic", s.fix_topic, "fix");
  nh.param<std::string>("odom_topic", s.odom_topic, "");
  nh.param<std::string>("pose_topic", s.pose_topic, "");
  nh.param<std::string>("vehicles_topic", s.vehicles_topic, "");
  nh.param<std::string>("utm_frame_id", s.utm_frame_id, "utm");
  nh.param("pose_is_utm", s.pose_is_utm, false);
  bool ok = true;
  const auto set = [&ok](auto& target, const auto& value) {
    if (value) {
      target = *value;
    } else {
      ok = false;
    }
  };
  set(s.yaw_offset_rad, param(nh, "yaw_offset_rad", 0.0, any_finite, "finite"));
  set(s.max_fix_age_s, param(nh, "max_fix_age_s", 2.0, non_negative, ">= 0 (0: no limit)"));
  set(s.max_distance_m, param(nh, "max_distance_m", 1000.0, positive, "> 0"));
  nh.param("uncertainty/use_fix_covariance", s.use_fix_covariance, true);
  set(s.sigma_m, param(nh, "uncertainty/sigma_m", 0.0, non_negative, ">= 0 metres (0: exact)"));
  set(s.region_probability, param(
                                nh, "uncertainty/region_probability", 0.95,
                                [](double v) { return v > 0.0 && v < 1.0; }, "in (0, 1)"));
  s.assess.max_distance_m = s.max_distance_m;
  double value = 0.0;
  if (nh.getParam("assess/valid_distance_m", value)) {
    if (!positive(value)) {
      ROS_FATAL("parameter ~assess/valid_distance_m = %g is out of range: > 0", value);
      return false;
    }
    s.assess.valid_distance_m = value;
  }
  if (nh.getParam("assess/threshold", value)) {
    if (!any_finite(value)) {
      ROS_FATAL("parameter ~assess/threshold = %g is not finite", value);
      return false;
    }
    s.assess.threshold = value;
  }
  if (nh.getParam("assess/max_kerb_height_m", value)) {
    if (!non_negative(value)) {
      ROS_FATAL("parameter ~assess/max_kerb_height_m = %g is out of range: >= 0 metres", value);
      return false;
    }
    s.assess.max_kerb_height_m = value;
  }
  set(s.better.search_radius_m,
      param(nh, "better_place/search_radius_m", 100.0, positive, "> 0 metres"));
  int max_candidates = 5;
  nh.param("better_place/max_candidates", max_candidates, 5);
  if (max_candidates < 1) {
    ROS_FATAL("parameter ~better_place/max_candidates = %d is out of range: >= 1", max_candidates);
    return false;
  }
  s.better.max_candidates = static_cast<std::size_t>(max_candidates);
  s.better.assess = s.assess;
  set(s.default_width_m, param(nh, "crossing/default_width_m", 6.0, positive, "> 0 metres"));
  set(s.kerb_margin_m, param(nh, "crossing/kerb_margin_m", 0.5, non_negative, ">= 0 metres"));
  s.gap_defaults.width_m = s.default_width_m;
  set(s.gap_defaults.lane_width_m,
      param(nh, "crossing/lane_width_m", 3.25, positive, "> 0 metres"));
  set(s.gap_defaults.maxspeed_kmh,
      param(nh, "crossing/default_maxspeed_kmh", 50.0, positive, "> 0 km/h"));
  set(s.monitor.drift_m, param(nh, "monitor/drift_m", 0.5, positive, "> 0 metres"));
  set(s.monitor.corridor_half_width_m,
      param(nh, "monitor/corridor_half_width_m", 1.5, positive, "> 0 metres"));
  set(s.monitor.heading_tolerance_rad,
      param(nh, "monitor/heading_tolerance_rad", 0.35, positive, "> 0 radians"));
  set(s.monitor.done_margin_m, param(nh, "monitor/done_margin_m", 0.2, positive, "> 0 metres"));
  set(s.robot.speed_mps, param(nh, "robot/speed_mps", 1.2, positive, "> 0 m/s"));
  set(s.robot.startup_s, param(nh, "robot/startup_s", 1.0, non_negative, ">= 0 s"));
  set(s.robot.radius_m, param(nh, "robot/radius_m", 0.4, non_negative, ">= 0 metres"));
  nh.param<std::string>("gap/policy", s.policy, "ours");
  if (s.policy != "ours" && s.policy != "hcm") {
    ROS_FATAL("parameter ~gap/policy = '%s': expected ours or hcm", s.policy.c_str());
    return false;
  }
  set(s.gap.min_pet_s, param(nh, "gap/min_pet_s", 1.2, non_negative, ">= 0 s"));
  set(s.gap.safety_buffer_m, param(nh, "gap/safety_buffer_m", 0.5, non_negative, ">= 0 metres"));
  set(s.gap.speed_uncertainty_fraction,
      param(nh, "gap/speed_uncertainty_fraction", 0.1, non_negative, ">= 0"));
  set(s.gap.stopped_speed_mps, param(nh, "gap/stopped_speed_mps", 0.1, non_negative, ">= 0 m/s"));
  set(s.gap.max_track_age_s, param(nh, "gap/max_track_age_s", 0.5, positive, "> 0 s"));
  set(s.gap.sensor_range_m, param(nh, "gap/sensor_range_m", 200.0, positive, "> 0 metres"));
  set(s.gap.unseen_speed_factor,
      param(nh, "gap/unseen_speed_factor", 1.2, positive, "> 0 (x maxspeed)"));
  set(s.gap.turning_speed_kmh, param(nh, "gap/turning_speed_kmh", 25.0, positive, "> 0 km/h"));
  set(s.hcm.start_clearance_s, param(nh, "gap/hcm_start_clearance_s", 3.0, non_negative, ">= 0 s"));
  return ok;
}

class RoadcrossNode {
 public:
  RoadcrossNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, Settings settings,
                roadcross::MapSet maps)
      : settings_(std::move(settings)), maps_(std::move(maps)) {
    assessment_pub_ = pnh.advertise<roadcross_ros::Assessment>("assessment", 10);
    fix_sub_ = nh.subscribe(settings_.fix_topic, 10, &RoadcrossNode::on_fix, this);
    if (!settings_.odom_topic.empty()) {
      odom_sub_ = nh.subscribe(settings_.odom_topic, 10, &RoadcrossNode::on_odom, this);
    }
    if (!settings_.pose_topic.empty()) {
      pose_sub_ = nh.subscribe(settings_.pose_topic, 10, &RoadcrossNode::on_pose, this);
    }
    if (!settings_.vehicles_topic.empty()) {
      vehicles_sub_ = nh.subscribe(settings_.vehicles_topic, 10, &RoadcrossNode::on_vehicles, this);
    }
    services_.push_back(pnh.advertiseService("assess", &RoadcrossNode::assess, this));
    services_.push_back(pnh.advertiseService("better_place", &RoadcrossNode::better_place, this));
    services_.push_back(pnh.advertiseService("road_heading", &RoadcrossNode::road_heading, this));
    services_.push_back(pnh.advertiseService("monitor", &RoadcrossNode::monitor, this));
    services_.push_back(pnh.advertiseService("gap_decision", &RoadcrossNode::gap_decision, this));
    services_.push_back(pnh.advertiseService("reload", &RoadcrossNode::reload, this));
    diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 1);
    diagnostics_timer_ = nh.createTimer(ros::Duration(1.0),
                                        [this](const ros::TimerEvent&) { publish_diagnostics(); });
    publish_diagnostics();
  }

 private:
  struct Fix {
    double lat_deg = 0.0, lon_deg = 0.0;
    ros::Time stamp, received;
    /// From position_covariance when its type is DIAGONAL_KNOWN or KNOWN (and ~uncertainty/
    /// use_fix_covariance), else ~uncertainty/sigma_m, else none.
    std::optional<roadcross::PositionUncertainty> uncertainty;
  };
  struct PoseSample {
    double x = 0.0, y = 0.0, yaw_rad = 0.0;  // yaw: true ENU after ~yaw_offset_rad
    ros::Time received;
  };

  // --- subscriptions ---

  void on_fix(const sensor_msgs::NavSatFix& fix) {
    if (fix.status.status < sensor_msgs::NavSatStatus::STATUS_FIX || !std::isfinite(fix.latitude) ||
        !std::isfinite(fix.longitude)) {
      ROS_WARN_THROTTLE(5.0, "ignoring GPS fixes without a position (status %d)",
                        fix.status.status);
      return;
    }
    fix_ =
        Fix{fix.latitude, fix.longitude, fix.header.stamp, ros::Time::now(), uncertainty_of(fix)};
    roadcross::Position here = roadcross::Position::wgs84(fix.latitude, fix.longitude);
    use_map_for(here);
    here.uncertainty = fix_->uncertainty;
    roadcross_ros::Assessment out;
    out.map_id = map().info().map_id;
    if (const auto a = map().assess(here, settings_.assess); a.ok()) {
      fill(out, *a);
    } else {
      out.error = a.status.message;
      out.has_score = false;
      ROS_WARN_THROTTLE(5.0, "assessment of the fix failed: %s", a.status.message.c_str());
    }
    out.header.stamp = fix.header.stamp;
    out.header.frame_id = settings_.utm_frame_id;
    assessment_pub_.publish(out);
  }

  void on_pose_sample(const geometry_msgs::Pose& pose) {
    pose_ = PoseSample{
        pose.position.x, pose.position.y,
        roadcross::geo::normalize_angle_rad(yaw_of(pose.orientation) + settings_.yaw_offset_rad),
        ros::Time::now()};
  }
  void on_odom(const nav_msgs::Odometry& odom) { on_pose_sample(odom.pose.pose); }
  void on_pose(const geometry_msgs::PoseStamped& pose) { on_pose_sample(pose.pose); }
  void on_vehicles(const roadcross_ros::VehicleList& list) { vehicles_ = list; }

  // --- helpers ---

  /// The map in use: the one that answered the latest fix or WGS84 request.
  roadcross::Map& map() { return maps_.map(current_map_); }
  const roadcross::Map& map() const { return maps_.map(current_map_); }

  /// With a set of maps, makes the map that answers `position` (WGS84) the one in use; UTM
  /// positions stay with the map in use (they are in its zone). Where no map has a road near
  /// enough, the map in use stays and its own answer says so.
  void use_map_for(const roadcross::Position& position) {
    if (maps_.size() == 1 || position.kind != roadcross::Position::Kind::wgs84) return;
    const auto chosen = maps_.choose(position, settings_.max_distance_m);
    if (!chosen.ok() || *chosen == current_map_) return;
    current_map_ = *chosen;
    const roadcross::MapInfo& info = map().info();
    ROS_INFO("roadcross: now answering from %s (UTM zone %d%s)", info.path.c_str(), info.zone.zone,
             info.zone.northern ? "N" : "S");
  }

  /// The fix's horizontal uncertainty: NavSatFix.position_covariance is row-major ENU in m^2,
  /// so its first 2x2 block is east/north, in true ENU (the runtime turns it into the grid).
  std::optional<roadcross::PositionUncertainty> uncertainty_of(
      const sensor_msgs::NavSatFix& fix) const {
    const auto& c = fix.position_covariance;
    const auto type = fix.position_covariance_type;
    if (settings_.use_fix_covariance &&
        (type == sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN ||
         type == sensor_msgs::NavSatFix::COVARIANCE_TYPE_DIAGONAL_KNOWN)) {
      const double east_north = type == sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN ? c[1] : 0.0;
      return roadcross::PositionUncertainty::enu(c[0], east_north, c[4],
                                                 settings_.region_probability);
    }
    return default_uncertainty();
  }

  /// ~uncertainty/sigma_m as an uncertainty, none when it is 0.
  std::optional<roadcross::PositionUncertainty> default_uncertainty() const {
    if (settings_.sigma_m <= 0.0) return std::nullopt;
    return roadcross::PositionUncertainty::circular(settings_.sigma_m,
                                                    settings_.region_probability);
  }

  /// The runtime position of a request, or the reason there is none.
  std::optional<roadcross::Position> position_of(const roadcross_ros::Position& p,
                                                 std::string& error) {
    std::optional<roadcross::Position> position = requested_position(p, error);
    if (position) use_map_for(*position);
    return position;
  }

  /// The request's position with its uncertainty, or the reason there is none.
  std::optional<roadcross::Position> requested_position(const roadcross_ros::Position& p,
                                                        std::string& error) const {
    std::optional<roadcross::Position> position = fix_position_of(p, error);
    if (!position) return position;
    // A request's own sigma_m wins; else CURRENT carries the fix's uncertainty and the others
    // ~uncertainty/sigma_m.
    if (p.sigma_m > 0.0 || !std::isfinite(p.sigma_m)) {
      position->uncertainty =
          roadcross::PositionUncertainty::circular(p.sigma_m, settings_.region_probability);
    } else if (!position->uncertainty) {
      position->uncertainty = default_uncertainty();
    }
    return position;
  }

  std::optional<roadcross::Position> fix_position_of(const roadcross_ros::Position& p,
                                                     std::string& error) const {
    switch (p.kind) {
      case roadcross_ros::Position::WGS84:
        return roadcross::Position::wgs84(p.latitude_deg, p.longitude_deg);
      case roadcross_ros::Position::UTM:
        return roadcross::Position::utm(p.easting_m, p.northing_m);
      case roadcross_ros::Position::CURRENT:
        if (settings_.pose_is_utm && pose_ && fresh(pose_->received)) {
          return roadcross::Position::utm(pose_->x, pose_->y);
        }
        if (!fix_) {
          error = "no GPS fix received yet on " + fix_topic_name();
          return std::nullopt;
        }
        if (!fresh(fix_->received)) {
          error = "the latest GPS fix on " + fix_topic_name() + " is " +
                  std::to_string((ros::Time::now() - fix_->received).toSec()) +
                  " s old (~max_fix_age_s " + std::to_string(settings_.max_fix_age_s) + ")";
          return std::nullopt;
        }
        roadcross::Position current = roadcross::Position::wgs84(fix_->lat_deg, fix_->lon_deg);
        current.uncertainty = fix_->uncertainty;
        return current;
    }
    error = "position.kind " + std::to_string(p.kind) + " is not CURRENT (0), WGS84 (1) or UTM (2)";
    return std::nullopt;
  }

  bool fresh(const ros::Time& received) const {
    return settings_.max_fix_age_s <= 0.0 ||
           (ros::Time::now() - received).toSec() <= settings_.max_fix_age_s;
  }

  std::string fix_topic_name() const { return fix_sub_.getTopic(); }

  /// Grid-to-true rotation at a UTM point of the map's zone (radians); 0 when the point cannot
  /// be projected (then grid and true differ by well under a degree anyway inside a map).
  double convergence_at(const roadcross::PlanePoint& p) const {
    try {
      const auto zone = map().info().zone;
      const auto ll = roadcross::geo::utm_to_wgs84(p.easting_m, p.northing_m, zone);
      return roadcross::geo::wgs84_to_utm(ll.lat_deg, ll.lon_deg, zone).convergence_rad;
    } catch (const std::exception& e) {
      ROS_WARN_THROTTLE(5.0, "no meridian convergence at E %.1f N %.1f: %s", p.easting_m,
                        p.northing_m, e.what());
      return 0.0;
    }
  }

  static void fill(roadcross_ros::Assessment& out, const roadcross::Assessment& a) {
    out.query_easting_m = a.road.query.easting_m;
    out.query_northing_m = a.road.query.northing_m;
    out.valid = a.valid;
    out.suitable = a.suitable;
    out.reasons = a.reasons;
    for (const std::string& code : a.reasons) {
      out.reason_sentences.emplace_back(roadcross::describe_reason(code));
    }
    out.segment_id = a.road.segment_id;
    out.osm_way_id = a.road.osm_way_id;
    out.highway = a.road.highway;
    out.name = a.road.name;
    out.distance_m = a.road.distance_m;
    out.closest_easting_m = a.road.closest.easting_m;
    out.closest_northing_m = a.road.closest.northing_m;
    out.has_score = a.score.has_value();
    out.score = a.score.value_or(0);
    out.context_score = a.context_score.value_or(0);
    out.threshold = a.threshold;
    out.valid_distance_m = a.valid_distance_m;
    out.rank = a.rank.value_or(-1);
    out.junction_distance_m = or_nan(a.junction_distance_m);
    out.radius_m = or_nan(a.radius_m);
    out.crossing_distance_m = or_nan(a.crossing_distance_m);
    out.maxspeed_kmh = or_nan(a.maxspeed_kmh);
    out.width_m = or_nan(a.width_m);
    out.lanes = a.lanes.value_or(-1);
    out.landform = a.landform.value_or("");
    out.sight_min_m = or_nan(a.sight_min_m);
    out.required_sight_m = or_nan(a.required_sight_m);
    out.tunnel = a.tunnel;
    out.kerb = a.kerb.value_or("");
    out.kerb_height_m = or_nan(a.kerb_height_m);
    out.max_kerb_height_m = a.max_kerb_height_m;
    out.crossing_island = tri_state(a.crossing_island);
    out.pavement_far_side = tri_state(a.pavement_far_side);
    out.override_note = a.override_note;
    out.uncertain = a.region.has_value();
    if (a.region) {
      out.region_semi_major_m = a.region->semi_major_m;
      out.region_semi_minor_m = a.region->semi_minor_m;
      out.region_segment_ids = a.region->segment_ids;
      out.same_road = a.region->same_road;
      out.suitable_share = a.region->suitable_share;
      out.heading_spread_rad = a.region->heading_spread_rad;
    } else {
      out.same_road = true;
      out.suitable_share = a.suitable ? 1.0 : 0.0;
    }
  }

  // --- services ---

  bool assess(roadcross_ros::Assess::Request& req, roadcross_ros::Assess::Response& res) {
    res.map_id = map().info().map_id;
    const auto position = position_of(req.position, res.message);
    if (!position) return true;  // success = false with the message: the call itself worked
    roadcross::AssessOptions options = settings_.assess;
    if (req.valid_distance_m > 0.0) options.valid_distance_m = req.valid_distance_m;
    if (req.use_threshold) options.threshold = req.threshold;
    const auto a = map().assess(*position, options);
    res.assessment.header.stamp = ros::Time::now();
    res.assessment.header.frame_id = settings_.utm_frame_id;
    res.assessment.map_id = res.map_id;
    if (!a.ok()) {
      res.message = res.assessment.error = a.status.message;
      return true;
    }
    fill(res.assessment, *a);
    res.success = true;
    return true;
  }

  bool better_place(roadcross_ros::BetterPlace::Request& req,
                    roadcross_ros::BetterPlace::Response& res) {
    res.map_id = map().info().map_id;
    const auto position = position_of(req.position, res.message);
    if (!position) return true;
    roadcross::BetterPlaceOptions options = settings_.better;
    if (req.search_radius_m > 0.0) options.search_radius_m = req.search_radius_m;
    if (req.max_candidates > 0) options.max_candidates = req.max_candidates;
    const auto places = map().better_place(*position, options);
    if (!places.ok()) {
      res.message = places.status.message;
      return true;
    }
    for (const roadcross::Candidate& c : places->candidates) {
      roadcross_ros::Candidate out;
      out.easting_m = c.point.easting_m;
      out.northing_m = c.point.northing_m;
      try {
        const auto ll =
            roadcross::geo::utm_to_wgs84(c.point.easting_m, c.point.northing_m, map().info().zone);
        out.latitude_deg = ll.lat_deg;
        out.longitude_deg = ll.lon_deg;
      } catch (const std::exception&) {
        out.latitude_deg = out.longitude_deg = kNaN;
      }
      out.walking_distance_m = c.walking_distance_m;
      out.segment_id = c.segment_id;
      out.suitable = c.suitable;
      out.score = c.score;
      out.designated_crossing = c.designated_crossing;
      out.crossing_yaw_rad =
          roadcross::geo::normalize_angle_rad(c.crossing_heading_rad + convergence_at(c.point));
      out.reasons = c.reasons;
      out.suitable_share = c.suitable_share ? *c.suitable_share : kNaN;
      res.candidates.push_back(std::move(out));
    }
    res.reason = places->reason;
    res.success = true;
    return true;
  }

  bool road_heading(roadcross_ros::RoadHeading::Request& req,
                    roadcross_ros::RoadHeading::Response& res) {
    res.map_id = map().info().map_id;
    const auto position = position_of(req.position, res.message);
    if (!position) return true;
    const auto h = map().road_heading(*position, settings_.max_distance_m);
    if (!h.ok()) {
      res.message = h.status.message;
      return true;
    }
    res.segment_id = h->road.segment_id;
    res.name = h->road.name;
    res.distance_m = h->road.distance_m;
    res.road_grid_yaw_rad = h->road_heading_rad;
    res.crossing_grid_yaw_rad = h->crossing_heading_rad;
    res.convergence_rad = h->convergence_rad;
    res.road_yaw_rad =
        roadcross::geo::normalize_angle_rad(h->road_heading_rad + h->convergence_rad);
    res.crossing_yaw_rad =
        roadcross::geo::normalize_angle_rad(h->crossing_heading_rad + h->convergence_rad);
    res.crossing_orientation.z = std::sin(res.crossing_yaw_rad / 2.0);
    res.crossing_orientation.w = std::cos(res.crossing_yaw_rad / 2.0);
    res.on_centreline = h->on_centreline;
    res.heading_spread_rad = h->heading_spread_rad ? *h->heading_spread_rad : kNaN;
    res.success = true;
    return true;
  }

  bool monitor(roadcross_ros::Monitor::Request& req, roadcross_ros::Monitor::Response& res) {
    res.map_id = map().info().map_id;
    if (req.start.kind == roadcross_ros::Position::CURRENT) {
      res.message = "start: give where the crossing started (WGS84 or UTM), not CURRENT";
      return true;
    }
    const auto start = position_of(req.start, res.message);
    if (!start) return true;
    const auto plan =
        roadcross::plan_crossing(map(), *start, settings_.default_width_m, settings_.kerb_margin_m);
    if (!plan.ok()) {
      res.message = plan.status.message;
      return true;
    }
    const double convergence_rad = convergence_at(plan->start);
    roadcross::Pose pose;
    if (req.use_current_pose) {
      if (!pose_ || !fresh(pose_->received)) {
        res.message = "no recent odometry/pose (~odom_topic or ~pose_topic) for the robot's yaw";
        return true;
      }
      roadcross_ros::Position current;
      current.kind = roadcross_ros::Position::CURRENT;
      const auto here = position_of(current, res.message);
      if (!here) return true;
      const auto utm = map().to_utm(*here);
      if (!utm.ok()) {
        res.message = utm.status.message;
        return true;
      }
      pose.position = *utm;
      pose.yaw_rad = pose_->yaw_rad - convergence_rad;
    } else {
      pose.position = {req.easting_m, req.northing_m};
      pose.yaw_rad = req.yaw_rad - convergence_rad;
    }
    const auto p = roadcross::monitor(*plan, pose, settings_.monitor);
    if (!p.ok()) {
      res.message = p.status.message;
      return true;
    }
    res.state = static_cast<std::uint8_t>(p->state);
    res.state_name = roadcross::to_string(p->state);
    res.progress = p->progress;
    res.lateral_deviation_m = p->lateral_deviation_m;
    res.heading_error_rad = p->heading_error_rad;
    res.start_easting_m = plan->start.easting_m;
    res.start_northing_m = plan->start.northing_m;
    res.target_easting_m = plan->target.easting_m;
    res.target_northing_m = plan->target.northing_m;
    res.plan_yaw_rad = roadcross::geo::normalize_angle_rad(plan->heading_rad + convergence_rad);
    res.success = true;
    return true;
  }

  bool gap_decision(roadcross_ros::GapDecision::Request& req,
                    roadcross_ros::GapDecision::Response& res) {
    res.map_id = map().info().map_id;
    const auto position = position_of(req.position, res.message);
    if (!position) return true;
    const std::string policy = req.policy.empty() ? settings_.policy : req.policy;
    if (policy != "ours" && policy != "hcm") {
      res.message = "policy '" + policy + "': expected ours or hcm";
      return true;
    }
    if (req.use_latest_vehicles && !vehicles_) {
      res.message = settings_.vehicles_topic.empty()
                        ? std::string("use_latest_vehicles needs ~vehicles_topic")
                        : "no vehicle list received yet on " + vehicles_sub_.getTopic();
      return true;
    }
    const roadcross_ros::VehicleList& list = req.use_latest_vehicles ? *vehicles_ : req.vehicles;
    const auto crossing = roadcross::gap_crossing(map(), *position, settings_.gap_defaults);
    if (!crossing.ok()) {
      res.message = crossing.status.message;
      return true;
    }
    // Times relative to "now" (0): ROS stamps are ~1.7e9 s, and seconds relative to them keep
    // the runtime's arithmetic exact to the nanosecond.
    const ros::Time now = list.header.stamp.isZero() ? ros::Time::now() : list.header.stamp;
    std::vector<roadcross::TrackedVehicle> vehicles;
    for (const roadcross_ros::TrackedVehicle& in : list.vehicles) {
      roadcross::TrackedVehicle v;
      if (in.frame == roadcross_ros::TrackedVehicle::FRAME_ROBOT_ENU) {
        v.frame = roadcross::TrackedVehicle::Frame::robot_enu;
      } else if (in.frame != roadcross_ros::TrackedVehicle::FRAME_UTM) {
        res.message = "vehicle " + std::to_string(vehicles.size()) + ": frame " +
                      std::to_string(in.frame) + " is not FRAME_UTM (0) or FRAME_ROBOT_ENU (1)";
        return true;
      }
      v.x_m = in.x_m;
      v.y_m = in.y_m;
      v.vx_mps = in.vx_mps;
      v.vy_mps = in.vy_mps;
      if (in.length_m != 0.0) v.length_m = in.length_m;
      if (in.speed_uncertainty_mps >= 0.0) v.speed_uncertainty_mps = in.speed_uncertainty_mps;
      v.time_s = in.stamp.isZero() ? 0.0 : (in.stamp - now).toSec();
      vehicles.push_back(v);
    }
    const auto d =
        policy == "hcm"
            ? roadcross::hcm_gap_decision(*crossing, settings_.robot, vehicles.data(),
                                          vehicles.size(), 0.0, settings_.gap, settings_.hcm)
            : roadcross::gap_decision(*crossing, settings_.robot, vehicles.data(), vehicles.size(),
                                      0.0, settings_.gap);
    if (!d.ok()) {
      res.message = d.status.message;
      return true;
    }
    res.go = d->verdict == roadcross::GapVerdict::go;
    res.verdict = roadcross::to_string(d->verdict);
    res.reason = roadcross::to_string(d->reason);
    res.limiting_vehicle = d->limiting_vehicle;
    res.margin_s = or_nan(d->margin_s);
    res.earliest_start_in_s = or_nan(d->earliest_start_s);
    res.stage = d->stage;
    res.crossing_time_s = d->crossing_time_s;
    res.required_sight_m = d->required_sight_m;
    res.visible_road_m = d->visible_road_m;
    res.critical_gap_s = d->critical_gap_s;
    res.vehicles_counted = d->vehicles_counted;
    res.stale_tracks = d->stale_tracks;
    res.beyond_sensor_range = d->beyond_sensor_range;
    res.lanes = crossing->lanes;
    res.road_width_m = crossing->road_width_m;
    res.maxspeed_kmh = crossing->maxspeed_kmh;
    res.crossing_yaw_rad =
        roadcross::geo::normalize_angle_rad(crossing->heading_rad + crossing->convergence_rad);
    res.success = true;
    return true;
  }

  // --- map identity and replacement ---

  /// Opens req.path (or the current path) and, only when that succeeds, answers from it from
  /// the next callback on. The single spinner thread runs this between two queries, so none is
  /// dropped or answered from a half-swapped map; a process that installed the new file by
  /// rename (roadcross install) leaves the old one readable until this swap closes it.
  bool reload(roadcross_ros::Reload::Request& req, roadcross_ros::Reload::Response& res) {
    const std::vector<std::string> paths =
        req.path.empty() ? settings_.db_paths : std::vector<std::string>{req.path};
    res.previous_map_id = map().info().map_id;
    roadcross::Result<roadcross::MapSet> opened = roadcross::MapSet::open(paths);
    if (!opened.ok()) {
      res.message = "kept " + map().info().path + ": " + opened.status.message;
      res.path = map().info().path;
      res.map_id = map().info().map_id;
      ROS_ERROR("reload failed, %s", res.message.c_str());
      return true;
    }
    const roadcross::geo::UtmZone zone_before = map().info().zone;
    maps_ = std::move(*opened.value);
    current_map_ = 0;
    if (fix_) use_map_for(roadcross::Position::wgs84(fix_->lat_deg, fix_->lon_deg));
    if (map().info().zone.zone != zone_before.zone ||
        map().info().zone.northern != zone_before.northern) {
      ROS_WARN("reload: %s is in another UTM zone than the map before; UTM positions change zone",
               map().info().path.c_str());
    }
    settings_.db_paths = paths;
    res.success = true;
    res.path = map().info().path;
    res.map_id = map().info().map_id;
    res.message = "answering from " + res.path;
    ROS_INFO("roadcross: reloaded %s, map_id %s (was %s), %lld segments", res.path.c_str(),
             res.map_id.c_str(), res.previous_map_id.c_str(),
             static_cast<long long>(map().info().segment_count));
    publish_diagnostics();
    return true;
  }

  /// One DiagnosticStatus "roadcross: map": the path and identity of the map answering now.
  void publish_diagnostics() {
    const roadcross::MapInfo& info = map().info();
    diagnostic_msgs::DiagnosticStatus status;
    status.name = "roadcross: map";
    status.hardware_id = info.path;
    status.level = info.map_id.empty() ? diagnostic_msgs::DiagnosticStatus::WARN
                                       : diagnostic_msgs::DiagnosticStatus::OK;
    status.message = info.map_id.empty() ? "map without map_id (built before map ids): rebuild"
                                         : "map " + info.map_id.substr(0, 12);
    const auto add = [&](const std::string& key, const std::string& value) {
      diagnostic_msgs::KeyValue pair;
      pair.key = key;
      pair.value = value;
      status.values.push_back(pair);
    };
    add("path", info.path);
    add("map_id", info.map_id);
    add("osm_timestamp", info.osm_timestamp);
    add("segment_count", std::to_string(info.segment_count));
    add("schema_version", std::to_string(info.schema_version));
    add("tool_version", info.tool_version);
    diagnostic_msgs::DiagnosticArray array;
    array.header.stamp = ros::Time::now();
    array.status.push_back(status);
    diagnostics_pub_.publish(array);
  }

  Settings settings_;
  roadcross::MapSet maps_;
  std::size_t current_map_ = 0;  ///< index in maps_ of the map in use
  ros::Publisher diagnostics_pub_;
  ros::Timer diagnostics_timer_;
  ros::Publisher assessment_pub_;
  ros::Subscriber fix_sub_, odom_sub_, pose_sub_, vehicles_sub_;
  std::vector<ros::ServiceServer> services_;
  std::optional<Fix> fix_;
  std::optional<PoseSample> pose_;
  std::optional<roadcross_ros::VehicleList> vehicles_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "roadcross");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  Settings settings;
  if (!read_settings(pnh, settings)) return 2;
  roadcross::Result<roadcross::MapSet> maps = roadcross::MapSet::open(settings.db_paths);
  if (!maps.ok()) {
    std::string given;
    for (const std::string& path : settings.db_paths) given += (given.empty() ? "" : ", ") + path;
    ROS_FATAL("cannot open ~db '%s': %s", given.c_str(), maps.status.message.c_str());
    return 1;
  }
  for (std::size_t i = 0; i < maps->size(); ++i) {
    const roadcross::MapInfo& info = maps->map(i).info();
    ROS_INFO("roadcross: %s, map_id %s, OSM data as of %s, %lld segments, UTM zone %d%s",
             info.path.c_str(), info.map_id.empty() ? "(none)" : info.map_id.c_str(),
             info.osm_timestamp.empty() ? "(unknown)" : info.osm_timestamp.c_str(),
             static_cast<long long>(info.segment_count), info.zone.zone,
             info.zone.northern ? "N" : "S");
  }
  RoadcrossNode node(nh, pnh, std::move(settings), std::move(*maps.value));
  ros::spin();
  return 0;
}
