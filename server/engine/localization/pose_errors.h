#pragma once
// Pose errors of one part under an estimated and a true pose, as defined by the BOP benchmark
// (Hodaň et al., "BOP: Benchmark for 6D Object Pose Estimation", ECCV 2018, and the BOP Challenge
// 2019/2020 evaluation): ADD, ADD-S (ADI) and MSSD over the part's model vertices. Details and
// references: docs/LOCALIZATION.md.

#include <span>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::localization {

// The largest distance between two vertices (BOP's calc_pts_diameter); 0 for fewer than two.
double Diameter(std::span<const Eigen::Vector3f> vertices);

// ADD (Hinterstoisser et al. 2012): the mean distance between each vertex under the estimate and
// the same vertex under the truth.
double AddError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth);

// ADD-S (BOP's adi): the mean over the vertices under the truth of the distance to the nearest
// vertex under the estimate (kd-tree); indifferent to symmetries, which it needs no list of. Not
// symmetric in its poses: swapping estimate and truth can change it.
double AddSError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth);

// MSSD: the minimum over the symmetry transforms S (part frame, from SymmetryTransforms) of the
// largest distance between a vertex under the estimate and under truth * S. An empty list counts
// as the identity alone.
double MssdError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth,
                 std::span<const Pose3> symmetries);

}  // namespace vscan::localization
