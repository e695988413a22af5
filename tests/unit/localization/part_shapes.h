#pragma once
// Vertex sets with known symmetries for the localization tests.

#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::localization::testing {

// The 8 corners and 6 face centres of the cube [-half, half]^3.
std::vector<Eigen::Vector3f> CubeWithFaceCentres(double half);

// The 24 rotations that map a cube centred on the origin onto itself (identity included).
std::vector<Pose3> CubeRotations();

// Rings of `count` evenly spaced vertices of the given radius about the z axis, one per height.
std::vector<Eigen::Vector3f> Rings(double radius, int count, const std::vector<double>& heights);

}  // namespace vscan::localization::testing
