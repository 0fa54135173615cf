// The runtime on damaged maps. The input is a list of edits to a small real map
// (ROADCROSS_FUZZ_MAP, loaded once): byte flips, damaged pages, a truncation, and changed or
// deleted rows (any column of the segments, their R*Tree, the crossings or the metadata set to
// a hostile value). Every query on the result must return an answer or an error status in
// bounded time: never a crash, a hang (libFuzzer's -timeout) or undefined behaviour (UBSan).
#include <sqlite3.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "roadcross/gap.hpp"
#include "roadcross/runtime.hpp"

namespace {

constexpr std::size_t kPageBytes = 4096;  // the writer's page size
constexpr std::size_t kMaxEdits = 8;

/// Hostile SQL values for a changed row ("DELETE" deletes the row instead).
constexpr std::array<const char*, 18> kValues = {"NULL",
                                                 "0",
                                                 "-1",
                                                 "1",
                                                 "2147483647",
                                                 "-2147483648",
                                                 "9223372036854775807",
                                                 "-9223372036854775808",
                                                 "1e308",
                                                 "-1e308",
                                                 "1e-300",
                                                 "0.5",
                                                 "'x'",
                                                 "X'00'",
                                                 "'TUNNEL'",
                                                 "'SUITABLE'",
                                                 "X'47500003E86400000000000000000000000000'",
                                                 "DELETE"};

constexpr std::array<const char*, 4> kTables = {"segments", "rtree_segments_geom", "crossings",
                                                "roadcross_metadata"};

struct BaseMap {
  std::string bytes;
  std::array<std::vector<std::string>, kTables.size()> columns;
};

std::vector<std::string> column_names(sqlite3* db, const char* table) {
  std::vector<std::string> out;
  sqlite3_stmt* st = nullptr;
  const std::string sql = std::string("SELECT name FROM pragma_table_info('") + table + "')";
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr) == SQLITE_OK) {
    while (sqlite3_step(st) == SQLITE_ROW) {
      out.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)));
    }
  }
  sqlite3_finalize(st);
  return out;
}

const BaseMap& base_map() {
  static const BaseMap base = [] {
    BaseMap b;
    const std::string path = roadcross::fuzz::required_env("ROADCROSS_FUZZ_MAP");
    std::ifstream in(path, std::ios::binary);
    b.bytes.assign(std::istreambuf_iterator<char>(in), {});
    sqlite3* db = nullptr;
    if (b.bytes.empty() || sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr)) {
      std::fprintf(stderr, "cannot read ROADCROSS_FUZZ_MAP %s\n", path.c_str());
      std::abort();
    }
    for (std::size_t t = 0; t < kTables.size(); ++t) b.columns[t] = column_names(db, kTables[t]);
    sqlite3_close(db);
    return b;
  }();
  return base;
}

/// A file of this process for the damaged map (SQLite needs a real path; tmpfs when there).
const std::string& scratch_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/roadcross-map-fuzz-" +
           std::to_string(::getpid()) + ".gpkg";
  }();
  return path;
}

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool more() const { return at_ < size_; }
  std::uint32_t next(int bytes) {
    std::uint32_t v = 0;
    for (int i = 0; i < bytes; ++i) v = v << 8 | (at_ < size_ ? data_[at_++] : 0u);
    return v;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_, at_ = 0;
};

/// Applies the input's edits; returns the SQL of the row edits (run once the bytes are on disk).
std::string edit_bytes(Reader& in, std::string& bytes) {
  const BaseMap& base = base_map();
  std::string sql;
  for (std::size_t edit = 0; edit < kMaxEdits && in.more() && !bytes.empty(); ++edit) {
    switch (in.next(1) % 4) {
      case 0: {  // flip bits of one byte
        const std::size_t at = in.next(3) % bytes.size();
        const auto mask = static_cast<char>(in.next(1) | 1u);
        bytes[at] = static_cast<char>(bytes[at] ^ mask);
        break;
      }
      case 1: {  // a damaged page: one byte repeated over it
        const std::size_t pages = (bytes.size() + kPageBytes - 1) / kPageBytes;
        const std::size_t page = in.next(2) % pages;
        const char fill = static_cast<char>(in.next(1));
        const std::size_t end = std::min(bytes.size(), (page + 1) * kPageBytes);
        std::memset(bytes.data() + page * kPageBytes, fill, end - page * kPageBytes);
        break;
      }
      case 2: {  // a changed (or deleted) row
        const std::size_t t = in.next(1) % kTables.size();
        const std::vector<std::string>& columns = base.columns[t];
        const std::string& column =
            columns.empty() ? "rowid" : columns[in.next(1) % columns.size()];
        const std::uint32_t row = in.next(1) % 64 + 1;
        const char* value = kValues[in.next(1) % kValues.size()];
        const std::string where = " WHERE rowid = " + std::to_string(row) + ";";
        sql += std::strcmp(value, "DELETE") == 0
                   ? std::string("DELETE FROM \"") + kTables[t] + "\"" + where
                   : std::string("UPDATE \"") + kTables[t] + "\" SET \"" + column +
                         "\" = " + value + where;
        break;
      }
      default:  // a truncated file
        bytes.resize(in.next(3) % bytes.size());
        break;
    }
  }
  return sql;
}

void write_map(const std::string& bytes, const std::string& sql) {
  {
    std::ofstream out(scratch_path(), std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  if (sql.empty()) return;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(scratch_path().c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK) {
    // Triggers (the GeoPackage's R*Tree upkeep) would undo a changed index row: edit raw.
    sqlite3_exec(db, "PRAGMA recursive_triggers = OFF", nullptr, nullptr, nullptr);
    sqlite3_exec(db, ("BEGIN;" + sql + "COMMIT;").c_str(), nullptr, nullptr, nullptr);
  }
  sqlite3_close(db);
}

void query(roadcross::Map& map, Reader& in) {
  const roadcross::MapInfo& info = map.info();
  const double e0 = info.min_easting_m, n0 = info.min_northing_m;
  const double de = info.max_easting_m - e0, dn = info.max_northing_m - n0;
  for (int i = 0; i < 3; ++i) {
    const double fe = static_cast<double>(in.next(1)) / 255.0;
    const double fn = static_cast<double>(in.next(1)) / 255.0;
    const auto position = roadcross::Position::utm(e0 + fe * de, n0 + fn * dn);
    (void)map.assess(position);
    (void)map.nearest(position);
    (void)map.road_heading(position);
    roadcross::BetterPlaceOptions better;
    better.search_radius_m = 60.0;
    (void)map.better_place(position, better);
    (void)roadcross::gap_crossing(map, position);
  }
  for (std::int64_t fid = 1; fid <= 3; ++fid) (void)map.assess_segment(fid);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  std::string bytes = base_map().bytes;
  const std::string sql = edit_bytes(in, bytes);
  write_map(bytes, sql);
  auto map = roadcross::Map::open(scratch_path());
  if (map.ok()) query(*map, in);
  return 0;
}
