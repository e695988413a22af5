#include "raster_test_scenes.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

namespace vscan::raster::testing {

RasterRenderer* SharedRenderer() {
  static const auto renderer = RasterRenderer::Create();
  if (!renderer.ok()) {
    ADD_FAILURE() << renderer.status().ToString();
    return nullptr;
  }
  return renderer->get();
}

std::shared_ptr<const TriangleMesh> MakeSquare(double half_side) {
  auto mesh = std::make_shared<TriangleMesh>();
  const auto h = static_cast<float>(half_side);
  mesh->vertices = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  mesh->triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

std::shared_ptr<const TriangleMesh> MakeGrid(double half_side, int cells) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      mesh->vertices.emplace_back(static_cast<float>(half_side * (2.0 * i / cells - 1)),
                                  static_cast<float>(half_side * (2.0 * j / cells - 1)), 0.0f);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      mesh->triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

std::shared_ptr<const TriangleMesh> MakeSphere(double radius, int rings, int segments) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (int r = 0; r <= rings; ++r) {
    const double polar = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2 * std::numbers::pi * s / segments;
      mesh->vertices.emplace_back(Eigen::Vector3d(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                                  std::cos(polar))
                                      .cast<float>() *
                                  static_cast<float>(radius));
    }
  }
  const auto at = [&](int r, int s) { return static_cast<uint32_t>(r * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      if (r > 0) mesh->triangles.push_back({at(r, s), at(r + 1, s), at(r, s + 1)});
      if (r + 1 < rings) mesh->triangles.push_back({at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
    }
  }
  return mesh;
}

TriangleMesh ReadAsciiPly(const std::string& path) {
  std::ifstream in(path);
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
    } else if (key == "property" && element == "vertex") {
      ++vertex_properties;
    } else if (key == "end_header") {
      break;
    }
  }
  TriangleMesh mesh;
  for (size_t i = 0; i < vertices && in; ++i) {
    Eigen::Vector3f v;
    in >> v.x() >> v.y() >> v.z();
    for (size_t k = 3; k < vertex_properties; ++k) in >> line;
    mesh.vertices.push_back(v);
  }
  for (size_t i = 0; i < faces && in; ++i) {
    size_t n = 0;
    in >> n;
    std::vector<uint32_t> ids(n);
    for (auto& id : ids) in >> id;
    for (size_t k = 1; k + 1 < n; ++k) mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  if (!in) return {};
  return mesh;
}

std::shared_ptr<const TriangleMesh> Bunny() {
  static const auto bunny =
      std::make_shared<const TriangleMesh>(ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"));
  return bunny;
}

std::vector<int64_t> PointOfPixel(const PointCloud& cloud, const sensor::PinholeCamera& camera) {
  std::vector<int64_t> index(camera.pixel_count(), -1);
  for (size_t i = 0; i < cloud.pixels.size(); ++i) index[cloud.pixels[i]] = static_cast<int64_t>(i);
  return index;
}

}  // namespace vscan::raster::testing
