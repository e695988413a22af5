#pragma once
// The aligned scans placed in the model frame: each aligned scan read again, moved by its final
// pose and cropped; and their union evened out to one point per voxel.

#include <atomic>
#include <vector>

#include <Eigen/Core>

#include "reconstruction/union_cloud.h"
#include "service/model/model_alignment.h"
#include "service/model/model_crop.h"
#include "service/model/model_plan.h"

namespace vscan::service {

struct PlacedScans {
  std::vector<size_t> index;                          // the scan's index in the plan
  std::vector<std::vector<Eigen::Vector3f>> points;   // model frame, cropped
  std::vector<Eigen::Vector3f> origins;               // the sensor's position, model frame
  size_t total_points() const;
};

// Only the scans alignment placed (aligned = true). CANCELLED when cancel becomes true.
StatusOr<PlacedScans> PlaceScans(const StoredClouds& clouds, const ModelPlan& plan, const AlignedScans& aligned,
                                 const ModelCrop& crop, const std::atomic<bool>* cancel);

// One point per voxel of edge voxel_size (the centroid of the points in it), with the mean
// direction towards the sensors that saw it.
reconstruction::UnionCloud ThinnedUnion(const PlacedScans& scans, double voxel_size);

// Bounding-box diagonal of every placed point.
double PlacedDiagonal(const PlacedScans& scans);

}  // namespace vscan::service
