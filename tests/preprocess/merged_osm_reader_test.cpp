// MergedOsmReader: several sorted OSM files as one stream in (type, id) order, an object held by
// several files handed on once, in its highest version. Expected streams written out by hand
// from the files below.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/osm/osm_pass.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;

namespace {

std::string node(long id, int version) {
  return "  <node id=\"" + std::to_string(id) + "\" version=\"" + std::to_string(version) +
         "\" lat=\"50.0\" lon=\"14.4\"/>\n";
}

std::string way(long id, int version) {
  return "  <way id=\"" + std::to_string(id) + "\" version=\"" + std::to_string(version) +
         "\"><nd ref=\"1\"/><nd ref=\"2\"/></way>\n";
}

/// "n1v1 w10v2 ...": the merged stream of `paths`.
std::string merged(const std::vector<std::string>& paths,
                   osmium::osm_entity_bits::type entities = osmium::osm_entity_bits::all) {
  rp::MergedOsmReader reader(paths, entities);
  std::string out;
  while (const osmium::OSMObject* object = reader.next()) {
    if (!out.empty()) out += ' ';
    out += osmium::item_type_to_char(object->type());
    out += std::to_string(object->id()) + "v" + std::to_string(object->version());
  }
  return out;
}

TEST(MergedOsmReader, ObjectsInBothFilesOnceInIdOrder) {
  rt::TempDir dir;
  // a: nodes 1, 2, 5; ways 10, 12.   b: nodes 2, 3, 5 (newer); ways 11, 12.
  const std::string a = dir.write(
      "a.osm", rt::osm_document(node(1, 1) + node(2, 1) + node(5, 1) + way(10, 1) + way(12, 3)));
  const std::string b = dir.write(
      "b.osm", rt::osm_document(node(2, 1) + node(3, 1) + node(5, 2) + way(11, 1) + way(12, 3)));
  // Nodes before ways, by id; node 2 and way 12 once; node 5 in its version 2 (b's).
  EXPECT_EQ(merged({a, b}), "n1v1 n2v1 n3v1 n5v2 w10v1 w11v1 w12v3");
  // The order of the files changes nothing.
  EXPECT_EQ(merged({b, a}), "n1v1 n2v1 n3v1 n5v2 w10v1 w11v1 w12v3");
  // A file merged with itself is that file.
  EXPECT_EQ(merged({a, a}), "n1v1 n2v1 n5v1 w10v1 w12v3");
  // Only the types asked for.
  EXPECT_EQ(merged({a, b}, osmium::osm_entity_bits::way), "w10v1 w11v1 w12v3");
}

TEST(MergedOsmReader, AFileEndingFirstLeavesTheOthers) {
  rt::TempDir dir;
  const std::string a = dir.write("a.osm", rt::osm_document(node(7, 1)));
  const std::string b =
      dir.write("b.osm", rt::osm_document(node(1, 1) + node(9, 1) + way(3, 1) + way(4, 1)));
  const std::string empty = dir.write("empty.osm", rt::osm_document(""));
  EXPECT_EQ(merged({a, b, empty}), "n1v1 n7v1 n9v1 w3v1 w4v1");
}

TEST(MergedOsmReader, AnUnsortedFileIsNamed) {
  rt::TempDir dir;
  const std::string a = dir.write("a.osm", rt::osm_document(node(1, 1)));
  const std::string unsorted = dir.write("unsorted.osm", rt::osm_document(node(4, 1) + node(3, 1)));
  try {
    merged({a, unsorted});
    FAIL() << "no error";
  } catch (const rp::InputError& e) {
    EXPECT_EQ(e.file(), unsorted);
    EXPECT_NE(std::string(e.what()).find("node 3 comes after node 4"), std::string::npos)
        << e.what();
  }
  // A way before a node is out of order too (nodes come first).
  const std::string way_first =
      dir.write("way_first.osm", rt::osm_document(way(10, 1) + node(1, 1)));
  EXPECT_THROW(merged({a, way_first}), rp::InputError);
}

TEST(MergedOsmReader, AFileThatIsNotOsmIsNamed) {
  rt::TempDir dir;
  const std::string a = dir.write("a.osm", rt::osm_document(node(1, 1)));
  const std::string broken = dir.write("broken.osm", "<osm><node id=\"1\" lat=\"50\"");
  try {
    merged({a, broken});
    FAIL() << "no error";
  } catch (const rp::InputError& e) {
    EXPECT_EQ(e.file(), broken);
  }
}

}  // namespace
