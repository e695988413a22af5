#include "service/scan/scan_backends.h"

#include <chrono>
#include <vector>

#include "raster/raster_scanner.h"
#include "service/scan/scan_metrics.h"

namespace vscan::service {
namespace {

void CopyStats(const raster::RasterStats& raster_stats, raycast::ScanStats* stats) {
  stats->rays = raster_stats.pixels;
  stats->points = raster_stats.points;
  stats->min_range = raster_stats.min_range;
  stats->max_range = raster_stats.max_range;
  stats->elapsed_ms = raster_stats.elapsed_ms;
}

raster::RasterMethod MethodOf(const ScanPlan& plan) {
  return plan.backend == ScanBackend::kRasterDepth ? raster::RasterMethod::kDepthBuffer
                                                   : raster::RasterMethod::kColourBuffer;
}

raster::RasterOptions RasterOptionsFor(uint32_t fields, raycast::ScanFrame frame, const std::atomic<bool>* cancel) {
  raster::RasterOptions options;
  options.fields = fields;
  options.frame = frame;
  options.cancel = cancel;
  return options;
}

StatusOr<PointCloud> RunRaster(const ScanPlan& plan, const sensor::PinholeCamera& camera, uint32_t fields,
                               raycast::ScanFrame frame, const scenes::ScanTarget& target, RasterProvider& provider,
                               const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  ASSIGN_OR_RETURN(raster::RasterRenderer * renderer, provider.Get());
  raster::RasterStats raster_stats;
  ASSIGN_OR_RETURN(PointCloud cloud,
                   raster::RasterScan(*renderer, target.cache_key, *target.instances, camera, plan.world_from_sensor,
                                      MethodOf(plan), RasterOptionsFor(fields, frame, cancel), &raster_stats));
  CopyStats(raster_stats, stats);
  return cloud;
}

// The clean sensor-frame scan under a measured one with returned light: the shaders evaluate the
// light's direct term per pixel.
StatusOr<raster::LitCloud> RunLitRaster(const ScanPlan& plan, uint32_t fields, const capture::ReturnedLightSpec& light,
                                        const scenes::ScanTarget& target, RasterProvider& provider,
                                        const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  ASSIGN_OR_RETURN(raster::RasterRenderer * renderer, provider.Get());
  raster::DirectLight direct{light.emitter, light.materials, light.default_material};
  raster::RasterStats raster_stats;
  ASSIGN_OR_RETURN(raster::LitCloud lit,
                   raster::RasterScanLit(*renderer, target.cache_key, *target.instances, plan.camera,
                                         plan.world_from_sensor, MethodOf(plan), direct,
                                         RasterOptionsFor(fields, raycast::ScanFrame::kSensor, cancel), &raster_stats));
  CopyStats(raster_stats, stats);
  return lit;
}

StatusOr<PointCloud> RunClean(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                              const std::atomic<bool>* cancel, raycast::ScanStats* stats) {
  if (plan.backend != ScanBackend::kRaycast) {
    return RunRaster(plan, plan.camera, plan.fields, plan.frame, target, raster, cancel, stats);
  }
  raycast::ScanOptions options;
  options.fields = plan.fields;
  options.frame = plan.frame;
  options.cancel = cancel;
  return raycast::Scan(*target.raycast, plan.camera, plan.world_from_sensor, options, stats);
}

// The raster backends keep the plan's depth range (their depth precision follows near and far), so
// they report no out-of-range rejections and see through surfaces nearer than near. Their returned
// light is the direct term only, from their shaders: the indirect light's bounces are Embree rays of
// the ray-cast backend.
StatusOr<PointCloud> RunMeasuredRaster(const ScanPlan& plan, capture::MeasurementSpec spec,
                                       const scenes::ScanTarget& target, RasterProvider& raster,
                                       const std::atomic<bool>* cancel, raycast::ScanStats* stats,
                                       capture::MeasureStats* measure_stats) {
  const uint32_t fields = capture::CleanFieldsFor(spec);
  raster::LitCloud clean;
  if (spec.returned_light) {
    spec.returned_light->indirect_samples = 0;
    ASSIGN_OR_RETURN(clean, RunLitRaster(plan, fields, *spec.returned_light, target, raster, cancel, stats));
  } else {
    ASSIGN_OR_RETURN(clean.cloud, RunRaster(plan, plan.camera, fields, raycast::ScanFrame::kSensor, target, raster,
                                            cancel, stats));
  }
  ASSIGN_OR_RETURN(PointCloud cloud,
                   capture::MeasureScan(*target.raycast, plan.camera, plan.world_from_sensor, std::move(clean.cloud),
                                        spec, cancel, measure_stats, clean.direct_radiance));
  if (plan.frame == raycast::ScanFrame::kWorld) capture::SensorToWorld(plan.world_from_sensor, cloud);
  return cloud;
}

// Instance ids are small integers the scene hands out; past this a ray takes the default material.
constexpr uint32_t kMaxMaterialIds = 1u << 20;

// The returned light sees each object's material (scenes resolve it into the instances).
capture::MeasurementSpec WithObjectMaterials(capture::MeasurementSpec spec, const scenes::ScanTarget& target) {
  if (!spec.returned_light || !target.instances) return spec;
  std::vector<sensor::Material>& materials = spec.returned_light->materials;
  for (const raycast::SceneInstance& instance : *target.instances) {
    if (instance.instance_id == 0 || instance.instance_id >= kMaxMaterialIds) continue;
    if (materials.size() <= instance.instance_id) {
      materials.resize(instance.instance_id + 1, spec.returned_light->default_material);
    }
    materials[instance.instance_id] = instance.material;
  }
  return spec;
}

StatusOr<PointCloud> RunBackend(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                                const std::atomic<bool>* cancel, raycast::ScanStats* stats,
                                capture::MeasureStats* measure_stats) {
  const capture::MeasurementSpec spec = WithObjectMaterials(plan.measurement, target);
  if (measure_stats) *measure_stats = capture::MeasureStats{};
  if (!spec.any()) return RunClean(plan, target, raster, cancel, stats);
  capture::MeasureStats local;
  capture::MeasureStats& m = measure_stats ? *measure_stats : local;
  StatusOr<PointCloud> cloud =
      plan.backend == ScanBackend::kRaycast
          ? capture::ScanMeasured(*target.raycast, plan.camera, plan.world_from_sensor, spec, plan.frame, cancel,
                                  stats, &m)
          : RunMeasuredRaster(plan, spec, target, raster, cancel, stats, &m);
  if (!cloud.ok()) return cloud.status();
  stats->points = m.points;
  stats->min_range = m.min_range;
  stats->max_range = m.max_range;
  return cloud;
}

}  // namespace

StatusOr<PointCloud> RunScanBackend(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                                    const std::atomic<bool>* cancel, raycast::ScanStats* stats,
                                    capture::MeasureStats* measure_stats) {
  const auto start = std::chrono::steady_clock::now();
  StatusOr<PointCloud> cloud = RunBackend(plan, target, raster, cancel, stats, measure_stats);
  RecordScan(plan.backend, cloud.status(), *stats,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return cloud;
}

}  // namespace vscan::service
