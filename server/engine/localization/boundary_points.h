#pragma once
// Points on the rim of a surface (a face's edge, a hole's, where a part ends in front of what lies
// behind it), with the direction in the surface that points out of it: the features a flat part
// seen face-on still has when every pair of its face's points looks the same.

#include <vector>

#include <Eigen/Core>

#include "localization/oriented_points.h"

namespace vscan::localization {

// Per point, the unit direction in its tangent plane towards the side where the surface ends, or
// zero for a point inside its surface. A point's surface is its neighbours within radius whose
// normals are within 30 degrees of its own and that lie within radius / 4 of its tangent plane; it
// is on the rim when those neighbours leave a gap wider than a quarter turn around it.
std::vector<Eigen::Vector3f> RimDirections(const OrientedPoints& cloud, double radius);

}  // namespace vscan::localization
