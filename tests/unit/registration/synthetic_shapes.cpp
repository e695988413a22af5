#include "synthetic_shapes.h"

#include <array>
#include <numbers>
#include <random>

namespace vscan::registration::testing {
namespace {

const Eigen::Vector3d kHalfBox(0.10, 0.075, 0.05);
const Eigen::Vector3d kSphereCentre(0.17, 0.02, 0.03);
constexpr double kSphereRadius = 0.05;

}  // namespace

Cloud BoxAndSphere(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  // Face pairs of the box (by axis), then the sphere.
  std::array<double, 4> area{};
  for (int axis = 0; axis < 3; ++axis) {
    area[static_cast<size_t>(axis)] = 2.0 * 4.0 * kHalfBox[(axis + 1) % 3] * kHalfBox[(axis + 2) % 3];
  }
  area[3] = 4.0 * std::numbers::pi * kSphereRadius * kSphereRadius;
  std::discrete_distribution<int> pick(area.begin(), area.end());
  Cloud cloud;
  cloud.points.reserve(count);
  cloud.normals.reserve(count);
  while (cloud.points.size() < count) {
    const int part = pick(rng);
    Eigen::Vector3d p, n;
    if (part < 3) {
      n = Eigen::Vector3d::Zero();
      n[part] = u(rng) < 0.0 ? -1.0 : 1.0;
      p = Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(kHalfBox);
      p[part] = n[part] * kHalfBox[part];
      // The part of the box inside the sphere is not surface.
      if ((p - kSphereCentre).norm() < kSphereRadius) continue;
    } else {
      n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      p = kSphereCentre + kSphereRadius * n;
      if ((p.cwiseAbs() - kHalfBox).maxCoeff() < 0.0) continue;
    }
    cloud.points.push_back(p.cast<float>());
    cloud.normals.push_back(n.cast<float>());
  }
  return cloud;
}

Cloud Moved(const Cloud& cloud, const Pose3& pose) {
  Cloud moved;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    moved.points.push_back((pose * cloud.points[i].cast<double>()).cast<float>());
    moved.normals.push_back((pose.linear() * cloud.normals[i].cast<double>()).cast<float>());
  }
  return moved;
}

}  // namespace vscan::registration::testing
