// Writes small hand-written OSM XML documents to temporary files for tests.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace roadcross::testing {

/// A temporary directory removed (with its files) when the object goes out of scope.
class TempDir {
 public:
  TempDir() {
    char pattern[] = "/tmp/roadcross-test-XXXXXX";
    path_ = ::mkdtemp(pattern);
  }
  ~TempDir() { std::system(("rm -rf '" + path_ + "'").c_str()); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

  /// Writes `content` to `name` in the directory and returns its path.
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream(file(name)) << content;
    return file(name);
  }

 private:
  std::string path_;
};

/// An <osm> document around `body` (nodes and ways).
inline std::string osm_document(const std::string& body) {
  return "<?xml version='1.0' encoding='UTF-8'?>\n<osm version=\"0.6\" generator=\"test\">\n" +
         body + "</osm>\n";
}

inline std::string osm_node(long id, double lat, double lon, const std::string& tags = "") {
  char text[160];
  std::snprintf(text, sizeof text, "  <node id=\"%ld\" version=\"1\" lat=\"%.7f\" lon=\"%.7f\"", id,
                lat, lon);
  return std::string(text) + (tags.empty() ? "/>\n" : ">" + tags + "</node>\n");
}

/// A way over `refs` (space-separated node ids) with `tags` given as k=v pairs separated by ';'.
inline std::string osm_way(long id, const std::string& refs, const std::string& tags) {
  std::string out = "  <way id=\"" + std::to_string(id) + "\" version=\"1\">\n";
  std::size_t start = 0;
  while (start < refs.size()) {
    std::size_t end = refs.find(' ', start);
    if (end == std::string::npos) end = refs.size();
    if (end > start) out += "    <nd ref=\"" + refs.substr(start, end - start) + "\"/>\n";
    start = end + 1;
  }
  start = 0;
  while (start < tags.size()) {
    std::size_t end = tags.find(';', start);
    if (end == std::string::npos) end = tags.size();
    const std::string pair = tags.substr(start, end - start);
    const std::size_t eq = pair.find('=');
    out += "    <tag k=\"" + pair.substr(0, eq) + "\" v=\"" + pair.substr(eq + 1) + "\"/>\n";
    start = end + 1;
  }
  return out + "  </way>\n";
}

}  // namespace roadcross::testing
