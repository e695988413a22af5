#include "localization/part_symmetries.h"

#include <cmath>
#include <numbers>

namespace vscan::localization {
namespace {

bool IsIdentity(const Pose3& pose) { return pose.isApprox(Pose3::Identity(), 1e-12); }

}  // namespace

std::vector<Pose3> SymmetryTransforms(const PartSymmetries& symmetries, double max_step) {
  std::vector<Pose3> discrete{Pose3::Identity()};
  for (const Pose3& s : symmetries.discrete) {
    if (!IsIdentity(s)) discrete.push_back(s);
  }
  std::vector<Pose3> rotations;
  const int steps = static_cast<int>(std::ceil(std::numbers::pi / max_step));
  for (const ContinuousSymmetry& c : symmetries.continuous) {
    for (int i = 0; i < steps; ++i) {
      rotations.push_back(RotationAboutLine(c.point, c.axis, 2 * std::numbers::pi * i / steps));
    }
  }
  if (rotations.empty()) return discrete;
  std::vector<Pose3> all;
  all.reserve(discrete.size() * rotations.size());
  for (const Pose3& d : discrete) {
    for (const Pose3& r : rotations) all.push_back(r * d);
  }
  return all;
}

}  // namespace vscan::localization
