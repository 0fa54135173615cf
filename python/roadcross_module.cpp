// Python bindings of the roadcross runtime (pybind11): `import roadcross`.
//
// The C++ API reports failure through Result/Status; here every failure is raised as an
// exception of the roadcross.Error hierarchy, one class per StatusCode, each also derived from the
// built-in exception a Python user would catch (FileNotFoundError, ValueError, LookupError,
// RuntimeError). The exception's message is the runtime's, its `code` attribute the StatusCode
// name. Positions are keyword-only: lat=/lon= (WGS84 degrees) or easting=/northing= (UTM metres
// in the map's zone), so that a swapped pair cannot pass silently.
//
// The GIL is held during every call (calls take microseconds): a Map used from several Python
// threads is therefore serialised, never raced (the C++ Map is one SQLite connection, not
// thread-safe). For parallel queries use one Map per thread, as in C++.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/gap.hpp"
#include "roadcross/map_set.hpp"
#include "roadcross/monitor.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/version.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace roadcross::python {
namespace {

// The exception classes, created once at import. Raw owned references that are never released:
// a static py::object would be destroyed after the interpreter is gone.
struct ErrorClasses {
  PyObject* base = nullptr;
  PyObject* file_not_found = nullptr;
  PyObject* not_a_database = nullptr;
  PyObject* wrong_version = nullptr;
  PyObject* corrupt_database = nullptr;
  PyObject* invalid_argument = nullptr;
  PyObject* not_found = nullptr;
  PyObject* internal = nullptr;
  PyObject* corrupt_segment = nullptr;
};
ErrorClasses g_errors;

PyObject* add_error_class(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("roadcross.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (cls == nullptr) throw py::error_already_set();
  m.attr(name) = py::reinterpret_borrow<py::object>(cls);
  return cls;  // the module and this reference keep it alive
}

void add_error_classes(py::module_& m) {
  const py::module_ builtins = py::module_::import("builtins");
  g_errors.base = add_error_class(
      m, "Error",
      "Base class of every error the roadcross runtime reports. `code` is the runtime's "
      "StatusCode name (e.g. 'file_not_found'); str(error) is the runtime's message.",
      py::make_tuple(builtins.attr("Exception")));
  const py::object base = py::reinterpret_borrow<py::object>(g_errors.base);
  g_errors.file_not_found =
      add_error_class(m, "MapNotFoundError",
                      "The map file does not exist or cannot be read (also a FileNotFoundError).",
                      py::make_tuple(base, builtins.attr("FileNotFoundError")));
  g_errors.not_a_database =
      add_error_class(m, "NotARoadcrossMapError",
                      "The file is not SQLite, not a GeoPackage, or not written by roadcross-build "
                      "(also a ValueError).",
                      py::make_tuple(base, builtins.attr("ValueError")));
  g_errors.wrong_version = add_error_class(
      m, "WrongVersionError",
      "A roadcross map of a schema version this runtime cannot read; the message says whether to "
      "update the runtime or rebuild the map (also a ValueError).",
      py::make_tuple(base, builtins.attr("ValueError")));
  g_errors.corrupt_database =
      add_error_class(m, "CorruptMapError",
                      "A roadcross map whose content breaks the contract (also a ValueError).",
                      py::make_tuple(base, builtins.attr("ValueError")));
  g_errors.corrupt_segment = add_error_class(
      m, "CorruptSegmentError",
      "One segment of the map cannot be right (a non-finite or out-of-range value, an unknown "
      "reason code, an index box that does not hold it, flags contradicting its reasons): no "
      "verdict is given there. The message names the segment (also a CorruptMapError).",
      py::make_tuple(py::reinterpret_borrow<py::object>(g_errors.corrupt_database)));
  g_errors.invalid_argument = add_error_class(
      m, "InvalidArgumentError",
      "NaN or infinite input, latitude/longitude out of range, a position outside the map's UTM "
      "zone, or an option out of its range (also a ValueError).",
      py::make_tuple(base, builtins.attr("ValueError")));
  g_errors.not_found = add_error_class(
      m, "NoRoadError",
      "No road in the map near enough to answer (within max_distance_m), or no such segment "
      "(also a LookupError).",
      py::make_tuple(base, builtins.attr("LookupError")));
  g_errors.internal =
      add_error_class(m, "InternalError", "An unexpected SQLite error (also a RuntimeError).",
                      py::make_tuple(base, builtins.attr("RuntimeError")));
}

PyObject* error_class(StatusCode code) {
  switch (code) {
    case StatusCode::file_not_found:
      return g_errors.file_not_found;
    case StatusCode::not_a_database:
      return g_errors.not_a_database;
    case StatusCode::wrong_version:
      return g_errors.wrong_version;
    case StatusCode::corrupt_database:
      return g_errors.corrupt_database;
    case StatusCode::corrupt_segment:
      return g_errors.corrupt_segment;
    case StatusCode::invalid_argument:
      return g_errors.invalid_argument;
    case StatusCode::not_found:
      return g_errors.not_found;
    case StatusCode::ok:
    case StatusCode::internal:
      break;
  }
  return g_errors.internal;
}

[[noreturn]] void raise(const Status& status) {
  const py::handle cls(error_class(status.code));
  py::object error = cls(py::str(status.message));
  error.attr("code") = to_string(status.code);
  PyErr_SetObject(cls.ptr(), error.ptr());
  throw py::error_already_set();
}

template <typename T>
T value_or_raise(Result<T>&& result) {
  if (!result.ok()) raise(result.status);
  return std::move(*result.value);
}

/// The query position from the keyword arguments: exactly one complete pair.
Position position_from(std::optional<double> lat, std::optional<double> lon,
                       std::optional<double> easting, std::optional<double> northing) {
  const bool wgs84 = lat.has_value() || lon.has_value();
  const bool utm = easting.has_value() || northing.has_value();
  if (wgs84 && utm) {
    throw py::type_error("give lat= and lon=, or easting= and northing=, not both");
  }
  if (wgs84) {
    if (!lat || !lon) throw py::type_error("lat= needs lon= and lon= needs lat=");
    return Position::wgs84(*lat, *lon);
  }
  if (utm) {
    if (!easting || !northing) {
      throw py::type_error("easting= needs northing= and northing= needs easting=");
    }
    return Position::utm(*easting, *northing);
  }
  throw py::type_error(
      "give a position: lat= and lon= (WGS84 degrees) or easting= and northing= (UTM metres in "
      "the map's zone)");
}

/// position_from with the zone of a UTM position (MapSet: its maps may lie in several zones).
Position zoned_position_from(std::optional<double> lat, std::optional<double> lon,
                             std::optional<double> easting, std::optional<double> northing,
                             const std::optional<std::string>& utm_zone) {
  Position position = position_from(lat, lon, easting, northing);
  if (!utm_zone) return position;
  if (position.kind != Position::Kind::utm) {
    throw py::type_error("utm_zone= goes with easting= and northing=, not with lat= and lon=");
  }
  const std::optional<geo::UtmZone> zone = parse_utm_zone(*utm_zone);
  if (!zone) {
    throw py::value_error("utm_zone '" + *utm_zone +
                          "' is not a UTM zone (1..60 with N or S, "
                          "e.g. '33N')");
  }
  return Position::utm(position.first, position.second, *zone);
}

// The four position keywords, first after the keyword-only marker of every positional query.
#define ROADCROSS_POSITION_ARGS                                            \
  py::kw_only(), py::arg("lat") = py::none(), py::arg("lon") = py::none(), \
                 py::arg("easting") = py::none(), py::arg("northing") = py::none()
#define ROADCROSS_POSITION_DOC                                                             \
  "Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting, " \
  "northing: UTM metres in the map's zone (Map.info.utm_zone).\n"

/// repr(obj) as "Name(a=..., b=...)" from the listed attributes.
std::string repr_of(const py::handle& obj, const char* name,
                    const std::vector<const char*>& attributes) {
  std::string out = std::string(name) + "(";
  bool first = true;
  for (const char* attribute : attributes) {
    if (!first) out += ", ";
    first = false;
    out += attribute;
    out += "=";
    out += py::repr(obj.attr(attribute)).cast<std::string>();
  }
  return out + ")";
}

// The attribute names are copied into the closure (an initializer_list's array would not
// outlive this call).
template <typename Class>
void add_repr(Class& cls, const char* name, std::initializer_list<const char*> attributes) {
  cls.def("__repr__", [name, names = std::vector<const char*>(attributes)](const py::object& self) {
    return repr_of(self, name, names);
  });
}

/// A Map that can be closed (Python's `with` and close()) before it is garbage-collected.
/// Queries run without the GIL, so that other Python threads keep running while the runtime
/// works (a hostile map's query may take seconds before the runtime stops it); the mutex keeps
/// the one SQLite connection to one thread at a time, as the runtime requires.
class PyMap {
 public:
  explicit PyMap(const std::filesystem::path& path) : map_(open_without_gil(path.string())) {}

  /// f(Map&) -> Result<T>, run without the GIL and under the mutex; the value, or the Status
  /// raised as the roadcross exception. f must not touch Python objects.
  template <typename F>
  auto query(F&& f) {
    using ResultType = decltype(f(std::declval<Map&>()));
    std::optional<ResultType> result;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      if (map_) result.emplace(f(*map_));
    }
    if (!result) throw py::value_error("this roadcross.Map is closed");
    return value_or_raise(std::move(*result));
  }

  /// A copy of the map's description (a reference would dangle after close()).
  MapInfo info() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!map_) throw py::value_error("this roadcross.Map is closed");
    return map_->info();
  }
  void close() {
    py::gil_scoped_release release;  // a query in another thread may hold the mutex
    const std::lock_guard<std::mutex> lock(mutex_);
    map_.reset();
  }
  bool closed() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return !map_.has_value();
  }

 private:
  static std::optional<Map> open_without_gil(const std::string& path) {
    Result<Map> opened = [&] {
      py::gil_scoped_release release;
      return Map::open(path);
    }();
    return value_or_raise(std::move(opened));
  }

  std::mutex mutex_;
  std::optional<Map> map_;
};

