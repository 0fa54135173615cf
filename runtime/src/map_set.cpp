#include "roadcross/map_set.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>

namespace roadcross {

namespace {

template <typename T>
Result<T> fail(StatusCode code, std::string message) {
  return Result<T>{Status{code, std::move(message)}, std::nullopt};
}

/// Metres per degree of latitude, rounded down (110 574 m at the equator, more towards the
/// poles), so that a margin in degrees computed with it is never too small.
constexpr double kMinMetresPerDegreeLat = 110'000.0;
/// Metres per degree of longitude at the equator, rounded up (111 320 m): divided by the
/// cosine of the latitude, it gives a margin in degrees that is never too small.
constexpr double kMaxMetresPerDegreeLonAtEquator = 111'400.0;

/// The files a path names: itself, or a directory's entries that are not directories, by name.
Status expand(const std::string& path, std::vector<std::string>& files) {
  std::error_code error;
  if (!std::filesystem::is_directory(path, error)) {
    files.push_back(path);
    return {};
  }
  std::vector<std::string> entries;
  for (std::filesystem::directory_iterator it(path, error), end; !error && it != end;
       it.increment(error)) {
    std::error_code type_error;
    if (!it->is_directory(type_error)) entries.push_back(it->path().string());
  }
  if (error) {
    return {StatusCode::file_not_found,
            path + ": cannot list the map directory: " + error.message()};
  }
  if (entries.empty()) {
    return {StatusCode::file_not_found, path + ": the map directory holds no file"};
  }
  std::sort(entries.begin(), entries.end());
  files.insert(files.end(), entries.begin(), entries.end());
  return {};
}

}  // namespace

/// A map and where it is: its coverage in both coordinate systems, read once on open.
struct MapSet::Impl {
  std::vector<Map> maps;

  /// A covering map and the position in its grid.
  struct Candidate {
    std::size_t index = 0;
    Position in_zone;
  };
  std::vector<Candidate> candidates;  // reused by every query: no allocation per query

  /// The position as latitude/longitude, or invalid_argument.
  static Status to_lat_lon(const Position& position, geo::LatLon& out) noexcept;
  /// Fills `candidates` with the maps whose extent grown by search_m holds the position.
  Status find_candidates(const Position& position, double search_m) noexcept;
};

Status MapSet::Impl::to_lat_lon(const Position& position, geo::LatLon& out) noexcept {
  if (!std::isfinite(position.first) || !std::isfinite(position.second)) {
    return {StatusCode::invalid_argument, "position has a NaN or infinite coordinate"};
  }
  if (position.kind == Position::Kind::wgs84) {
    if (!geo::is_valid_utm_lat_lon(position.first, position.second)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "lat %.7f lon %.7f is outside the UTM domain (lat -80..84, lon -180..180)",
                    position.first, position.second);
      return {StatusCode::invalid_argument, text};
    }
    out = {position.first, position.second};
    return {};
  }
  if (position.zone.zone == 0) {
    return {StatusCode::invalid_argument,
            "a UTM position without its zone is ambiguous in a map set (its maps may lie in "
            "several zones): give the position as lat/lon, or with its zone"};
  }
  if (position.zone.zone < 1 || position.zone.zone > 60) {
    return {StatusCode::invalid_argument,
            "UTM zone " + std::to_string(position.zone.zone) + " is not in 1..60"};
  }
  try {
    out = geo::utm_to_wgs84(position.first, position.second, position.zone);
    return {};
  } catch (const std::exception& e) {
    return {StatusCode::invalid_argument, e.what()};
  }
}

Status MapSet::Impl::find_candidates(const Position& position, double search_m) noexcept {
  candidates.clear();
  if (!(search_m >= 0.0)) return {StatusCode::invalid_argument, "the search distance must be >= 0"};
  geo::LatLon ll;
  Status status = to_lat_lon(position, ll);
  if (!status.ok()) return status;
  const double margin_lat_deg = search_m / kMinMetresPerDegreeLat;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const MapInfo& info = maps[i].info();
    const geo::LatLonBox& box = info.coverage_wgs84;
    // The box's latitude farthest from the equator has the shortest degree of longitude.
    const double far_lat_deg = std::min(
        89.0, std::max(std::abs(box.min_lat_deg), std::abs(box.max_lat_deg)) + margin_lat_deg);
    const double margin_lon_deg =
        search_m / (kMaxMetresPerDegreeLonAtEquator * std::cos(geo::deg_to_rad(far_lat_deg)));
    if (ll.lat_deg < box.min_lat_deg - margin_lat_deg ||
        ll.lat_deg > box.max_lat_deg + margin_lat_deg ||
        ll.lon_deg < box.min_lon_deg - margin_lon_deg ||
        ll.lon_deg > box.max_lon_deg + margin_lon_deg) {
      continue;
    }
    geo::UtmPoint p;
    try {
      p = geo::wgs84_to_utm(ll.lat_deg, ll.lon_deg, info.zone);
    } catch (const std::exception&) {
      continue;  // too far from the map's zone to be in it
    }
    if (p.easting_m < info.min_easting_m - search_m ||
        p.easting_m > info.max_easting_m + search_m ||
        p.northing_m < info.min_northing_m - search_m ||
        p.northing_m > info.max_northing_m + search_m) {
      continue;
    }
    // The uncertainty goes with the position: a circular or ENU one means the same in every
    // map's grid (the map turns ENU into its grid at the position).
    Position in_zone = Position::utm(p.easting_m, p.northing_m, info.zone);
    in_zone.uncertainty = position.uncertainty;
    candidates.push_back({i, in_zone});
  }
  if (candidates.empty()) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "no map of the set (%zu maps) covers lat %.7f lon %.7f within %g m", maps.size(),
                  ll.lat_deg, ll.lon_deg, search_m);
    return {StatusCode::not_found, text};
  }
  return {};
}

