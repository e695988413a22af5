#pragma once
// How far a point lies outside the convex hull of a point set, by support functions over many
// directions: a lower bound of the distance, 0 inside.

#include <vector>

#include <Eigen/Core>

namespace vscan::physics::test {

// Over `directions` directions spread on the sphere (a Fibonacci lattice); more are tighter.
double OutsideHullBy(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& points, int directions = 4000);

}  // namespace vscan::physics::test
