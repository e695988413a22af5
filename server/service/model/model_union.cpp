#include "service/model/model_union.h"

#include <limits>

#include "reconstruction/union_cloud.h"
#include "service/model/model_scans.h"

namespace vscan::service {

size_t PlacedScans::total_points() const {
  size_t n = 0;
  for (const auto& p : points) n += p.size();
  return n;
}

StatusOr<PlacedScans> PlaceScans(const StoredClouds& clouds, const ModelPlan& plan, const AlignedScans& aligned,
                                 const ModelCrop& crop, const std::atomic<bool>* cancel) {
  PlacedScans placed;
  for (size_t i = 0; i < aligned.scans.size(); ++i) {
    const ScanAlignmentRecord& record = aligned.scans[i];
    if (!record.aligned) continue;
    if (cancel && cancel->load()) return Cancelled("model job stopped");
    ASSIGN_OR_RETURN(ModelScan scan, LoadModelScan(clouds, plan, i, ModelCrop{}));
    const Eigen::Isometry3f model_from_sensor = record.model_from_sensor.cast<float>();
    std::vector<Eigen::Vector3f> points;
    points.reserve(scan.points.size());
    for (const Eigen::Vector3f& p : scan.points) {
      const Eigen::Vector3f q = model_from_sensor * p;
      if (crop.Contains(q)) points.push_back(q);
    }
    placed.index.push_back(i);
    placed.points.push_back(std::move(points));
    placed.origins.push_back(record.model_from_sensor.translation().cast<float>());
  }
  return placed;
}

reconstruction::UnionCloud ThinnedUnion(const PlacedScans& scans, double voxel_size) {
  std::vector<reconstruction::ScanPoints> views;
  for (size_t k = 0; k < scans.points.size(); ++k) views.push_back({scans.points[k], scans.origins[k]});
  return reconstruction::VoxelDownsample(views, static_cast<float>(voxel_size));
}

double PlacedDiagonal(const PlacedScans& scans) {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f max = -min;
  bool any = false;
  for (const auto& points : scans.points) {
    for (const Eigen::Vector3f& p : points) {
      min = min.cwiseMin(p);
      max = max.cwiseMax(p);
      any = true;
    }
  }
  return any ? (max - min).cast<double>().norm() : 0.0;
}

}  // namespace vscan::service
