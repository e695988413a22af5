#include "registration/shot_descriptors.h"

#include <algorithm>
#include <memory>

#include <pcl/features/shot_omp.h>
#include <pcl/point_types.h>

namespace vscan::registration {
namespace {

// Keypoints per call into PCL, so that cancellation is noticed within a fraction of a second.
constexpr size_t kBatch = 1024;

bool IsCancelled(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

}  // namespace

StatusOr<ShotDescriptors> DescribeWithShot(std::span<const Eigen::Vector3f> points,
                                           std::span<const Eigen::Vector3f> normals,
                                           std::span<const uint32_t> keypoints, double radius,
                                           const std::atomic<bool>* cancel) {
  if (normals.size() != points.size()) return InvalidArgument("normals: one per point is needed");
  ShotDescriptors out;
  out.values.resize(ShotDescriptors::kLength, static_cast<Eigen::Index>(keypoints.size()));
  if (keypoints.empty()) return out;

  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  auto cloud_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  cloud->resize(points.size());
  cloud_normals->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    (*cloud)[i].getVector3fMap() = points[i];
    (*cloud_normals)[i].getNormalVector3fMap() = normals[i];
    (*cloud_normals)[i].curvature = 0.0f;
  }
  pcl::SHOTEstimationOMP<pcl::PointXYZ, pcl::Normal, pcl::SHOT352> shot;
  shot.setInputCloud(cloud);
  shot.setInputNormals(cloud_normals);
  shot.setRadiusSearch(radius);

  Eigen::Index kept = 0;
  pcl::PointCloud<pcl::SHOT352> described;
  for (size_t begin = 0; begin < keypoints.size(); begin += kBatch) {
    if (IsCancelled(cancel)) return Cancelled("features: cancelled");
    const size_t end = std::min(keypoints.size(), begin + kBatch);
    auto batch = std::make_shared<pcl::Indices>(keypoints.begin() + static_cast<std::ptrdiff_t>(begin),
                                                keypoints.begin() + static_cast<std::ptrdiff_t>(end));
    shot.setIndices(batch);
    shot.compute(described);
    for (size_t b = 0; b < described.size(); ++b) {
      const Eigen::Map<const Eigen::VectorXf> values(described[b].descriptor, ShotDescriptors::kLength);
      if (!values.allFinite() || values.squaredNorm() == 0.0f) continue;
      out.values.col(kept++) = values;
      out.points.push_back(keypoints[begin + b]);
    }
  }
  out.values.conservativeResize(Eigen::NoChange, kept);
  return out;
}

}  // namespace vscan::registration
