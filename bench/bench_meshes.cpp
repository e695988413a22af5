#include "bench_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>

namespace vscan::bench {
namespace {

[[noreturn]] void Fail(const std::string& what) {
  std::fprintf(stderr, "bench: %s\n", what.c_str());
  std::exit(1);
}

// Vertex count, face count and how many properties each vertex line carries.
struct PlyHeader {
  size_t vertices = 0, faces = 0, vertex_properties = 0;
};

PlyHeader ReadHeader(std::istream& in, const std::string& path) {
  PlyHeader h;
  std::string line, current;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format" && line.find("ascii") == std::string::npos) Fail(path + ": not an ASCII PLY");
    if (key == "element") {
      words >> current;
      size_t n = 0;
      words >> n;
      if (current == "vertex") h.vertices = n;
      if (current == "face") h.faces = n;
    }
    if (key == "property" && current == "vertex") ++h.vertex_properties;
    if (key == "end_header") return h;
  }
  Fail(path + ": no end_header");
}

}  // namespace

TriangleMesh ReadAsciiPly(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail("cannot open " + path);
  const PlyHeader h = ReadHeader(in, path);
  if (h.vertex_properties < 3) Fail(path + ": vertices need x y z");
  TriangleMesh mesh;
  mesh.vertices.resize(h.vertices);
  for (auto& v : mesh.vertices) {
    in >> v.x() >> v.y() >> v.z();
    for (size_t k = 3; k < h.vertex_properties; ++k) {
      float ignored;
      in >> ignored;
    }
  }
  mesh.triangles.reserve(h.faces);
  for (size_t f = 0; f < h.faces; ++f) {
    size_t n = 0;
    in >> n;
    std::vector<uint32_t> ids(n);
    for (auto& id : ids) in >> id;
    for (size_t k = 1; k + 1 < n; ++k) mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  if (!in) Fail(path + ": truncated or malformed body");
  return mesh;
}

BunnyGrid MakeBunnyGrid(const TriangleMesh& bunny, int copies, uint32_t width, uint32_t height) {
  Eigen::Vector3f lo, hi;
  bunny.Bounds(lo, hi);
  const Eigen::Vector3d size = (hi - lo).cast<double>();
  const Eigen::Vector3d centre = (0.5f * (lo + hi)).cast<double>();
  // Neighbours overlap a little and sit at alternating depths, so the grid fills the frame.
  const double step_x = 0.85 * size.x(), step_y = 0.8 * size.y(), step_z = 0.4 * size.z();
  const int columns = static_cast<int>(std::ceil(std::sqrt(copies * 1.25)));
  auto mesh = std::make_shared<const TriangleMesh>(bunny);

  BunnyGrid grid;
  int placed = 0;
  double rows_height = 0;
  for (int row = 0; placed < copies; ++row) {
    const int in_row = std::min(row % 2 == 0 ? columns : columns - 1, copies - placed);
    for (int c = 0; c < in_row; ++c, ++placed) {
      raycast::SceneInstance instance;
      instance.mesh = mesh;
      instance.instance_id = static_cast<uint32_t>(placed + 1);
      const Eigen::Vector3d at((c - (in_row - 1) / 2.0) * step_x, -row * step_y, (c % 2) * -step_z);
      const double yaw = (placed % 5 - 2) * 12.0 * std::numbers::pi / 180.0;
      instance.world_from_object = Eigen::Translation3d(at) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                                   Eigen::Translation3d(-centre);
      grid.instances.push_back(instance);
    }
    rows_height = row * step_y;
  }
  // Frame the grid's extent from 1 m in front of it.
  const double grid_width = (columns - 1) * step_x + size.x();
  const double grid_height = rows_height + size.y();
  const double distance = 1.0;
  const double half_width = 0.5 * std::max(grid_width, grid_height * width / height) * 0.95;
  const double hfov = 2.0 * std::atan(half_width / distance) * 180.0 / std::numbers::pi;
  grid.camera = sensor::CameraFromFov(width, height, hfov, 0.1, 10.0);
  const Eigen::Vector3d target(0.0, -0.5 * rows_height, 0.0);
  grid.world_from_sensor =
      *PoseFromLookAt(target + Eigen::Vector3d(0, 0, distance), target, Eigen::Vector3d::UnitY(), "bench");
  return grid;
}

}  // namespace vscan::bench
