// read_osm_pass(): every object of the asked types reaches the handlers in file order; a pass
// over the nodes of a file sorted by type (its header says so) ends at the first way, with
// every node read, and one over a file not marked sorted reads it whole.
#include <gtest/gtest.h>

#include <osmium/handler.hpp>
#include <osmium/io/any_output.hpp>
#include <string>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/osm/osm_pass.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;

namespace {

constexpr int kNodes = 20000;  // more than two .pbf blocks (8000 nodes each)

/// kNodes nodes (ids 1..kNodes), then ways 1..3 over the first nodes, then relation 1.
std::string objects_sorted_by_type() {
  std::string body;
  for (int id = 1; id <= kNodes; ++id) {
    body += "  <node id=\"" + std::to_string(id) + "\" version=\"1\" lat=\"50." +
            std::to_string(id) + "\" lon=\"14.4\"/>\n";
  }
  for (int id = 1; id <= 3; ++id) {
    body += "  <way id=\"" + std::to_string(id) + "\" version=\"1\"><nd ref=\"" +
            std::to_string(id) + "\"/><nd ref=\"" + std::to_string(id + 1) + "\"/></way>\n";
  }
  body +=
      "  <relation id=\"1\" version=\"1\"><member type=\"way\" ref=\"1\" role=\"\"/>"
      "</relation>\n";
  return rt::osm_document(body);
}

/// The objects of the XML file `xml` as a .pbf at `pbf`, its header marked sorted or not.
void write_pbf(const std::string& xml, const std::string& pbf, bool marked_sorted) {
  osmium::io::Reader reader{xml};
  osmium::io::Header header;
  if (marked_sorted) header.set("sorting", "Type_then_ID");
  osmium::io::Writer writer{pbf, header, osmium::io::overwrite::allow};
  while (osmium::memory::Buffer buffer = reader.read()) writer(std::move(buffer));
  writer.close();
  reader.close();
}

/// Counts what it is handed; `ids_ascend` stays true while node ids come 1, 2, 3, ...
struct Counter : osmium::handler::Handler {
  int nodes = 0, ways = 0, relations = 0;
  bool ids_ascend = true;
  void node(const osmium::Node& node) {
    ids_ascend = ids_ascend && node.id() == nodes + 1;
    ++nodes;
  }
  void way(const osmium::Way&) { ++ways; }
  void relation(const osmium::Relation&) { ++relations; }
};

Counter pass(const std::string& path, osmium::osm_entity_bits::type entities) {
  rp::Progress progress(false);
  Counter counter;
  rp::read_osm_pass(path, entities, progress, counter);
  return counter;
}

TEST(OsmPass, NodesOfASortedFileEndAtTheFirstWay) {
  rt::TempDir dir;
  const std::string xml = dir.write("objects.osm", objects_sorted_by_type());
  const std::string sorted = xml + ".sorted.pbf", unmarked = xml + ".pbf";
  write_pbf(xml, sorted, true);
  write_pbf(xml, unmarked, false);
  EXPECT_TRUE(rp::sorted_by_type(sorted));
  EXPECT_FALSE(rp::sorted_by_type(unmarked));
  EXPECT_FALSE(rp::sorted_by_type(xml));
  for (const std::string& path : {sorted, unmarked, xml}) {
    const Counter nodes = pass(path, osmium::osm_entity_bits::node);
    EXPECT_EQ(nodes.nodes, kNodes) << path;
    EXPECT_TRUE(nodes.ids_ascend) << path;
    EXPECT_EQ(nodes.ways + nodes.relations, 0) << path;  // read to stop, never handed on
    const Counter rest =
        pass(path, osmium::osm_entity_bits::way | osmium::osm_entity_bits::relation);
    EXPECT_EQ(rest.nodes, 0) << path;
    EXPECT_EQ(rest.ways, 3) << path;
    EXPECT_EQ(rest.relations, 1) << path;
    const Counter all = pass(path, osmium::osm_entity_bits::all);
    EXPECT_EQ(all.nodes + all.ways + all.relations, kNodes + 4) << path;
  }
}

}  // namespace
