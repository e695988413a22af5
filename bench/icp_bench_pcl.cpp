#include "icp_bench_pcl.h"

#include <limits>

#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>
#include <pcl/search/kdtree.h>

namespace vscan::bench {
namespace {

constexpr int kNormalThreads = 2;

// PCL keeps the iteration count protected.
class CountingIcp : public pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal, double> {
 public:
  int iterations() const { return nr_iterations_; }
};

pcl::PointCloud<pcl::PointNormal>::Ptr ToPcl(const IcpCloud& cloud) {
  auto out = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = cloud.points[i];
    p.getNormalVector3fMap() = cloud.normals[i];
    p.curvature = 0.0f;
    out->push_back(p);
  }
  return out;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr PointsOnly(const IcpCloud& cloud) {
  auto out = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : cloud.points) out->push_back({p.x(), p.y(), p.z()});
  return out;
}

}  // namespace

struct PclPeer::Clouds {
  pcl::PointCloud<pcl::PointNormal>::Ptr source, target;
  pcl::PointCloud<pcl::PointXYZ>::Ptr source_xyz, target_xyz;
};

PclPeer::PclPeer(const IcpPair& pair)
    : clouds_(std::make_unique<Clouds>(Clouds{ToPcl(pair.source), ToPcl(pair.target), PointsOnly(pair.source),
                                              PointsOnly(pair.target)})) {}

PclPeer::~PclPeer() = default;

IcpOutcome PclPeer::Icp(const PclIcpSettings& settings, double max_distance) const {
  using Point = pcl::PointNormal;
  CountingIcp icp;
  icp.setTransformationEstimation(
      std::make_shared<pcl::registration::TransformationEstimationPointToPlaneLLS<Point, Point, double>>());
  icp.setInputSource(clouds_->source);
  icp.setInputTarget(clouds_->target);
  icp.setMaxCorrespondenceDistance(max_distance);
  icp.setMaximumIterations(settings.max_iterations);
  icp.setTransformationEpsilon(settings.translation_epsilon);
  icp.setTransformationRotationEpsilon(settings.rotation_epsilon);
  icp.setEuclideanFitnessEpsilon(settings.relative_mse > 0.0 ? settings.relative_mse
                                                              : -std::numeric_limits<double>::max());
  pcl::PointCloud<Point> aligned;
  icp.align(aligned);
  return {icp.getFinalTransformation(), icp.iterations()};
}

void PclPeer::EstimateNormals(int k) const {
  for (const auto& cloud : {clouds_->source_xyz, clouds_->target_xyz}) {
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimator(kNormalThreads);
    estimator.setInputCloud(cloud);
    estimator.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    estimator.setKSearch(k);
    pcl::PointCloud<pcl::Normal> normals;
    estimator.compute(normals);
  }
}

}  // namespace vscan::bench
