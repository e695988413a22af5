#include "service/model/model_scans.h"

#include <limits>

#include "service/clouds/cloud_store.h"
#include "service/model/model_frame.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {

sensor::PinholeCamera CameraFromRecord(const store::CloudCamera& c) {
  sensor::PinholeCamera camera;
  camera.width = c.width;
  camera.height = c.height;
  camera.fx = c.fx;
  camera.fy = c.fy;
  camera.cx = c.cx;
  camera.cy = c.cy;
  camera.near = c.near;
  camera.far = c.far;
  return camera;
}

StatusOr<ModelScan> LoadModelScan(const StoredClouds& clouds, const ModelPlan& plan, size_t index,
                                  const ModelCrop& crop) {
  const ModelCloud& cloud = plan.clouds.at(index);
  const store::CloudRecord& record = cloud.record;
  ASSIGN_OR_RETURN(const StoredCloud stored, LoadCloud(clouds, record.cloud_id));
  ASSIGN_OR_RETURN(const PointCloud points,
                   ParsePly(stored.ply, "cloud '" + record.cloud_id + "'", std::numeric_limits<uint64_t>::max()));
  return ModelScanFromPoints(plan, cloud, index, points, crop);
}

ModelScan ModelScanFromPoints(const ModelPlan& plan, const ModelCloud& cloud, size_t index, const PointCloud& points,
                              const ModelCrop& crop) {
  const store::CloudRecord& record = cloud.record;
  ModelScan scan;
  scan.index = index;
  scan.cloud_id = record.cloud_id;
  scan.name = record.name;
  if (record.camera) scan.camera = CameraFromRecord(*record.camera);

  const Pose3 model_from_world = ModelFromWorld(cloud.table, record.table_angle_deg);
  std::optional<Pose3> world_from_sensor;
  if (record.world_from_sensor) world_from_sensor = Pose3(*record.world_from_sensor);
  // A world-frame cloud without a sensor pose keeps its world coordinates as its "sensor" frame.
  const Pose3 sensor_from_points = record.frame == store::CloudFrame::kWorld && world_from_sensor
                                       ? world_from_sensor->inverse()
                                       : Pose3::Identity();
  if (record.frame != store::CloudFrame::kWorld || world_from_sensor) scan.sensor_origin = Eigen::Vector3f::Zero();
  const Pose3 world_from_points = record.frame == store::CloudFrame::kWorld ? Pose3::Identity()
                                                                            : world_from_sensor.value_or(Pose3::Identity());

  if (record.origin == store::CloudOrigin::kCampaignScan && world_from_sensor) {
    scan.true_model_from_sensor = model_from_world * *world_from_sensor;
  }
  if (!plan.align) {
    // Taken as they are: the stored pose, or the world placement of a world-frame cloud.
    scan.initial_model_from_sensor = model_from_world * (world_from_sensor ? *world_from_sensor : world_from_points);
  } else if (plan.initial_pose == InitialPoseMode::kFeatures) {
    scan.features = true;
  } else if (cloud.commanded_world_from_sensor) {
    scan.initial_model_from_sensor = model_from_world * *cloud.commanded_world_from_sensor;
    scan.initial_information = cloud.initial_information;
  } else if (world_from_sensor) {
    scan.initial_model_from_sensor = model_from_world * *world_from_sensor;
  } else {
    scan.features = true;
  }

  const bool pixels = points.Has(kFieldPixel) && points.pixels.size() == points.size();
  const Eigen::Isometry3f to_sensor = sensor_from_points.cast<float>();
  const Eigen::Isometry3f to_model = scan.initial_model_from_sensor.cast<float>();
  scan.points.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points.positions[i].allFinite()) continue;
    const Eigen::Vector3f p = to_sensor * points.positions[i];
    if (!scan.features && !crop.Contains(to_model * p)) continue;
    scan.points.push_back(p);
    if (pixels) scan.pixels.push_back(points.pixels[i]);
  }
  return scan;
}

}  // namespace vscan::service