std::optional<geo::UtmZone> parse_utm_zone(const std::string& text) noexcept {
  if (text.empty()) return std::nullopt;
  std::size_t digits = 0;
  while (digits < text.size() && digits < 2 &&
         std::isdigit(static_cast<unsigned char>(text[digits])))
    ++digits;
  if (digits == 0) return std::nullopt;
  const int zone = (digits == 1 ? text[0] - '0' : (text[0] - '0') * 10 + (text[1] - '0'));
  const std::string_view hemisphere = std::string_view(text).substr(digits);
  if (zone < 1 || zone > 60) return std::nullopt;
  if (hemisphere.empty() || hemisphere == "N" || hemisphere == "n") return geo::UtmZone{zone, true};
  if (hemisphere == "S" || hemisphere == "s") return geo::UtmZone{zone, false};
  return std::nullopt;
}

MapSet::MapSet(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
MapSet::MapSet(MapSet&&) noexcept = default;
MapSet& MapSet::operator=(MapSet&&) noexcept = default;
MapSet::~MapSet() = default;

Result<MapSet> MapSet::open(const std::vector<std::string>& paths) noexcept {
  try {
    if (paths.empty()) return fail<MapSet>(StatusCode::invalid_argument, "no map given");
    std::vector<std::string> files;
    for (const std::string& path : paths) {
      Status status = expand(path, files);
      if (!status.ok()) return Result<MapSet>{std::move(status), std::nullopt};
    }
    auto impl = std::make_unique<Impl>();
    impl->maps.reserve(files.size());
    for (const std::string& file : files) {
      Result<Map> map = Map::open(file);
      if (!map.ok()) return Result<MapSet>{std::move(map.status), std::nullopt};
      impl->maps.push_back(std::move(*map.value));
    }
    impl->candidates.reserve(impl->maps.size());
    return Result<MapSet>{Status{}, MapSet(std::move(impl))};
  } catch (const std::exception& e) {
    return fail<MapSet>(StatusCode::internal, e.what());
  }
}

std::size_t MapSet::size() const noexcept {
  return impl_->maps.size();
}

Map& MapSet::map(std::size_t index) noexcept {
  return impl_->maps[index];
}

const Map& MapSet::map(std::size_t index) const noexcept {
  return impl_->maps[index];
}

MapSource MapSet::source(std::size_t index) const {
  const MapInfo& info = impl_->maps[index].info();
  return {index, info.path, info.map_id};
}

Result<std::vector<std::size_t>> MapSet::covering(const Position& position,
                                                  double search_m) noexcept {
  try {
    Status status = impl_->find_candidates(position, search_m);
    std::vector<std::size_t> indexes;
    if (status.code == StatusCode::not_found) status = {};
    if (!status.ok()) return fail<std::vector<std::size_t>>(status.code, status.message);
    for (const Impl::Candidate& c : impl_->candidates) indexes.push_back(c.index);
    return Result<std::vector<std::size_t>>{Status{}, std::move(indexes)};
  } catch (const std::exception& e) {
    return fail<std::vector<std::size_t>>(StatusCode::internal, e.what());
  }
}

Result<std::size_t> MapSet::answering_candidate(const Position& position,
                                                double max_distance_m) noexcept {
  if (!(max_distance_m > 0.0)) {
    return fail<std::size_t>(StatusCode::invalid_argument, "max_distance_m must be > 0");
  }
  Status status = impl_->find_candidates(position, max_distance_m);
  if (!status.ok()) return Result<std::size_t>{std::move(status), std::nullopt};
  if (impl_->candidates.size() == 1) {
    return Result<std::size_t>{Status{}, std::size_t{0}};
  }
  // Overlapping maps: the nearest road of all of them decides (the earlier map on a tie).
  std::size_t best = 0;
  double best_distance_m = std::numeric_limits<double>::infinity();
  Status last_not_found;
  for (std::size_t c = 0; c < impl_->candidates.size(); ++c) {
    const Impl::Candidate& candidate = impl_->candidates[c];
    Result<NearestRoad> road =
        impl_->maps[candidate.index].nearest(candidate.in_zone, max_distance_m);
    if (road.status.code == StatusCode::not_found) {
      last_not_found = std::move(road.status);
      continue;
    }
    if (!road.ok()) return Result<std::size_t>{std::move(road.status), std::nullopt};
    if (road->distance_m < best_distance_m) {
      best_distance_m = road->distance_m;
      best = c;
    }
  }
  if (std::isinf(best_distance_m))
    return Result<std::size_t>{std::move(last_not_found), std::nullopt};
  return Result<std::size_t>{Status{}, best};
}

Result<std::size_t> MapSet::choose(const Position& position, double max_distance_m) noexcept {
  Result<std::size_t> chosen = answering_candidate(position, max_distance_m);
  if (!chosen.ok()) return chosen;
  const Impl::Candidate& c = impl_->candidates[*chosen];
  if (impl_->candidates.size() == 1) {
    // One candidate is taken without a search: say not_found here as nearest would.
    Result<NearestRoad> road = impl_->maps[c.index].nearest(c.in_zone, max_distance_m);
    if (!road.ok()) return Result<std::size_t>{std::move(road.status), std::nullopt};
  }
  return Result<std::size_t>{Status{}, c.index};
}

namespace {

/// A map's answer with its source.
template <typename T>
Result<FromMap<T>> from_map(Result<T>&& answer, MapSource&& source) {
  if (!answer.ok()) return Result<FromMap<T>>{std::move(answer.status), std::nullopt};
  return Result<FromMap<T>>{Status{}, FromMap<T>{std::move(*answer.value), std::move(source)}};
}

}  // namespace

Result<FromMap<NearestRoad>> MapSet::nearest(const Position& position,
                                             double max_distance_m) noexcept {
  try {
    Result<std::size_t> chosen = answering_candidate(position, max_distance_m);
    if (!chosen.ok()) return Result<FromMap<NearestRoad>>{std::move(chosen.status), std::nullopt};
    const Impl::Candidate& c = impl_->candidates[*chosen];
    return from_map(impl_->maps[c.index].nearest(c.in_zone, max_distance_m), source(c.index));
  } catch (const std::exception& e) {
    return fail<FromMap<NearestRoad>>(StatusCode::internal, e.what());
  }
}

Result<FromMap<Assessment>> MapSet::assess(const Position& position,
                                           const AssessOptions& options) noexcept {
  try {
    Result<std::size_t> chosen = answering_candidate(position, options.max_distance_m);
    if (!chosen.ok()) return Result<FromMap<Assessment>>{std::move(chosen.status), std::nullopt};
    const Impl::Candidate& c = impl_->candidates[*chosen];
    return from_map(impl_->maps[c.index].assess(c.in_zone, options), source(c.index));
  } catch (const std::exception& e) {
    return fail<FromMap<Assessment>>(StatusCode::internal, e.what());
  }
}

Result<FromMap<BetterPlaces>> MapSet::better_place(const Position& position,
                                                   const BetterPlaceOptions& options) noexcept {
  try {
    Result<std::size_t> chosen = answering_candidate(position, options.assess.max_distance_m);
    if (!chosen.ok()) {
      return Result<FromMap<BetterPlaces>>{std::move(chosen.status), std::nullopt};
    }
    const Impl::Candidate& c = impl_->candidates[*chosen];
    return from_map(impl_->maps[c.index].better_place(c.in_zone, options), source(c.index));
  } catch (const std::exception& e) {
    return fail<FromMap<BetterPlaces>>(StatusCode::internal, e.what());
  }
}

Result<FromMap<RoadHeading>> MapSet::road_heading(const Position& position,
                                                  double max_distance_m) noexcept {
  try {
    Result<std::size_t> chosen = answering_candidate(position, max_distance_m);
    if (!chosen.ok()) return Result<FromMap<RoadHeading>>{std::move(chosen.status), std::nullopt};
    const Impl::Candidate& c = impl_->candidates[*chosen];
    return from_map(impl_->maps[c.index].road_heading(c.in_zone, max_distance_m), source(c.index));
  } catch (const std::exception& e) {
    return fail<FromMap<RoadHeading>>(StatusCode::internal, e.what());
  }
}

}  // namespace roadcross
