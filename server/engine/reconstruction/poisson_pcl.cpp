#include "reconstruction/poisson_pcl.h"

#include <thread>
#include <vector>

#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

namespace vscan::reconstruction {

StatusOr<TriangleMesh> PoissonPcl(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                                  const PoissonOptions& options) {
  if (points.size() != normals.size()) return InvalidArgument("normals: one per point is needed");
  if (options.depth < 1 || options.depth > 14) return InvalidArgument("poisson.depth: must lie in [1, 14]");
  if (points.empty()) return TriangleMesh{};
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  cloud->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    pcl::PointNormal& p = (*cloud)[i];
    p.x = points[i].x();
    p.y = points[i].y();
    p.z = points[i].z();
    p.normal_x = normals[i].x();
    p.normal_y = normals[i].y();
    p.normal_z = normals[i].z();
  }
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(options.depth);
  poisson.setThreads(options.threads > 0 ? options.threads
                                         : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  poisson.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointNormal> vertices;
  std::vector<pcl::Vertices> polygons;
  poisson.reconstruct(vertices, polygons);
  TriangleMesh mesh;
  mesh.vertices.reserve(vertices.size());
  for (const auto& v : vertices) mesh.vertices.emplace_back(v.x, v.y, v.z);
  for (const pcl::Vertices& poly : polygons) {
    // Fan over polygons in case PCL hands back more than triangles.
    for (size_t k = 1; k + 1 < poly.vertices.size(); ++k) {
      mesh.triangles.push_back({static_cast<uint32_t>(poly.vertices[0]), static_cast<uint32_t>(poly.vertices[k]),
                                static_cast<uint32_t>(poly.vertices[k + 1])});
    }
  }
  return mesh;
}

}  // namespace vscan::reconstruction
