#include "registration/shot_descriptors.h"
#include "vscan/common/cancel_flag.h"

#include <algorithm>
#include <memory>

#include <pcl/features/shot.h>
#include <pcl/features/shot_lrf.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <tbb/parallel_for.h>

namespace vscan::registration {
namespace {

// Keypoints per task. PCL's own OpenMP loop is not used, so the work runs on TBB's threads (and
// within the caller's arena) like the rest of the engine.
constexpr size_t kDescriptorBatch = 256;

}  // namespace

StatusOr<ShotDescriptors> DescribeWithShot(std::span<const Eigen::Vector3f> points,
                                           std::span<const Eigen::Vector3f> normals,
                                           std::span<const uint32_t> keypoints, double radius,
                                           const std::atomic<bool>* cancel) {
  if (normals.size() != points.size()) return InvalidArgument("normals: one per point is needed");
  if (keypoints.empty()) return ShotDescriptors{};

  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  auto cloud_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  cloud->resize(points.size());
  cloud_normals->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    (*cloud)[i].getVector3fMap() = points[i];
    (*cloud_normals)[i].getNormalVector3fMap() = normals[i];
    (*cloud_normals)[i].curvature = 0.0f;
  }
  // One tree for every task; its searches only read it.
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>(false);
  tree->setInputCloud(cloud);

  // Each keypoint's descriptor; NaN where its local frame could not be fixed.
  pcl::PointCloud<pcl::SHOT352> described;
  described.resize(keypoints.size());
  std::atomic<bool> cancelled = false;
  const size_t batches = (keypoints.size() + kDescriptorBatch - 1) / kDescriptorBatch;
  tbb::parallel_for(size_t{0}, batches, [&](size_t batch) {
    if (IsCancelled(cancel)) {
      cancelled = true;
      return;
    }
    const size_t begin = batch * kDescriptorBatch, end = std::min(keypoints.size(), begin + kDescriptorBatch);
    auto indices = std::make_shared<pcl::Indices>(keypoints.begin() + static_cast<std::ptrdiff_t>(begin),
                                                  keypoints.begin() + static_cast<std::ptrdiff_t>(end));
    pcl::SHOTLocalReferenceFrameEstimation<pcl::PointXYZ, pcl::ReferenceFrame> frames_estimation;
    frames_estimation.setInputCloud(cloud);
    frames_estimation.setIndices(indices);
    frames_estimation.setSearchMethod(tree);
    frames_estimation.setRadiusSearch(radius);
    auto frames = std::make_shared<pcl::PointCloud<pcl::ReferenceFrame>>();
    frames_estimation.compute(*frames);

    pcl::SHOTEstimation<pcl::PointXYZ, pcl::Normal, pcl::SHOT352> shot;
    shot.setInputCloud(cloud);
    shot.setInputNormals(cloud_normals);
    shot.setIndices(indices);
    shot.setSearchMethod(tree);
    shot.setRadiusSearch(radius);
    shot.setInputReferenceFrames(frames);
    pcl::PointCloud<pcl::SHOT352> batch_described;
    shot.compute(batch_described);
    if (batch_described.size() != end - begin) return;  // left all zero, so dropped below
    std::copy(batch_described.begin(), batch_described.end(), described.begin() + static_cast<std::ptrdiff_t>(begin));
  });
  if (cancelled) return Cancelled("features: cancelled");

  ShotDescriptors out;
  out.values.resize(ShotDescriptors::kLength, static_cast<Eigen::Index>(keypoints.size()));
  Eigen::Index kept = 0;
  for (size_t k = 0; k < keypoints.size(); ++k) {
    const Eigen::Map<const Eigen::VectorXf> values(described[k].descriptor, ShotDescriptors::kLength);
    if (!values.allFinite() || values.squaredNorm() == 0.0f) continue;
    out.values.col(kept++) = values;
    out.points.push_back(keypoints[k]);
  }
  out.values.conservativeResize(Eigen::NoChange, kept);
  return out;
}

}  // namespace vscan::registration
