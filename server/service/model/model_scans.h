#pragma once
// A model job's clouds read back as scans: points in the sensor frame, the pose alignment starts
// from (the commanded sensor pose of a campaign scan, the given sensor pose of an upload, or none)
// and the true pose when the server knows it (a campaign scan's achieved pose), all in the model
// frame.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sensor/camera.h"
#include "service/clouds/cloud_store.h"
#include "service/model/model_crop.h"
#include "service/model/model_plan.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::service {

struct ModelScan {
  size_t index = 0;
  std::string cloud_id;
  std::string name;
  // Sensor frame. Points the crop drops (under the initial pose, when it is known) are gone.
  std::vector<Eigen::Vector3f> points;
  // The pixel of each point, when the cloud has them.
  std::vector<uint32_t> pixels;
  std::optional<sensor::PinholeCamera> camera;
  // Where the sensor stood in the points' frame, when known (the origin of a sensor-frame cloud, or
  // of a world-frame cloud with a sensor pose, which is brought into its sensor frame).
  std::optional<Eigen::Vector3f> sensor_origin;
  // The initial pose is unknown: alignment finds it from features.
  bool features = false;
  Pose3 initial_model_from_sensor = Pose3::Identity();
  // How firmly the initial pose is known, when it is (ModelCloud::initial_information).
  std::optional<Eigen::Matrix<double, 6, 6>> initial_information;
  std::optional<Pose3> true_model_from_sensor;
};

// Reads plan.clouds[index]. crop applies to scans whose initial pose is known.
StatusOr<ModelScan> LoadModelScan(const StoredClouds& clouds, const ModelPlan& plan, size_t index,
                                  const ModelCrop& crop);

// The same from points already in memory (a campaign's scan just captured), framed as cloud.record says.
ModelScan ModelScanFromPoints(const ModelPlan& plan, const ModelCloud& cloud, size_t index, const PointCloud& points,
                              const ModelCrop& crop);

sensor::PinholeCamera CameraFromRecord(const store::CloudCamera& camera);

}  // namespace vscan::service