/// (answer, MapSource) of a set's answer, or the error raised.
template <typename T>
std::pair<T, MapSource> answer_and_source(Result<FromMap<T>>&& result) {
  FromMap<T> answer = value_or_raise(std::move(result));
  return {std::move(answer.answer), std::move(answer.map)};
}

/// A MapSet that can be closed before it is garbage-collected; queries run without the GIL under
/// a mutex, as PyMap's.
class PyMapSet {
 public:
  explicit PyMapSet(const std::vector<std::filesystem::path>& paths)
      : set_(open_without_gil(strings_of(paths))) {}

  /// f(MapSet&) -> Result<FromMap<T>>, run without the GIL and under the mutex; (answer,
  /// MapSource), or the Status raised. f must not touch Python objects.
  template <typename F>
  auto query(F&& f) {
    using ResultType = decltype(f(std::declval<MapSet&>()));
    std::optional<ResultType> result;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      if (set_) result.emplace(f(*set_));
    }
    if (!result) throw py::value_error("this roadcross.MapSet is closed");
    return answer_and_source(std::move(*result));
  }

  /// Copies of every map's description, in the set's order.
  std::vector<MapInfo> infos() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!set_) throw py::value_error("this roadcross.MapSet is closed");
    std::vector<MapInfo> out;
    for (std::size_t i = 0; i < set_->size(); ++i) out.push_back(set_->map(i).info());
    return out;
  }
  std::size_t size() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!set_) throw py::value_error("this roadcross.MapSet is closed");
    return set_->size();
  }
  void close() {
    py::gil_scoped_release release;  // a query in another thread may hold the mutex
    const std::lock_guard<std::mutex> lock(mutex_);
    set_.reset();
  }
  bool closed() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return !set_.has_value();
  }

 private:
  static std::vector<std::string> strings_of(const std::vector<std::filesystem::path>& paths) {
    std::vector<std::string> out;
    for (const auto& path : paths) out.push_back(path.string());
    return out;
  }
  static std::optional<MapSet> open_without_gil(const std::vector<std::string>& paths) {
    Result<MapSet> opened = [&] {
      py::gil_scoped_release release;
      return MapSet::open(paths);
    }();
    return value_or_raise(std::move(opened));
  }

  std::mutex mutex_;
  std::optional<MapSet> set_;
};

AssessOptions assess_options(std::optional<double> valid_distance_m,
                             std::optional<double> threshold, double max_distance_m,
                             std::optional<double> max_kerb_height_m) {
  AssessOptions options;
  options.valid_distance_m = valid_distance_m;
  options.threshold = threshold;
  options.max_distance_m = max_distance_m;
  options.max_kerb_height_m = max_kerb_height_m;
  return options;
}

const char* frame_name(TrackedVehicle::Frame frame) {
  return frame == TrackedVehicle::Frame::utm ? "utm" : "robot_enu";
}

