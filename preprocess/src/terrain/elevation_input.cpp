#include "roadcross/preprocess/terrain/elevation_input.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <string_view>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/gdal_module.hpp"

namespace roadcross::preprocess {

namespace {

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == ';';
}

/// Splits `line` into at most `max_fields` fields; returns the number found (max_fields + 1
/// when there are more).
std::size_t split_fields(std::string_view line, std::string_view* fields, std::size_t max_fields) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_separator(line[i])) ++i;
    if (i == line.size()) break;
    const std::size_t start = i;
    while (i < line.size() && !is_separator(line[i])) ++i;
    if (count == max_fields) return max_fields + 1;
    fields[count++] = line.substr(start, i - start);
  }
  return count;
}

bool parse_double(std::string_view text, double& out) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(out);
}

bool has_letter(std::string_view line) {
  return std::any_of(line.begin(), line.end(), [](char c) {
    return std::isalpha(static_cast<unsigned char>(c)) != 0 && c != 'e' && c != 'E';
  });
}

std::string quoted_excerpt(std::string_view line) {
  constexpr std::size_t kMax = 60;
  std::string out(line.substr(0, kMax));
  if (line.size() > kMax) out += "...";
  return "'" + out + "'";
}

std::string lower_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

ElevationKind elevation_kind_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == "xyz" || ext == "txt" || ext == "csv" ? ElevationKind::xyz : ElevationKind::raster;
}

void read_xyz_chunks(const std::string& path, std::size_t chunk_points,
                     const std::function<void(std::vector<ElevationPoint>&)>& on_chunk) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the elevation file (does it exist?)");
  std::vector<char> buffer(1 << 20);
  in.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));

  chunk_points = std::max<std::size_t>(1, chunk_points);
  std::vector<ElevationPoint> points;
  points.reserve(std::min<std::size_t>(chunk_points, 1 << 16));
  std::size_t total = 0;
  std::string line;
  std::size_t line_number = 0;
  bool seen_content = false;
  std::string_view fields[3];
  while (std::getline(in, line)) {
    ++line_number;
    std::string_view view(line);
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    if (std::all_of(view.begin(), view.end(), is_separator)) continue;
    const bool first = !seen_content;
    seen_content = true;
    const std::size_t n = split_fields(view, fields, 3);
    ElevationPoint p;
    if (n == 3 && parse_double(fields[0], p.x) && parse_double(fields[1], p.y) &&
        parse_double(fields[2], p.z)) {
      if (p.z < kMinAltitudeM || p.z > kMaxAltitudeM) {
        throw InputError(path, "line " + std::to_string(line_number) + ": altitude " +
                                   std::string(fields[2]) + " m is outside [-500, 9000] m");
      }
      points.push_back(p);
      if (points.size() == chunk_points) {
        total += points.size();
        on_chunk(points);
        points.clear();
      }
      continue;
    }
    if (first && has_letter(view)) continue;  // a header such as "X Y Z"
    throw InputError(path, "line " + std::to_string(line_number) +
                               ": expected three numbers 'easting northing altitude' separated "
                               "by spaces, tabs, commas or semicolons, got " +
                               quoted_excerpt(view));
  }
  if (in.bad()) throw InputError(path, "read error after line " + std::to_string(line_number));
  total += points.size();
  if (total == 0) {
    throw InputError(path, line_number == 0 ? "the elevation file is empty"
                                            : "no 'easting northing altitude' point in the file");
  }
  if (!points.empty()) on_chunk(points);
}

std::vector<ElevationPoint> read_xyz(const std::string& path) {
  std::vector<ElevationPoint> all;
  read_xyz_chunks(path, std::size_t(1) << 20, [&](std::vector<ElevationPoint>& chunk) {
    all.insert(all.end(), chunk.begin(), chunk.end());
  });
  return all;
}

std::string detect_xyz_crs(const std::string& path, const std::vector<ElevationPoint>& points) {
  // S-JTSK / Krovak East North over Czechia (EPSG:5514 area of use, rounded outwards).
  const auto in_sjtsk = [](const ElevationPoint& p) {
    return p.x > -905000.0 && p.x < -430000.0 && p.y > -1230000.0 && p.y < -930000.0;
  };
  const std::size_t step = std::max<std::size_t>(1, points.size() / 1000);
  bool all = true;
  for (std::size_t i = 0; i < points.size() && all; i += step) all = in_sjtsk(points[i]);
  if (all && in_sjtsk(points.back())) return "EPSG:5514";
  const ElevationPoint& p = points.front();
  std::string hint;
  if (p.x > 430000.0 && p.x < 905000.0 && p.y > 930000.0 && p.y < 1230000.0) {
    hint =
        " (these look like S-JTSK with positive axes: Y X in EPSG:5513 order, or negate them "
        "for EPSG:5514)";
  }
  throw InputError(path, "cannot tell the coordinate system of the points (first point " +
                             std::to_string(p.x) + " " + std::to_string(p.y) + ")" + hint +
                             "; give it with --elevation-crs, e.g. --elevation-crs EPSG:5514 for "
                             "S-JTSK or EPSG:32633 for UTM 33N");
}

CrsTransform::CrsTransform(const std::string& crs, const geo::UtmZone& zone)
    : backend_(gdal_module().crs_transform(crs, zone)) {}

CrsTransform::~CrsTransform() = default;

void CrsTransform::to_utm(std::vector<double>& x, std::vector<double>& y) const {
  backend_->to_utm(x, y);
}

void CrsTransform::from_utm(std::vector<double>& x, std::vector<double>& y) const {
  backend_->from_utm(x, y);
}

}  // namespace roadcross::preprocess
