#include "vscan_test/ascii_ply.h"

#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

namespace vscan::test {

TriangleMesh ReadAsciiPly(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  size_t vertices = 0, faces = 0, vertex_properties = 0;
  std::string line, element;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "element") {
      size_t n = 0;
      words >> element >> n;
      if (element == "vertex") vertices = n;
      if (element == "face") faces = n;
    }
    if (key == "property" && element == "vertex") ++vertex_properties;
    if (key == "end_header") break;
  }
  TriangleMesh mesh;
  mesh.vertices.resize(vertices);
  for (auto& v : mesh.vertices) {
    in >> v.x() >> v.y() >> v.z();
    for (size_t k = 3; k < vertex_properties; ++k) {
      float ignored;
      in >> ignored;
    }
  }
  for (size_t f = 0; f < faces; ++f) {
    size_t n = 0;
    in >> n;
    std::vector<uint32_t> ids(n);
    for (auto& id : ids) in >> id;
    for (size_t k = 1; k + 1 < n; ++k) mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  EXPECT_TRUE(static_cast<bool>(in)) << path << ": truncated PLY body";
  if (!in) return {};
  return mesh;
}

}  // namespace vscan::test