void bind_values(py::module_& m) {
  py::class_<PlanePoint> point(m, "PlanePoint",
                               "A point in the map's UTM zone, metres. Unpacks as "
                               "(easting_m, northing_m).");
  point
      .def(py::init([](double easting_m, double northing_m) {
             return PlanePoint{easting_m, northing_m};
           }),
           py::kw_only(), "easting_m"_a, "northing_m"_a)
      .def_readonly("easting_m", &PlanePoint::easting_m, "UTM easting, metres")
      .def_readonly("northing_m", &PlanePoint::northing_m, "UTM northing, metres")
      .def("__iter__",
           [](const PlanePoint& p) { return py::iter(py::make_tuple(p.easting_m, p.northing_m)); });
  add_repr(point, "PlanePoint", {"easting_m", "northing_m"});

  py::class_<MapInfo> info(m, "MapInfo", "What Map.info says about the open map.");
  info.def_readonly("path", &MapInfo::path, "the file as opened")
      .def_readonly("schema_version", &MapInfo::schema_version,
                    "the map file's schema version (an integer)")
      .def_readonly("tool_version", &MapInfo::tool_version, "roadcross-build version that wrote it")
      .def_property_readonly(
          "map_id",
          [](const MapInfo& i) -> py::object {
            return i.map_id.empty() ? py::object(py::none()) : py::object(py::str(i.map_id));
          },
          "the map's identity: SHA-256 of its content (64 hex digits), None for a map built "
          "before map ids")
      .def_property_readonly(
          "osm_timestamp",
          [](const MapInfo& i) -> py::object {
            return i.osm_timestamp.empty() ? py::object(py::none())
                                           : py::object(py::str(i.osm_timestamp));
          },
          "newest OSM object's timestamp, ISO 8601 UTC; None when the input had none")
      .def_property_readonly(
          "utm_zone", [](const MapInfo& i) { return i.zone.zone; }, "UTM zone number, 1..60")
      .def_property_readonly(
          "utm_northern", [](const MapInfo& i) { return i.zone.northern; },
          "True for the northern hemisphere")
      .def_readonly("epsg", &MapInfo::epsg, "EPSG code of the map's CRS (326zz or 327zz)")
      .def_readonly("segment_count", &MapInfo::segment_count, "number of road segments in the map")
      .def_property_readonly(
          "extent_utm_m",
          [](const MapInfo& i) {
            return py::make_tuple(i.min_easting_m, i.min_northing_m, i.max_easting_m,
                                  i.max_northing_m);
          },
          "(min_easting, min_northing, max_easting, max_northing) of all segments, UTM metres")
      .def_property_readonly(
          "extent_wgs84_deg",
          [](const MapInfo& i) {
            const geo::LatLonBox& b = i.coverage_wgs84;
            return py::make_tuple(b.min_lat_deg, b.min_lon_deg, b.max_lat_deg, b.max_lon_deg);
          },
          "(min_lat, min_lon, max_lat, max_lon) of the segments' UTM extent, WGS84 degrees: "
          "the box a MapSet picks the map by")
      .def_readonly("coverage_stored", &MapInfo::coverage_stored,
                    "True when the map stores its coverage; False for maps written before it "
                    "(computed on open)")
      .def_property_readonly(
          "metadata",
          [](const MapInfo& i) {
            py::dict out;
            for (const auto& [key, value] : i.metadata) out[py::str(key)] = value;
            return out;
          },
          "every row of the map's metadata table (schema version, build parameters, inputs)");
  add_repr(info, "MapInfo", {"path", "schema_version", "utm_zone", "segment_count"});

  py::class_<NearestRoad> road(m, "NearestRoad", "The road centreline nearest to a position.");
  road.def_readonly("segment_id", &NearestRoad::segment_id,
                    "id of the road segment (Map.assess_segment takes it)")
      .def_readonly("osm_way_id", &NearestRoad::osm_way_id,
                    "id of the OSM way the segment comes from")
      .def_readonly("highway", &NearestRoad::highway, "OSM highway=* value")
      .def_readonly("name", &NearestRoad::name, "the way's name; '' when it has none")
      .def_readonly("query", &NearestRoad::query, "the query position in the map's UTM zone")
      .def_readonly("closest", &NearestRoad::closest, "nearest point on the centreline, UTM")
      .def_readonly("distance_m", &NearestRoad::distance_m,
                    "distance from the query to the centreline, metres")
      .def_readonly("segment_length_m", &NearestRoad::segment_length_m, "metres");
  add_repr(road, "NearestRoad", {"segment_id", "osm_way_id", "highway", "name", "distance_m"});

  py::class_<RoadHeading> heading(m, "RoadHeading",
                                  "The road's direction at the nearest point and the heading "
                                  "that crosses it. Yaws are ENU (REP-103: 0 = east, "
                                  "counter-clockwise), radians in (-pi, pi], UTM grid frame.");
  heading.def_readonly("road", &RoadHeading::road, "the NearestRoad")
      .def_readonly("road_heading_rad", &RoadHeading::road_heading_rad,
                    "road direction (the OSM way's drawing direction), ENU grid yaw, radians")
      .def_readonly("crossing_heading_rad", &RoadHeading::crossing_heading_rad,
                    "perpendicular to the road, from the query's side across it, ENU grid yaw, "
                    "radians")
      .def_readonly("road_bearing_deg", &RoadHeading::road_bearing_deg,
                    "compass bearing of the road, degrees [0, 360), grid north")
      .def_readonly("crossing_bearing_deg", &RoadHeading::crossing_bearing_deg,
                    "compass bearing across the road, degrees [0, 360), grid north")
      .def_readonly("convergence_rad", &RoadHeading::convergence_rad,
                    "true_yaw = grid_yaw + convergence_rad, radians")
      .def_readonly("on_centreline", &RoadHeading::on_centreline,
                    "the query is on the centreline: the side is unknown and the right-hand "
                    "normal of the way direction is returned")
      .def_property_readonly(
          "distance_m", [](const RoadHeading& h) { return h.road.distance_m; },
          "distance to the centreline, metres");
  add_repr(heading, "RoadHeading",
           {"road_heading_rad", "crossing_heading_rad", "distance_m", "on_centreline"});

  py::class_<Assessment> assessment(
      m, "Assessment",
      "Is this a place to cross, and why not. Cost terms are None where the map has none (e.g. "
      "no elevation data was given to roadcross-build).");
  assessment.def_readonly("road", &Assessment::road, "the NearestRoad")
      .def_readonly("valid", &Assessment::valid, "within valid_distance_m of a centreline")
      .def_readonly("suitable", &Assessment::suitable,
                    "valid, score + context_score >= threshold, and not forbidden")
      .def_readonly("valid_distance_m", &Assessment::valid_distance_m, "metres, as applied")
      .def_readonly("threshold", &Assessment::threshold, "score threshold, as applied")
      .def_readonly("score", &Assessment::score, "the segment's crossing score, or None")
      .def_readonly("context_score", &Assessment::context_score,
                    "bonus/penalty from the surroundings (designated crossings, ...), or None")
      .def_readonly("rank", &Assessment::rank, "crossing rank, 0..14 (higher is worse), or None")
      .def_readonly("class_cost", &Assessment::class_cost,
                    "road class cost, 0..5 (primary 5 .. unclassified 1), or None")
      .def_readonly("curvature_level", &Assessment::curvature_level,
                    "0..5 (5 = at a junction), or None")
      .def_readonly("curvature_cost", &Assessment::curvature_cost,
                    "0..14, windowed over +-100 m of road, or None")
      .def_readonly("elevation_cost", &Assessment::elevation_cost, "0..9, or None")
      .def_readonly("junction_distance_m", &Assessment::junction_distance_m,
                    "distance along the road to the nearest junction, metres, or None")
      .def_readonly("radius_m", &Assessment::radius_m, "bend radius, metres, or None")
      .def_readonly("crossing_distance_m", &Assessment::crossing_distance_m,
                    "distance to the nearest designated crossing, metres, or None")
      .def_readonly("maxspeed_kmh", &Assessment::maxspeed_kmh, "km/h, or None")
      .def_readonly("width_m", &Assessment::width_m, "carriageway width, metres, or None")
      .def_readonly("lanes", &Assessment::lanes, "number of lanes, or None")
      .def_readonly("landform", &Assessment::landform, "terrain class name, or None")
      .def_readonly("sight_forward_m", &Assessment::sight_forward_m,
                    "sight distance along the way's direction, metres, or None")
      .def_readonly("sight_backward_m", &Assessment::sight_backward_m, "metres, or None")
      .def_readonly("sight_min_m", &Assessment::sight_min_m, "metres, or None")
      .def_readonly("required_sight_m", &Assessment::required_sight_m,
                    "sight distance a crossing needs here, metres, or None")
      .def_readonly("tunnel", &Assessment::tunnel,
                    "True in a tunnel, building passage or covered=yes")
      .def_readonly("kerb", &Assessment::kerb,
                    "kerb=* value of the highest kerb at a crossing within 5 m, or None")
      .def_readonly("kerb_height_m", &Assessment::kerb_height_m,
                    "its height (kerb:height, else the value's usual height), metres, or None")
      .def_readonly("max_kerb_height_m", &Assessment::max_kerb_height_m,
                    "the robot's highest climbable kerb the judgement used, metres")
      .def_readonly("crossing_island", &Assessment::crossing_island,
                    "True: a refuge island (two-stage crossing), False: none, None: unknown")
      .def_readonly("sidewalk_left", &Assessment::sidewalk_left,
                    "pavement left of the OSM way's direction: True, False or None (unknown)")
      .def_readonly("sidewalk_right", &Assessment::sidewalk_right, "the same on the right")
      .def_readonly("robot_side", &Assessment::robot_side,
                    "+1 left of the way's direction, -1 right, 0 unknown (on the centreline)")
      .def_readonly("pavement_far_side", &Assessment::pavement_far_side,
                    "pavement on the far side: True, False (NO_PAVEMENT_FAR_SIDE) or None")
      .def_readonly("override_note", &Assessment::override_note,
                    "the operator's note when an override applies, else ''")
      .def_readonly("reasons", &Assessment::reasons,
                    "reason codes (NEAR_JUNCTION, SHARP_BEND, BUSY_ROAD, TOO_FAR_FROM_ROAD, "
                    "LOW_SCORE, ...); roadcross.describe_reason(code) gives a sentence")
      .def_property_readonly(
          "distance_m", [](const Assessment& a) { return a.road.distance_m; },
          "distance to the road centreline, metres")
      .def_property_readonly(
          "segment_id", [](const Assessment& a) { return a.road.segment_id; }, "road.segment_id")
      .def_property_readonly(
          "osm_way_id", [](const Assessment& a) { return a.road.osm_way_id; }, "road.osm_way_id")
      .def_property_readonly(
          "highway", [](const Assessment& a) { return a.road.highway; },
          "road.highway: OSM highway=* value")
      .def_property_readonly(
          "name", [](const Assessment& a) { return a.road.name; },
          "road.name: '' when the way has none");
  add_repr(assessment, "Assessment",
           {"valid", "suitable", "score", "context_score", "distance_m", "reasons"});

  py::class_<Candidate> candidate(m, "Candidate",
                                  "A place to cross instead, reached by walking along the road "
                                  "on the robot's side.");
  candidate.def_readonly("point", &Candidate::point, "where to stand, UTM")
      .def_readonly("walking_distance_m", &Candidate::walking_distance_m, "metres")
      .def_readonly("segment_id", &Candidate::segment_id, "id of the road segment at that place")
      .def_readonly("suitable", &Candidate::suitable,
                    "suitable by the same rules as Assessment.suitable")
      .def_readonly("score", &Candidate::score, "score + context_score")
      .def_readonly("designated_crossing", &Candidate::designated_crossing,
                    "a designated crossing within 5 m")
      .def_readonly("crossing_heading_rad", &Candidate::crossing_heading_rad,
                    "ENU grid yaw across the road from that side, radians")
      .def_readonly("reasons", &Candidate::reasons,
                    "reason codes at that place, as in Assessment.reasons");
  add_repr(candidate, "Candidate",
           {"point", "walking_distance_m", "suitable", "score", "designated_crossing"});

  py::class_<BetterPlaces> places(m, "BetterPlaces",
                                  "Candidates, best first (suitable, then designated crossings, "
                                  "then score, then walking distance). Iterable; len() is the "
                                  "number of candidates.");
  places.def_readonly("candidates", &BetterPlaces::candidates, "list of Candidate")
      .def_readonly("reason", &BetterPlaces::reason, "why the list is empty, else ''")
      .def("__len__", [](const BetterPlaces& p) { return p.candidates.size(); })
      .def(
          "__iter__",
          [](const BetterPlaces& p) {
            return py::make_iterator(p.candidates.begin(), p.candidates.end());
          },
          py::keep_alive<0, 1>())
      .def("__getitem__", [](const BetterPlaces& p, py::ssize_t i) {
        const auto n = static_cast<py::ssize_t>(p.candidates.size());
        if (i < 0) i += n;
        if (i < 0 || i >= n) throw py::index_error("candidate index out of range");
        return p.candidates[static_cast<std::size_t>(i)];
      });
  add_repr(places, "BetterPlaces", {"candidates", "reason"});

  py::class_<CrossingPlan> plan(m, "CrossingPlan",
                                "A crossing: from start straight across to target (UTM metres).");
  plan.def(py::init(
               [](PlanePoint start, PlanePoint target, double heading_rad, double road_width_m) {
                 return CrossingPlan{start, target, heading_rad, road_width_m};
               }),
           py::kw_only(), "start"_a, "target"_a, "heading_rad"_a, "road_width_m"_a = 0.0)
      .def_readonly("start", &CrossingPlan::start, "where the crossing starts, UTM metres")
      .def_readonly("target", &CrossingPlan::target,
                    "where it ends beyond the far kerb, UTM metres")
      .def_readonly("heading_rad", &CrossingPlan::heading_rad,
                    "ENU grid yaw from start to target, radians")
      .def_readonly("road_width_m", &CrossingPlan::road_width_m, "metres");
  add_repr(plan, "CrossingPlan", {"start", "target", "heading_rad", "road_width_m"});

  py::class_<CrossingProgress> progress(m, "CrossingProgress", "Where the robot is on its plan.");
  progress.def_readonly("progress", &CrossingProgress::progress, "0 at start .. 1 at target")
      .def_readonly("lateral_deviation_m", &CrossingProgress::lateral_deviation_m,
                    "signed, metres: > 0 left of the line start -> target")
      .def_readonly("heading_error_rad", &CrossingProgress::heading_error_rad,
                    "pose yaw minus plan heading, radians (-pi, pi]")
      .def_property_readonly(
          "state", [](const CrossingProgress& p) { return to_string(p.state); },
          "'ON_TRACK', 'DRIFTING', 'LEAVING_CORRIDOR' or 'DONE'");
  add_repr(progress, "CrossingProgress",
           {"state", "progress", "lateral_deviation_m", "heading_error_rad"});

  py::class_<GapCrossing> crossing(m, "GapCrossing",
                                   "The crossing as the gap decision sees it (UTM metres).");
  crossing
      .def(py::init([](PlanePoint start, PlanePoint centre, double heading_rad, double road_width_m,
                       int lanes, double maxspeed_kmh, double convergence_rad,
                       std::optional<double> junction_distance_m,
                       std::optional<double> sight_forward_m,
                       std::optional<double> sight_backward_m, bool refuge_island, int stage) {
             return GapCrossing{
                 start,           centre,           heading_rad,     road_width_m,
                 lanes,           maxspeed_kmh,     convergence_rad, junction_distance_m,
                 sight_forward_m, sight_backward_m, refuge_island,   stage};
           }),
           py::kw_only(), "start"_a, "centre"_a, "heading_rad"_a,
           "road_width_m"_a = GapCrossing{}.road_width_m, "lanes"_a = GapCrossing{}.lanes,
           "maxspeed_kmh"_a = GapCrossing{}.maxspeed_kmh, "convergence_rad"_a = 0.0,
           "junction_distance_m"_a = py::none(), "sight_forward_m"_a = py::none(),
           "sight_backward_m"_a = py::none(), "refuge_island"_a = false, "stage"_a = 1)
      .def_readonly("start", &GapCrossing::start, "where the robot waits")
      .def_readonly("centre", &GapCrossing::centre, "the centreline on the crossing line")
      .def_readonly("heading_rad", &GapCrossing::heading_rad, "ENU grid yaw across, radians")
      .def_readonly("road_width_m", &GapCrossing::road_width_m, "carriageway width, metres")
      .def_readonly("lanes", &GapCrossing::lanes, ">= 1")
      .def_readonly("maxspeed_kmh", &GapCrossing::maxspeed_kmh, "km/h")
      .def_readonly("convergence_rad", &GapCrossing::convergence_rad, "radians")
      .def_readonly("junction_distance_m", &GapCrossing::junction_distance_m,
                    "metres along the road to the nearest junction, or None")
      .def_readonly("sight_forward_m", &GapCrossing::sight_forward_m,
                    "road visible in the OSM way's direction (the DB's sight), metres, or None")
      .def_readonly("sight_backward_m", &GapCrossing::sight_backward_m,
                    "road visible against the way's direction, metres, or None")
      .def_readonly("refuge_island", &GapCrossing::refuge_island,
                    "True: two stages, each over half the lanes, with a wait on the island")
      .def_readonly("stage", &GapCrossing::stage,
                    "with an island: 1 = kerb to island (near lanes), 2 = island to far kerb");
  add_repr(crossing, "GapCrossing",
           {"start", "heading_rad", "road_width_m", "lanes", "maxspeed_kmh"});

  py::class_<TrackedVehicle> vehicle(
      m, "Vehicle",
      "One tracked vehicle. Position and velocity in the map's UTM grid (easting=, northing=) or "
      "in the robot's ENU frame (east_m=, north_m=: true east/north offsets from the crossing "
      "start).");
  vehicle
      .def(py::init([](std::optional<double> easting, std::optional<double> northing,
                       std::optional<double> east_m, std::optional<double> north_m, double vx_mps,
                       double vy_mps, double length_m, std::optional<double> speed_uncertainty_mps,
                       double time_s) {
             TrackedVehicle v;
             const bool utm = easting || northing;
             const bool enu = east_m || north_m;
             if (utm == enu) {
               throw py::type_error(
                   "give easting= and northing= (UTM) or east_m= and north_m= (robot ENU)");
             }
             if (utm) {
               if (!easting || !northing) throw py::type_error("give both easting= and northing=");
               v.frame = TrackedVehicle::Frame::utm;
               v.x_m = *easting;
               v.y_m = *northing;
             } else {
               if (!east_m || !north_m) throw py::type_error("give both east_m= and north_m=");
               v.frame = TrackedVehicle::Frame::robot_enu;
               v.x_m = *east_m;
               v.y_m = *north_m;
             }
             v.vx_mps = vx_mps;
             v.vy_mps = vy_mps;
             v.length_m = length_m;
             v.speed_uncertainty_mps = speed_uncertainty_mps;
             v.time_s = time_s;
             return v;
           }),
           py::kw_only(), "easting"_a = py::none(), "northing"_a = py::none(),
           "east_m"_a = py::none(), "north_m"_a = py::none(), "vx_mps"_a, "vy_mps"_a,
           "length_m"_a = TrackedVehicle{}.length_m, "speed_uncertainty_mps"_a = py::none(),
           "time_s"_a = 0.0,
           "vx_mps, vy_mps: velocity, m/s (same frame as the position); length_m: > 0, metres; "
           "speed_uncertainty_mps: +- m/s (None: GapOptions' fraction of the speed); time_s: "
           "when it was observed, seconds on the clock of gap_decision's now_s")
      .def_property_readonly(
          "frame", [](const TrackedVehicle& v) { return frame_name(v.frame); },
          "'utm' or 'robot_enu'")
      .def_readonly("x_m", &TrackedVehicle::x_m, "easting (utm) or east offset (robot_enu), m")
      .def_readonly("y_m", &TrackedVehicle::y_m, "northing (utm) or north offset (robot_enu), m")
      .def_readonly("vx_mps", &TrackedVehicle::vx_mps, "velocity east (frame as x_m), m/s")
      .def_readonly("vy_mps", &TrackedVehicle::vy_mps, "velocity north (frame as y_m), m/s")
      .def_readonly("length_m", &TrackedVehicle::length_m, "vehicle length, metres, > 0")
      .def_readonly("speed_uncertainty_mps", &TrackedVehicle::speed_uncertainty_mps,
                    "+- m/s, or None: GapOptions' fraction of the speed")
      .def_readonly("time_s", &TrackedVehicle::time_s,
                    "when it was observed, seconds on the clock of now_s");
  add_repr(vehicle, "Vehicle", {"frame", "x_m", "y_m", "vx_mps", "vy_mps", "time_s"});

  py::class_<GapDecision> decision(m, "GapDecision", "GO or WAIT, and why.");
  decision
      .def_property_readonly(
          "verdict", [](const GapDecision& d) { return to_string(d.verdict); }, "'GO' or 'WAIT'")
      .def_property_readonly(
          "go", [](const GapDecision& d) { return d.verdict == GapVerdict::go; },
          "True when the robot may start now")
      .def_property_readonly(
          "reason", [](const GapDecision& d) { return to_string(d.reason); },
          "'CLEAR', 'VEHICLE_CONFLICT', 'BLOCKED', 'INSUFFICIENT_SIGHT', 'STALE_TRACK' or "
          "'GAP_TOO_SHORT'")
      .def_readonly("limiting_vehicle", &GapDecision::limiting_vehicle,
                    "index into the vehicles; -1: none, or the unseen vehicle")
      .def_readonly("margin_s", &GapDecision::margin_s,
                    "smallest predicted PET if starting now, seconds, or None")
      .def_readonly("earliest_start_s", &GapDecision::earliest_start_s,
                    "earliest GO time on the now_s clock, seconds, or None (never)")
      .def_readonly("stage", &GapDecision::stage,
                    "0: one-stage crossing; 1 or 2: the stage of a two-stage crossing decided")
      .def_readonly("crossing_time_s", &GapDecision::crossing_time_s, "seconds (of the stage)")
      .def_readonly("required_sight_m", &GapDecision::required_sight_m, "metres each way")
      .def_readonly("visible_road_m", &GapDecision::visible_road_m,
                    "road seen each way: sensor range cut by the sight distances, metres")
      .def_readonly("critical_gap_s", &GapDecision::critical_gap_s, "HCM t_c, seconds (HCM only)")
      .def_readonly("vehicles_counted", &GapDecision::vehicles_counted,
                    "vehicles that will still reach the crossing, count")
      .def_readonly("stale_tracks", &GapDecision::stale_tracks,
                    "tracks older than max_track_age_s, count")
      .def_readonly("beyond_sensor_range", &GapDecision::beyond_sensor_range,
                    "tracks farther than sensor_range_m (still counted), count");
  add_repr(decision, "GapDecision",
           {"verdict", "reason", "limiting_vehicle", "margin_s", "earliest_start_s"});
}

