#include "hull_support.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

namespace vscan::physics::test {
namespace {

std::vector<Eigen::Vector3d> FibonacciDirections(int count) {
  std::vector<Eigen::Vector3d> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return out;
}

const std::vector<Eigen::Vector3d>& Directions(int count) {
  static std::mutex mutex;
  static std::map<int, std::vector<Eigen::Vector3d>> made;
  std::lock_guard lock(mutex);
  auto [it, fresh] = made.try_emplace(count);
  if (fresh) it->second = FibonacciDirections(count);
  return it->second;
}

}  // namespace

double OutsideHullBy(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& points, int directions) {
  double out = 0.0;
  for (const auto& d : Directions(directions)) {
    double support = -std::numeric_limits<double>::infinity();
    for (const auto& q : points) support = std::max(support, d.dot(q));
    out = std::max(out, d.dot(p) - support);
  }
  return out;
}

}  // namespace vscan::physics::test
