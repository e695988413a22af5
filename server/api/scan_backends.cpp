#include "api/scan_backends.h"

#include "raster/raster_scanner.h"
#include "sensor/measurement.h"

namespace vscan::api {
namespace {

StatusOr<PointCloud> RunRaster(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& provider,
                               const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  ASSIGN_OR_RETURN(raster::RasterRenderer * renderer, provider.Get());
  raster::RasterOptions options;
  options.fields = plan.fields;
  options.frame = plan.frame;
  options.cancel = cancel;
  const auto method = plan.backend == ScanBackend::kRasterDepth ? raster::RasterMethod::kDepthBuffer
                                                                 : raster::RasterMethod::kColourBuffer;
  raster::RasterStats raster_stats;
  ASSIGN_OR_RETURN(PointCloud cloud, raster::RasterScan(*renderer, target.cache_key, *target.instances, plan.camera,
                                                        plan.world_from_sensor, method, options, &raster_stats));
  stats->rays = raster_stats.pixels;
  stats->points = raster_stats.points;
  stats->min_range = raster_stats.min_range;
  stats->max_range = raster_stats.max_range;
  stats->elapsed_ms = raster_stats.elapsed_ms;
  return cloud;
}

StatusOr<PointCloud> RunClean(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                              const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  if (plan.backend != ScanBackend::kRaycast) return RunRaster(plan, target, raster, cancel, stats);
  raycast::ScanOptions options;
  options.fields = plan.fields;
  options.frame = plan.frame;
  options.cancel = cancel;
  return raycast::Scan(*target.raycast, plan.camera, plan.world_from_sensor, options, stats);
}

void SensorToWorld(const Pose3& world_from_sensor, PointCloud& cloud) {
  const Eigen::Affine3f transform(world_from_sensor.matrix().cast<float>());
  const Eigen::Matrix3f rotation = transform.linear();
  for (auto& p : cloud.positions) p = transform * p;
  for (auto& n : cloud.normals) n = rotation * n;
}

}  // namespace

StatusOr<PointCloud> RunScanBackend(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                                    const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  if (!plan.distortion.any() && !plan.noise.any()) return RunClean(plan, target, raster, cancel, stats);
  // The measurement model works in the sensor frame, so the clean scan is taken there first.
  ScanPlan sensor_plan = plan;
  sensor_plan.frame = raycast::ScanFrame::kSensor;
  ASSIGN_OR_RETURN(PointCloud cloud, RunClean(sensor_plan, target, raster, cancel, stats));
  RETURN_IF_ERROR(sensor::ApplyMeasurementModel(cloud, plan.distortion, plan.noise, plan.seed));
  if (plan.frame == raycast::ScanFrame::kWorld) SensorToWorld(plan.world_from_sensor, cloud);
  stats->points = cloud.size();
  return cloud;
}

}  // namespace vscan::api
