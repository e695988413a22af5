#include "feature_alignment_open3d.h"

#include <functional>
#include <memory>

#include <open3d/Open3D.h>

namespace vscan::bench {
namespace {

namespace reg = open3d::pipelines::registration;

std::shared_ptr<open3d::geometry::PointCloud> Cloud(const std::vector<Eigen::Vector3f>& points) {
  auto cloud = std::make_shared<open3d::geometry::PointCloud>();
  cloud->points_.reserve(points.size());
  for (const auto& p : points) cloud->points_.push_back(p.cast<double>());
  return cloud;
}

}  // namespace

bool Open3dAvailable() { return true; }

Open3dAlignment AlignWithOpen3d(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                                double voxel) {
  auto source_down = Cloud(source)->VoxelDownSample(voxel);
  auto target_down = Cloud(target)->VoxelDownSample(voxel);
  for (auto* cloud : {source_down.get(), target_down.get()}) {
    cloud->EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(2 * voxel, 30));
  }
  const auto source_fpfh = reg::ComputeFPFHFeature(*source_down, open3d::geometry::KDTreeSearchParamHybrid(5 * voxel, 100));
  const auto target_fpfh = reg::ComputeFPFHFeature(*target_down, open3d::geometry::KDTreeSearchParamHybrid(5 * voxel, 100));
  const double distance = 1.5 * voxel;
  const reg::CorrespondenceCheckerBasedOnEdgeLength edges(0.9);
  const reg::CorrespondenceCheckerBasedOnDistance near(distance);
  const auto coarse = reg::RegistrationRANSACBasedOnFeatureMatching(
      *source_down, *target_down, *source_fpfh, *target_fpfh, true, distance,
      reg::TransformationEstimationPointToPoint(false), 3, {std::cref(edges), std::cref(near)},
      reg::RANSACConvergenceCriteria(100000, 0.999));
  const auto fine = reg::RegistrationICP(*source_down, *target_down, distance, coarse.transformation_,
                                         reg::TransformationEstimationPointToPlane(),
                                         reg::ICPConvergenceCriteria(1e-7, 1e-7, 60));
  Open3dAlignment out;
  out.target_from_source = Pose3(fine.transformation_);
  out.fitness = fine.fitness_;
  return out;
}

}  // namespace vscan::bench
