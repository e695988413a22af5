#include "model_test_block.h"

#include <Eigen/Core>

namespace vscan::service::testing {
namespace {

// The L in the xz plane, counter-clockwise seen from -y, metres.
const Eigen::Vector2d kOutline[] = {{-0.04, 0.0}, {0.04, 0.0}, {0.04, 0.03}, {0.0, 0.03}, {0.0, 0.07}, {-0.04, 0.07}};

}  // namespace

TriangleMesh LBlock() {
  constexpr uint32_t n = 6;
  constexpr double half_depth = 0.03;
  TriangleMesh mesh;
  for (const double y : {-half_depth, half_depth}) {
    for (const Eigen::Vector2d& p : kOutline) mesh.vertices.emplace_back(static_cast<float>(p.x()), static_cast<float>(y), static_cast<float>(p.y()));
  }
  // Caps: a fan from the first corner covers the L (every fan triangle lies inside it). The outline
  // runs counter-clockwise seen from -y, so the front cap (y < 0) keeps that order.
  for (uint32_t k = 1; k + 1 < n; ++k) {
    mesh.triangles.push_back({0, k, k + 1});
    mesh.triangles.push_back({n, n + k + 1, n + k});
  }
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t a = k, b = (k + 1) % n;
    mesh.triangles.push_back({a, n + b, b});
    mesh.triangles.push_back({a, n + a, n + b});
  }
  return mesh;
}

}  // namespace vscan::service::testing
