#pragma once
// Helpers shared by the mesh import tests: file loading and independent reference parsers.

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace vscan::geometry::test {

inline std::string ReadDataFile(const std::string& relative) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/" + relative, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

using Point = std::array<float, 3>;

// What a correct importer must produce from a triangle soup: triangles whose three scaled corners
// are distinct, the distinct scaled corners they use, and their bounds.
struct Expected {
  size_t triangles = 0;
  std::set<Point> vertices;
  Point min{}, max{};
};

inline Expected ExpectFromSoup(const std::vector<std::array<std::array<double, 3>, 3>>& soup, double scale) {
  Expected e;
  bool first = true;
  for (const auto& tri : soup) {
    std::array<Point, 3> corners;
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) corners[c][k] = static_cast<float>(tri[c][k] * scale) + 0.0f;
    }
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) continue;
    ++e.triangles;
    for (const auto& p : corners) {
      e.vertices.insert(p);
      for (int k = 0; k < 3; ++k) {
        e.min[k] = first ? p[k] : std::min(e.min[k], p[k]);
        e.max[k] = first ? p[k] : std::max(e.max[k], p[k]);
      }
      first = false;
    }
  }
  return e;
}

// Facets of a binary STL, read straight from the 50-byte records.
inline std::vector<std::array<std::array<double, 3>, 3>> ParseBinaryStl(const std::string& bytes) {
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  std::vector<std::array<std::array<double, 3>, 3>> soup(count);
  for (uint32_t i = 0; i < count; ++i) {
    const char* record = bytes.data() + 84 + 50 * size_t{i} + 12;
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        float value;
        std::memcpy(&value, record + 4 * (3 * c + k), 4);
        soup[i][c][k] = value;
      }
    }
  }
  return soup;
}

// Faces of an ASCII PLY whose first three vertex properties are x y z and faces are triangles.
inline std::vector<std::array<std::array<double, 3>, 3>> ParseAsciiPly(const std::string& text) {
  std::istringstream in(text);
  std::string line, word;
  size_t vertex_count = 0, face_count = 0;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream fields(line);
    std::string kind;
    fields >> word >> kind;
    if (word == "element" && kind == "vertex") fields >> vertex_count;
    if (word == "element" && kind == "face") fields >> face_count;
  }
  std::vector<std::array<double, 3>> vertices(vertex_count);
  for (auto& v : vertices) {
    std::getline(in, line);
    std::istringstream fields(line);
    for (auto& x : v) {
      float f;
      fields >> f;
      x = f;
    }
  }
  std::vector<std::array<std::array<double, 3>, 3>> soup(face_count);
  for (auto& tri : soup) {
    size_t n, a, b, c;
    in >> n >> a >> b >> c;
    tri = {vertices.at(a), vertices.at(b), vertices.at(c)};
  }
  return soup;
}

}  // namespace vscan::geometry::test
