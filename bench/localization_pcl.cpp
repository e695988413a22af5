#include "localization_pcl.h"

#include <cmath>

#include <pcl/features/fpfh_omp.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace vscan::bench {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;
using Features = pcl::PointCloud<pcl::FPFHSignature33>;

constexpr double kFeatureStepVoxels = 2.5;
constexpr double kMinScore = 0.1;

Cloud::Ptr Thin(const Cloud::Ptr& cloud, double leaf) {
  pcl::VoxelGrid<pcl::PointNormal> grid;
  grid.setInputCloud(cloud);
  const auto l = static_cast<float>(leaf);
  grid.setLeafSize(l, l, l);
  Cloud::Ptr thin(new Cloud);
  grid.filter(*thin);
  for (auto& p : *thin) p.getNormalVector3fMap().normalize();
  return thin;
}

Features::Ptr Fpfh(const Cloud::Ptr& cloud, double radius) {
  pcl::FPFHEstimationOMP<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> fpfh;
  fpfh.setInputCloud(cloud);
  fpfh.setInputNormals(cloud);
  fpfh.setRadiusSearch(radius);
  Features::Ptr features(new Features);
  fpfh.compute(*features);
  return features;
}

double InlierShare(const Cloud& model, const Eigen::Matrix4f& pose, const pcl::KdTreeFLANN<pcl::PointNormal>& scan,
                   double distance) {
  Cloud placed;
  pcl::transformPointCloud(model, placed, pose);
  std::vector<int> index(1);
  std::vector<float> sq(1);
  size_t inliers = 0;
  for (const auto& p : placed) {
    if (scan.nearestKSearch(p, 1, index, sq) == 1 && sq[0] <= distance * distance) ++inliers;
  }
  return model.empty() ? 0 : static_cast<double>(inliers) / static_cast<double>(model.size());
}

}  // namespace

std::vector<PclInstance> PclLocalize(std::span<const Eigen::Vector3f> model_points,
                                     std::span<const Eigen::Vector3f> model_normals,
                                     std::span<const Eigen::Vector3f> scan_points, const Eigen::Vector3f& viewpoint,
                                     double voxel, size_t max_instances) {
  const double step = kFeatureStepVoxels * voxel;
  Cloud::Ptr model(new Cloud);
  for (size_t i = 0; i < model_points.size(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = model_points[i];
    p.getNormalVector3fMap() = model_normals[i];
    model->push_back(p);
  }
  Cloud::Ptr scan(new Cloud);
  for (const auto& q : scan_points) {
    pcl::PointNormal p;
    p.getVector3fMap() = q;
    scan->push_back(p);
  }

  // The plate.
  pcl::SACSegmentation<pcl::PointNormal> plane;
  plane.setModelType(pcl::SACMODEL_PLANE);
  plane.setMethodType(pcl::SAC_RANSAC);
  plane.setDistanceThreshold(1.5 * voxel);
  plane.setInputCloud(scan);
  pcl::PointIndices::Ptr on_plane(new pcl::PointIndices);
  pcl::ModelCoefficients coefficients;
  plane.segment(*on_plane, coefficients);
  pcl::ExtractIndices<pcl::PointNormal> extract;
  extract.setInputCloud(scan);
  extract.setIndices(on_plane);
  extract.setNegative(true);
  Cloud::Ptr parts(new Cloud);
  extract.filter(*parts);

  pcl::NormalEstimationOMP<pcl::PointNormal, pcl::PointNormal> normals;
  normals.setInputCloud(parts);
  normals.setRadiusSearch(2 * voxel);
  normals.setViewPoint(viewpoint.x(), viewpoint.y(), viewpoint.z());
  normals.compute(*parts);
  const pcl::KdTreeFLANN<pcl::PointNormal> parts_tree = [&] {
    pcl::KdTreeFLANN<pcl::PointNormal> tree;
    tree.setInputCloud(parts);
    return tree;
  }();

  Cloud::Ptr model_thin = Thin(model, step);
  Cloud::Ptr model_fine = Thin(model, voxel);
  const Features::Ptr model_features = Fpfh(model_thin, 5 * step);
  Cloud::Ptr scene = Thin(parts, step);
  Features::Ptr scene_features = Fpfh(scene, 5 * step);

  std::vector<PclInstance> found;
  while (found.size() < max_instances && scene->size() > 10) {
    pcl::SampleConsensusPrerejective<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> align;
    align.setInputSource(model_thin);
    align.setSourceFeatures(model_features);
    align.setInputTarget(scene);
    align.setTargetFeatures(scene_features);
    align.setMaximumIterations(20000);
    align.setNumberOfSamples(3);
    align.setCorrespondenceRandomness(5);
    align.setSimilarityThreshold(0.9f);
    align.setMaxCorrespondenceDistance(1.5 * step);
    align.setInlierFraction(0.25f);
    Cloud aligned;
    align.align(aligned);
    if (!align.hasConverged()) break;

    pcl::IterativeClosestPoint<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setInputSource(model_fine);
    icp.setInputTarget(parts);
    icp.setMaxCorrespondenceDistance(2 * voxel);
    icp.setMaximumIterations(30);
    Cloud refined;
    icp.align(refined, align.getFinalTransformation());
    const Eigen::Matrix4f pose = icp.hasConverged() ? icp.getFinalTransformation() : align.getFinalTransformation();
    const double score = InlierShare(*model_fine, pose, parts_tree, 1.5 * voxel);
    if (score < kMinScore) break;
    PclInstance instance;
    instance.world_from_part.matrix() = pose.cast<double>();
    instance.score = score;
    found.push_back(instance);

    // The scene points the placed part covers go, with their features.
    Cloud placed;
    pcl::transformPointCloud(*model_fine, placed, pose);
    Cloud::Ptr placed_ptr(new Cloud(placed));
    pcl::KdTreeFLANN<pcl::PointNormal> placed_tree;
    placed_tree.setInputCloud(placed_ptr);
    Cloud::Ptr kept(new Cloud);
    Features::Ptr kept_features(new Features);
    std::vector<int> index(1);
    std::vector<float> sq(1);
    for (size_t i = 0; i < scene->size(); ++i) {
      if (placed_tree.nearestKSearch((*scene)[i], 1, index, sq) == 1 && sq[0] <= step * step) continue;
      kept->push_back((*scene)[i]);
      kept_features->push_back((*scene_features)[i]);
    }
    if (kept->size() == scene->size()) break;
    scene = kept;
    scene_features = kept_features;
  }
  return found;
}

}  // namespace vscan::bench