void bind_map(py::module_& m) {
  py::class_<PyMap>(m, "Map",
                    "A roadcross map (GeoPackage written by roadcross-build), opened read-only.\n\n"
                    "Map(path) raises MapNotFoundError (a FileNotFoundError), "
                    "NotARoadcrossMapError or WrongVersionError (ValueErrors). One Map is one "
                    "SQLite connection: use one Map per thread. Replace a map file by renaming a "
                    "new file over it, then open a new Map; never rewrite it in place while a "
                    "Map has it open. Usable as a context manager (closes on exit).")
      .def(py::init<const std::filesystem::path&>(), "path"_a,
           "path: the map file (str or os.PathLike)")
      .def_property_readonly(
          "info",
          // A copy: a reference into the Map would dangle after close().
          [](PyMap& self) { return self.info(); },
          "MapInfo: UTM zone, extent, segment count, metadata")
      .def_property_readonly("closed", &PyMap::closed,
                             "True after close() or the end of the with block")
      .def("close", &PyMap::close, "Close the map now; later queries raise ValueError.")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__",
           [](PyMap& self, const py::object&, const py::object&, const py::object&) {
             self.close();
             return false;
           })
      .def(
          "to_utm",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing) {
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) { return map.to_utm(position); });
          },
          ROADCROSS_POSITION_ARGS,
          "The position in the map's UTM zone (PlanePoint, metres).\n" ROADCROSS_POSITION_DOC)
      .def(
          "nearest",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing, double max_distance_m) {
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) { return map.nearest(position, max_distance_m); });
          },
          ROADCROSS_POSITION_ARGS, "max_distance_m"_a = 1000.0,
          "The nearest road centreline (NearestRoad).\n" ROADCROSS_POSITION_DOC
          "max_distance_m: search radius, metres, > 0; NoRoadError when no road is that near.")
      .def(
          "assess",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing,
             std::optional<double> valid_distance_m, std::optional<double> threshold,
             double max_distance_m, std::optional<double> max_kerb_height_m) {
            const Position position = position_from(lat, lon, easting, northing);
            const AssessOptions options =
                assess_options(valid_distance_m, threshold, max_distance_m, max_kerb_height_m);
            return self.query([&](Map& map) { return map.assess(position, options); });
          },
          ROADCROSS_POSITION_ARGS, "valid_distance_m"_a = py::none(), "threshold"_a = py::none(),
          "max_distance_m"_a = AssessOptions{}.max_distance_m, "max_kerb_height_m"_a = py::none(),
          "Is this a suitable place to cross (Assessment).\n" ROADCROSS_POSITION_DOC
          "valid_distance_m: valid within this distance of a centreline, metres (None: the "
          "map's, 10 m by default); threshold: suitable when score + context_score >= this "
          "(None: the map's); max_distance_m: how far to look for a road, metres, > 0; "
          "max_kerb_height_m: the highest kerb the robot climbs, metres, >= 0 (None: the map "
          "profile's; a known higher kerb is KERB_TOO_HIGH, an unknown one never forbids).")
      .def(
          "assess_segment",
          [](PyMap& self, std::int64_t segment_id, std::optional<double> valid_distance_m,
             std::optional<double> threshold, std::optional<double> max_kerb_height_m) {
            const AssessOptions options =
                assess_options(valid_distance_m, threshold, 1000.0, max_kerb_height_m);
            return self.query([&](Map& map) { return map.assess_segment(segment_id, options); });
          },
          "segment_id"_a, py::kw_only(), "valid_distance_m"_a = py::none(),
          "threshold"_a = py::none(), "max_kerb_height_m"_a = py::none(),
          "The assessment on the centreline of one segment (distance 0); NoRoadError when there "
          "is no such segment. Thresholds as in assess.")
      .def(
          "better_place",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing, double search_radius_m,
             std::size_t max_candidates, std::optional<double> valid_distance_m,
             std::optional<double> threshold, std::optional<double> max_kerb_height_m) {
            BetterPlaceOptions options;
            options.search_radius_m = search_radius_m;
            options.max_candidates = max_candidates;
            options.assess = assess_options(valid_distance_m, threshold, 1000.0, max_kerb_height_m);
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) { return map.better_place(position, options); });
          },
          ROADCROSS_POSITION_ARGS, "search_radius_m"_a = BetterPlaceOptions{}.search_radius_m,
          "max_candidates"_a = BetterPlaceOptions{}.max_candidates,
          "valid_distance_m"_a = py::none(), "threshold"_a = py::none(),
          "max_kerb_height_m"_a = py::none(),
          "Better places to cross nearby, reached by walking along the road on the robot's side "
          "(BetterPlaces).\n" ROADCROSS_POSITION_DOC
          "search_radius_m: walking distance, metres, > 0; max_candidates: at most this many; "
          "thresholds as in assess.")
      .def(
          "road_heading",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing, double max_distance_m) {
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) { return map.road_heading(position, max_distance_m); });
          },
          ROADCROSS_POSITION_ARGS, "max_distance_m"_a = 1000.0,
          "The road's direction and the crossing heading (RoadHeading; ENU grid yaws, "
          "radians).\n" ROADCROSS_POSITION_DOC "max_distance_m: search radius, metres, > 0.")
      .def(
          "plan_crossing",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing, double default_width_m,
             double kerb_margin_m) {
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) {
              return plan_crossing(map, position, default_width_m, kerb_margin_m);
            });
          },
          ROADCROSS_POSITION_ARGS, "default_width_m"_a = 6.0, "kerb_margin_m"_a = 0.5,
          "A CrossingPlan from this position straight across the road, to half the road width "
          "(the map's width_m, else default_width_m, metres) plus kerb_margin_m (metres) beyond "
          "the centreline. For roadcross.monitor.\n" ROADCROSS_POSITION_DOC)
      .def(
          "gap_crossing",
          [](PyMap& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing, double default_width_m,
             double default_lane_width_m, double default_maxspeed_kmh) {
            GapCrossingDefaults defaults;
            defaults.width_m = default_width_m;
            defaults.lane_width_m = default_lane_width_m;
            defaults.maxspeed_kmh = default_maxspeed_kmh;
            const Position position = position_from(lat, lon, easting, northing);
            return self.query([&](Map& map) { return gap_crossing(map, position, defaults); });
          },
          ROADCROSS_POSITION_ARGS, "default_width_m"_a = GapCrossingDefaults{}.width_m,
          "default_lane_width_m"_a = GapCrossingDefaults{}.lane_width_m,
          "default_maxspeed_kmh"_a = GapCrossingDefaults{}.maxspeed_kmh,
          "The GapCrossing at this position (start, heading, lanes, width, maxspeed from the "
          "map; the defaults where it has none: width metres, lane width metres, km/h). For "
          "roadcross.gap_decision.\n" ROADCROSS_POSITION_DOC)
      .def("__repr__", [](PyMap& self) {
        if (self.closed()) return std::string("roadcross.Map(<closed>)");
        return "roadcross.Map(" + py::repr(py::str(self.info().path)).cast<std::string>() + ")";
      });
}

