#include "reconstruction_open3d.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>

namespace vscan::bench {

bool Open3dAvailable() { return true; }

TriangleMesh Open3dPoisson(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                           int depth) {
  open3d::geometry::PointCloud cloud;
  cloud.points_.reserve(points.size());
  cloud.normals_.reserve(normals.size());
  for (const auto& p : points) cloud.points_.push_back(p.cast<double>());
  for (const auto& n : normals) cloud.normals_.push_back(n.cast<double>());
  auto [o3d_mesh, densities] =
      open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(cloud, static_cast<size_t>(depth));
  TriangleMesh mesh;
  mesh.vertices.reserve(o3d_mesh->vertices_.size());
  for (const auto& v : o3d_mesh->vertices_) mesh.vertices.push_back(v.cast<float>());
  mesh.triangles.reserve(o3d_mesh->triangles_.size());
  for (const auto& t : o3d_mesh->triangles_) {
    mesh.triangles.push_back({static_cast<uint32_t>(t.x()), static_cast<uint32_t>(t.y()), static_cast<uint32_t>(t.z())});
  }
  return mesh;
}

}  // namespace vscan::bench
