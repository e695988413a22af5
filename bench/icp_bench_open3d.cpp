#include "icp_bench_open3d.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>

namespace vscan::bench {
namespace {

namespace registration = open3d::pipelines::registration;

open3d::geometry::PointCloud ToOpen3d(const IcpCloud& cloud) {
  open3d::geometry::PointCloud out;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    out.points_.push_back(cloud.points[i].cast<double>());
    out.normals_.push_back(cloud.normals[i].cast<double>());
  }
  return out;
}

}  // namespace

struct Open3dPeer::Clouds {
  open3d::geometry::PointCloud source, target;
};

Open3dPeer::Open3dPeer(const IcpPair& pair)
    : clouds_(std::make_unique<Clouds>(Clouds{ToOpen3d(pair.source), ToOpen3d(pair.target)})) {}

Open3dPeer::~Open3dPeer() = default;

IcpOutcome Open3dPeer::Icp(double relative, int max_iterations, double max_distance) const {
  const registration::RegistrationResult result = registration::RegistrationICP(
      clouds_->source, clouds_->target, max_distance, Eigen::Matrix4d::Identity(),
      registration::TransformationEstimationPointToPlane(),
      registration::ICPConvergenceCriteria(relative, relative, max_iterations));
  return {result.transformation_, 0};
}

}  // namespace vscan::bench