#define ROADCROSS_SET_POSITION_ARGS ROADCROSS_POSITION_ARGS, py::arg("utm_zone") = py::none()
#define ROADCROSS_SET_POSITION_DOC                                                          \
  "Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting, "  \
  "northing: UTM metres with utm_zone, the zone as '33N' or '34S' (required: a set's maps " \
  "may lie in several zones). Returns (answer, MapSource): the answer of the map whose "    \
  "road is nearest among the maps that cover the position, and which map that is.\n"

void bind_map_set(py::module_& m) {
  py::class_<MapSource> source(m, "MapSource", "Which map of a MapSet answered.");
  source.def_readonly("index", &MapSource::index, "position of the map in the set, from 0")
      .def_readonly("path", &MapSource::path, "the map's file, as opened")
      .def_property_readonly(
          "map_id",
          [](const MapSource& s) -> std::optional<std::string> {
            if (s.map_id.empty()) return std::nullopt;
            return s.map_id;
          },
          "the map's identifier (metadata map_id), None when it has none");
  add_repr(source, "MapSource", {"index", "path", "map_id"});

  py::class_<PyMapSet>(m, "MapSet",
                       "Several roadcross maps answered as one (a fleet's area in several files "
                       "or UTM zones).\n\n"
                       "MapSet(paths): each path a map file or a directory of maps (every file "
                       "in it must be a map). Raises like Map(path), naming the file at fault. "
                       "One MapSet per thread. Usable as a context manager (closes on exit).")
      .def(py::init<const std::vector<std::filesystem::path>&>(), "paths"_a,
           "paths: map files and directories of maps (str or os.PathLike each)")
      .def("__len__", [](PyMapSet& self) { return self.size(); })
      .def_property_readonly(
          "maps",
          [](PyMapSet& self) { return self.infos(); },
          "MapInfo of every map, in the set's order (a directory's maps by name)")
      .def_property_readonly("closed", &PyMapSet::closed,
                             "True after close() or the end of the with block")
      .def("close", &PyMapSet::close, "Close every map now; later queries raise ValueError.")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__",
           [](PyMapSet& self, const py::object&, const py::object&, const py::object&) {
             self.close();
             return false;
           })
      .def(
          "nearest",
          [](PyMapSet& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing,
             std::optional<std::string> utm_zone, double max_distance_m) {
            const Position position = zoned_position_from(lat, lon, easting, northing, utm_zone);
            return self.query([&](MapSet& set) { return set.nearest(position, max_distance_m); });
          },
          ROADCROSS_SET_POSITION_ARGS, "max_distance_m"_a = 1000.0,
          "Map.nearest over the set: (NearestRoad, MapSource).\n" ROADCROSS_SET_POSITION_DOC
          "max_distance_m: search radius, metres, > 0; NoRoadError when no map has a road that "
          "near.")
      .def(
          "assess",
          [](PyMapSet& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing,
             std::optional<std::string> utm_zone, std::optional<double> valid_distance_m,
             std::optional<double> threshold, double max_distance_m,
             std::optional<double> max_kerb_height_m) {
            const Position position = zoned_position_from(lat, lon, easting, northing, utm_zone);
            const AssessOptions options =
                assess_options(valid_distance_m, threshold, max_distance_m, max_kerb_height_m);
            return self.query([&](MapSet& set) { return set.assess(position, options); });
          },
          ROADCROSS_SET_POSITION_ARGS, "valid_distance_m"_a = py::none(),
          "threshold"_a = py::none(), "max_distance_m"_a = AssessOptions{}.max_distance_m,
          "max_kerb_height_m"_a = py::none(),
          "Map.assess over the set: (Assessment, MapSource).\n" ROADCROSS_SET_POSITION_DOC
          "Thresholds and max_distance_m as in Map.assess.")
      .def(
          "better_place",
          [](PyMapSet& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing,
             std::optional<std::string> utm_zone, double search_radius_m,
             std::size_t max_candidates, std::optional<double> valid_distance_m,
             std::optional<double> threshold, std::optional<double> max_kerb_height_m) {
            BetterPlaceOptions options;
            options.search_radius_m = search_radius_m;
            options.max_candidates = max_candidates;
            options.assess = assess_options(valid_distance_m, threshold, 1000.0, max_kerb_height_m);
            const Position position = zoned_position_from(lat, lon, easting, northing, utm_zone);
            return self.query([&](MapSet& set) { return set.better_place(position, options); });
          },
          ROADCROSS_SET_POSITION_ARGS, "search_radius_m"_a = BetterPlaceOptions{}.search_radius_m,
          "max_candidates"_a = BetterPlaceOptions{}.max_candidates,
          "valid_distance_m"_a = py::none(), "threshold"_a = py::none(),
          "max_kerb_height_m"_a = py::none(),
          "Map.better_place over the set: (BetterPlaces, MapSource).\n" ROADCROSS_SET_POSITION_DOC
          "Options as in Map.better_place.")
      .def(
          "road_heading",
          [](PyMapSet& self, std::optional<double> lat, std::optional<double> lon,
             std::optional<double> easting, std::optional<double> northing,
             std::optional<std::string> utm_zone, double max_distance_m) {
            const Position position = zoned_position_from(lat, lon, easting, northing, utm_zone);
            return self.query(
                [&](MapSet& set) { return set.road_heading(position, max_distance_m); });
          },
          ROADCROSS_SET_POSITION_ARGS, "max_distance_m"_a = 1000.0,
          "Map.road_heading over the set: (RoadHeading, MapSource).\n" ROADCROSS_SET_POSITION_DOC
          "max_distance_m: search radius, metres, > 0.")
      .def("__repr__", [](PyMapSet& self) {
        if (self.closed()) return std::string("roadcross.MapSet(<closed>)");
        return "roadcross.MapSet(<" + std::to_string(self.size()) + " maps>)";
      });
}

