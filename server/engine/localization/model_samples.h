#pragma once
// Points spread over a part's surface with the outward normal of the triangle each lies on: the
// part as the localizer matches it against a scan.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::localization {

struct ModelSamples {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;  // unit; outward for a mesh wound counter-clockwise outside
};

// count points, each on a triangle drawn with probability proportional to its area and uniform
// within it; the same mesh, count and seed give the same samples. Empty for a mesh without area.
ModelSamples SampleModel(const TriangleMesh& mesh, size_t count, uint64_t seed);

}  // namespace vscan::localization
