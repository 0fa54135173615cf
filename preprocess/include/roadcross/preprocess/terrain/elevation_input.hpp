// Elevation inputs: ČÚZK-style XYZ point files ("easting northing altitude" per line) and any
// raster GDAL reads, plus the coordinate transformation into the DB's UTM zone.
// GDAL/PROJ stay inside the GDAL module (common/gdal_module.hpp): this header is plain C++.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "roadcross/geo.hpp"

namespace roadcross::preprocess {

/// The altitudes an elevation input may hold, metres: below the Dead Sea shore (-430 m) or
/// above Everest is a damaged or misread file (random bytes, a wrong data type, a scale
/// missing), not terrain. Both XYZ points and raster pixels are checked.
inline constexpr double kMinAltitudeM = -500.0;
inline constexpr double kMaxAltitudeM = 9000.0;

struct ElevationPoint {
  double x = 0.0;  ///< easting (or longitude for a geographic CRS), in the file's CRS
  double y = 0.0;  ///< northing (or latitude)
  double z = 0.0;  ///< altitude, metres
};

enum class ElevationKind { xyz, raster };

/// One --elevation argument.
struct ElevationSource {
  std::string path;
  ElevationKind kind = ElevationKind::raster;
};

class CrsTransformBackend;

/// XYZ by extension (.xyz .txt .csv .asc-less text), otherwise a raster for GDAL.
ElevationKind elevation_kind_of(const std::string& path);

/// Reads an XYZ point file: three numbers per line separated by spaces, tabs, commas or
/// semicolons (runs of separators count once, trailing ones are ignored), an optional header
/// line first, Windows or Unix line ends, empty lines skipped. Altitudes must lie in
/// [-500, 9000] m. Throws InputError naming the file and line of the first bad line, or when the
/// file is missing or holds no point.
std::vector<ElevationPoint> read_xyz(const std::string& path);

/// The same, streamed: calls `on_chunk` with every `chunk_points` points in file order (the last
/// chunk may be shorter), so that a file larger than memory can be read. The callback may
/// modify the chunk. Throws as read_xyz.
void read_xyz_chunks(const std::string& path, std::size_t chunk_points,
                     const std::function<void(std::vector<ElevationPoint>&)>& on_chunk);

/// The CRS of XYZ points without --elevation-crs: "EPSG:5514" when every sampled point lies in
/// S-JTSK / Krovak East North's range over Czechia (E -905 000..-430 000, N -1 230 000..-930 000,
/// both negative). Throws InputError asking for --elevation-crs otherwise.
std::string detect_xyz_crs(const std::string& path, const std::vector<ElevationPoint>& points);

/// A coordinate transformation between a user-given CRS ("EPSG:5514", a PROJ string, WKT)
/// and a UTM zone, with axes in easting/northing (longitude/latitude) order. Loads the GDAL
/// module (throws std::runtime_error when it cannot).
class CrsTransform {
 public:
  /// Throws ParameterError when `crs` is not a CRS GDAL/PROJ knows.
  CrsTransform(const std::string& crs, const geo::UtmZone& zone);
  ~CrsTransform();
  CrsTransform(const CrsTransform&) = delete;
  CrsTransform& operator=(const CrsTransform&) = delete;

  /// In place, source CRS → UTM; points that cannot be transformed become NaN.
  void to_utm(std::vector<double>& x, std::vector<double>& y) const;
  /// In place, UTM → source CRS; failed points become NaN.
  void from_utm(std::vector<double>& x, std::vector<double>& y) const;

 private:
  std::unique_ptr<CrsTransformBackend> backend_;
};

}  // namespace roadcross::preprocess