GapOptions gap_options(double min_pet_s, double safety_buffer_m, double speed_uncertainty_fraction,
                       double stopped_speed_mps, double max_track_age_s, double sensor_range_m,
                       double unseen_speed_factor, double turning_speed_kmh) {
  GapOptions o;
  o.min_pet_s = min_pet_s;
  o.safety_buffer_m = safety_buffer_m;
  o.speed_uncertainty_fraction = speed_uncertainty_fraction;
  o.stopped_speed_mps = stopped_speed_mps;
  o.max_track_age_s = max_track_age_s;
  o.sensor_range_m = sensor_range_m;
  o.unseen_speed_factor = unseen_speed_factor;
  o.turning_speed_kmh = turning_speed_kmh;
  return o;
}

#define ROADCROSS_GAP_ARGS                                                                     \
  "now_s"_a, "speed_mps"_a = RobotMotion{}.speed_mps, "startup_s"_a = RobotMotion{}.startup_s, \
             "radius_m"_a = RobotMotion{}.radius_m, "min_pet_s"_a = GapOptions{}.min_pet_s,    \
             "safety_buffer_m"_a = GapOptions{}.safety_buffer_m,                               \
             "speed_uncertainty_fraction"_a = GapOptions{}.speed_uncertainty_fraction,         \
             "stopped_speed_mps"_a = GapOptions{}.stopped_speed_mps,                           \
             "max_track_age_s"_a = GapOptions{}.max_track_age_s,                               \
             "sensor_range_m"_a = GapOptions{}.sensor_range_m,                                 \
             "unseen_speed_factor"_a = GapOptions{}.unseen_speed_factor,                       \
             "turning_speed_kmh"_a = GapOptions{}.turning_speed_kmh
