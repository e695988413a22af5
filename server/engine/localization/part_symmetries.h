#pragma once
// The symmetries of a part as BOP declares them (models_info.json): discrete transforms and
// continuous rotation axes, expanded to the finite set of transforms MSSD takes its minimum over.

#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::localization {

// A rotation of any angle about the line through `point` along `axis` (part frame) maps the part
// onto itself.
struct ContinuousSymmetry {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

struct PartSymmetries {
  // Transforms of the part frame that map the part onto itself; the identity may be left out.
  std::vector<Pose3> discrete;
  std::vector<ContinuousSymmetry> continuous;

  bool any() const { return !discrete.empty() || !continuous.empty(); }
};

// BOP's max_sym_disc_step: a continuous symmetry is sampled so that the vertex farthest from its
// axis moves by at most this fraction of the diameter between samples, i.e. ceil(pi / 0.01) = 315
// rotations 2 pi / 315 apart.
inline constexpr double kBopSymmetryStep = 0.01;

// Every discrete transform (the identity first, added when missing) composed with every sampled
// rotation of every continuous symmetry (rotation after discrete transform), as BOP's
// misc.get_symmetry_transformations; without continuous symmetries, the discrete transforms alone.
std::vector<Pose3> SymmetryTransforms(const PartSymmetries& symmetries, double max_step = kBopSymmetryStep);

}  // namespace vscan::localization
