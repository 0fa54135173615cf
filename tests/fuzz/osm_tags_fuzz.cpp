// The OSM tag parsers (maxspeed, lanes, width, speed zones, a way's whole context) on arbitrary
// tag values: an answer or "not understood", never a crash, an exception or a non-finite value.
#include <cmath>
#include <cstdlib>

#include "fuzz_support.hpp"
#include "roadcross/preprocess/context/osm_tags.hpp"

namespace rp = roadcross::preprocess;

namespace {

/// Splits the input at NUL bytes into up to `n` strings (tag values).
std::vector<std::string> fields(std::string_view text, std::size_t n) {
  std::vector<std::string> out;
  while (out.size() + 1 < n) {
    const std::size_t nul = text.find('\0');
    if (nul == std::string_view::npos) break;
    out.emplace_back(text.substr(0, nul));
    text.remove_prefix(nul + 1);
  }
  out.emplace_back(text);
  out.resize(n);
  return out;
}

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<std::string> v = fields(roadcross::fuzz::as_text(data, size), 6);
  for (const char* country : {"CZ", "DE", "default"}) {
    if (const auto kmh = rp::parse_maxspeed_kmh(v[0], country)) check(std::isfinite(*kmh));
  }
  (void)rp::split_speed_zone(v[0]);
  (void)rp::country_of_speed_tag(v[0]);
  if (const auto lanes = rp::parse_lanes(v[1])) check(*lanes >= 0);
  if (const auto width = rp::parse_width_m(v[2])) check(std::isfinite(*width));
  const rp::Tags tags = {{"maxspeed", v[0]},      {"lanes", v[1]},
                         {"width", v[2]},         {"maxspeed:forward", v[3]},
                         {"zone:maxspeed", v[4]}, {"source:maxspeed", v[5]}};
  for (const char* highway : {"primary", "residential", "motorway_link"}) {
    for (const bool oneway : {false, true}) {
      const rp::WayContext c = rp::way_context(tags, highway, oneway, rp::ContextDefaults{});
      check(std::isfinite(c.maxspeed_kmh) && std::isfinite(c.width_m) && c.lanes >= 0);
    }
  }
  return 0;
}
