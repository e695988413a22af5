#pragma once
// Ground truth of a finished scan per scene object: where it truly is, how many of the scan's
// points it gave, and how many it would give alone in the scene (cast over the pixels of its
// projected bounding box only, so that small objects cost little).

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "scenes/scene_registry.h"
#include "sensor/camera.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::service {

struct ObjectTruth {
  std::string object_id;
  std::string mesh_id;
  std::string label;
  uint32_t instance_id = 0;
  double scale = 1.0;
  Pose3 world_from_object = Pose3::Identity();
  Pose3 sensor_from_object = Pose3::Identity();
  uint64_t visible_points = 0;      // the scan's measurements with this instance id
  uint64_t unoccluded_points = 0;   // clean hits of the object cast alone
  double visible_fraction = 0.0;    // visible over unoccluded (0 when unoccluded is 0)
  // The pixels [u0, u1) x [v0, v1) the object covers cast alone; all 0 when it covers none.
  uint32_t alone_u0 = 0, alone_v0 = 0, alone_u1 = 0, alone_v1 = 0;
  // v * width + u of each pixel the object covers cast alone, ascending (its full silhouette).
  std::vector<uint32_t> alone_pixels;
};

// The fields a scan with ground truth must carry to be counted: the asked ones plus instance ids
// (and statuses when rejected rays are returned, which do not count as seen).
uint32_t FieldsForGroundTruth(uint32_t fields, bool include_rejected);

// Objects of target.scene the camera would see alone, in instance-id order. cloud must carry
// instance ids (statuses when it holds rejected rays).
StatusOr<std::vector<ObjectTruth>> ObjectGroundTruth(const scenes::ScanTarget& target,
                                                     const sensor::PinholeCamera& camera,
                                                     const Pose3& world_from_sensor, const PointCloud& cloud,
                                                     const std::atomic<bool>* cancel);

// Drops the arrays of fields the caller did not ask for.
void KeepFields(PointCloud& cloud, uint32_t fields);

}  // namespace vscan::service