#define ROADCROSS_GAP_DOC                                                                      \
  "crossing: a GapCrossing (Map.gap_crossing); vehicles: a list of Vehicle; now_s: the "       \
  "current time, seconds, same clock as Vehicle.time_s. The robot: speed_mps (crossing "       \
  "speed, m/s, > 0), startup_s (seconds, >= 0), radius_m (half footprint, metres). Options: "  \
  "min_pet_s (seconds), safety_buffer_m (metres), speed_uncertainty_fraction (>= 0), "         \
  "stopped_speed_mps (m/s), max_track_age_s (seconds), sensor_range_m (metres, > 0), "         \
  "unseen_speed_factor (x maxspeed), turning_speed_kmh (km/h). InvalidArgumentError for NaN, " \
  "a timestamp after now_s, or out-of-range values."

void bind_functions(py::module_& m) {
  m.def(
      "monitor",
      [](const CrossingPlan& plan, double easting, double northing, double yaw_rad, double drift_m,
         double corridor_half_width_m, double heading_tolerance_rad, double done_margin_m) {
        MonitorOptions options;
        options.drift_m = drift_m;
        options.corridor_half_width_m = corridor_half_width_m;
        options.heading_tolerance_rad = heading_tolerance_rad;
        options.done_margin_m = done_margin_m;
        return value_or_raise(monitor(plan, Pose{{easting, northing}, yaw_rad}, options));
      },
      "plan"_a, py::kw_only(), "easting"_a, "northing"_a, "yaw_rad"_a,
      "drift_m"_a = MonitorOptions{}.drift_m,
      "corridor_half_width_m"_a = MonitorOptions{}.corridor_half_width_m,
      "heading_tolerance_rad"_a = MonitorOptions{}.heading_tolerance_rad,
      "done_margin_m"_a = MonitorOptions{}.done_margin_m,
      "Progress of the robot on a CrossingPlan (CrossingProgress). Pure computation, no map "
      "access.\neasting, northing: the robot's UTM position, metres; yaw_rad: its ENU grid yaw, "
      "radians (any value). drift_m: DRIFTING beyond this lateral deviation, metres; "
      "corridor_half_width_m: LEAVING_CORRIDOR beyond this, metres; heading_tolerance_rad: "
      "DRIFTING beyond this heading error, radians; done_margin_m: DONE within this of the "
      "target, metres.");
  m.def(
      "gap_decision",
      [](const GapCrossing& crossing, const std::vector<TrackedVehicle>& vehicles, double now_s,
         double speed_mps, double startup_s, double radius_m, double min_pet_s,
         double safety_buffer_m, double speed_uncertainty_fraction, double stopped_speed_mps,
         double max_track_age_s, double sensor_range_m, double unseen_speed_factor,
         double turning_speed_kmh) {
        const RobotMotion robot{speed_mps, startup_s, radius_m};
        return value_or_raise(gap_decision(
            crossing, robot, vehicles, now_s,
            gap_options(min_pet_s, safety_buffer_m, speed_uncertainty_fraction, stopped_speed_mps,
                        max_track_age_s, sensor_range_m, unseen_speed_factor, turning_speed_kmh)));
      },
      "crossing"_a, "vehicles"_a, py::kw_only(), ROADCROSS_GAP_ARGS,
      "May the robot start crossing now (GapDecision)? GO when every vehicle's predicted "
      "post-encroachment time is at least min_pet_s, no track is stale and the road is seen far "
      "enough (docs/runtime.md, Gap acceptance).\n" ROADCROSS_GAP_DOC);
  m.def(
      "hcm_gap_decision",
      [](const GapCrossing& crossing, const std::vector<TrackedVehicle>& vehicles, double now_s,
         double speed_mps, double startup_s, double radius_m, double min_pet_s,
         double safety_buffer_m, double speed_uncertainty_fraction, double stopped_speed_mps,
         double max_track_age_s, double sensor_range_m, double unseen_speed_factor,
         double turning_speed_kmh, double start_clearance_s) {
        const RobotMotion robot{speed_mps, startup_s, radius_m};
        HcmOptions hcm;
        hcm.start_clearance_s = start_clearance_s;
        return value_or_raise(hcm_gap_decision(
            crossing, robot, vehicles, now_s,
            gap_options(min_pet_s, safety_buffer_m, speed_uncertainty_fraction, stopped_speed_mps,
                        max_track_age_s, sensor_range_m, unseen_speed_factor, turning_speed_kmh),
            hcm));
      },
      "crossing"_a, "vehicles"_a, py::kw_only(), ROADCROSS_GAP_ARGS,
      "start_clearance_s"_a = HcmOptions{}.start_clearance_s,
      "The HCM reference policy (GapDecision): GO when no vehicle is in the crossing and the "
      "next one arrives no sooner than the critical gap t_c = width / speed_mps + "
      "start_clearance_s (seconds).\n" ROADCROSS_GAP_DOC);
  m.def(
      "sight_distance_m",
      [](const Assessment& assessment, double sensor_range_m, double clearance_m) {
        return sight_distance_m(assessment, sensor_range_m, clearance_m);
      },
      "assessment"_a, py::kw_only(), "sensor_range_m"_a = GapOptions{}.sensor_range_m,
      "clearance_m"_a = 3.0,
      "How far along the road the robot can see at an assessed place, metres: the sensor range "
      "(metres), cut at a bend by an obstruction clearance_m (metres) inside the curve.");
  m.def(
      "describe_reason", [](const std::string& code) { return std::string(describe_reason(code)); },
      "code"_a, "A sentence for a reason code (e.g. 'SHARP_BEND'), for people.");
}

}  // namespace
}  // namespace roadcross::python

PYBIND11_MODULE(roadcross, m) {
  m.doc() =
      "roadcross: where and how a pavement robot may cross a road.\n\n"
      "m = roadcross.Map('map.gpkg'); a = m.assess(lat=50.0757, lon=14.4160)\n"
      "Yaws are ENU (REP-103) radians in the map's UTM grid frame; distances in metres. Errors "
      "are roadcross.Error subclasses carrying the runtime's message. See docs/embedding.md.";
  m.attr("__version__") = roadcross::kVersion;
  roadcross::python::add_error_classes(m);
  roadcross::python::bind_values(m);
  roadcross::python::bind_map(m);
  roadcross::python::bind_map_set(m);
  roadcross::python::bind_functions(m);
}
