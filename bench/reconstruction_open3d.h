#pragma once
// Open3D's Poisson reconstruction as a benchmark peer; Open3D stays in its .cpp file, and a build
// without Open3D links the stub instead.

#include <span>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::bench {

bool Open3dAvailable();

// open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson at the given depth on every core;
// an empty mesh when Open3D is not built in.
TriangleMesh Open3dPoisson(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                           int depth);

}  // namespace vscan::bench
