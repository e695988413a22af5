#include "service/scan/scan_run.h"

#include <chrono>

#include "service/scan/request_memory.h"
#include "service/scan/scan_backends.h"
#include "service/scan/scan_metrics.h"
#include "service/scan/scan_pixel_images.h"
#include "service/scan/scan_target.h"

namespace vscan::service {

bool StreamsRows(const ScanPlan& plan, const ServerOptions& options) {
  return plan.backend == ScanBackend::kRaycast && !plan.measurement.any() && !plan.ground_truth &&
         !plan.pixel_images && !options.whole_cloud_scans;
}

Status RunScan(ServiceContext& context, const ScanPlan& plan, const std::atomic<bool>* cancel, ScanConsumer& out,
               ScanOutcome* outcome) {
  *outcome = ScanOutcome{};
  RETURN_IF_ERROR(CheckRequestMemory(ScanMemoryBytes(plan, StreamsRows(plan, context.options)),
                                     context.options.limits, "sensor", "this scan"));
  ASSIGN_OR_RETURN(const scenes::ScanTarget target, PrepareScanTarget(context, plan));
  outcome->streamed = StreamsRows(plan, context.options);
  if (outcome->streamed) {
    out.Begin(target.scene.revision, std::nullopt);
    raycast::ScanOptions options;
    options.fields = plan.fields;
    options.frame = plan.frame;
    options.cancel = cancel;
    const auto start = std::chrono::steady_clock::now();
    const Status status =
        raycast::ScanRows(*target.raycast, plan.camera, plan.world_from_sensor, options, out, &outcome->stats);
    RecordScan(plan.backend, status, outcome->stats,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return status;
  }
  if (!plan.ground_truth && !plan.pixel_images) {
    ASSIGN_OR_RETURN(const PointCloud cloud,
                     RunScanBackend(plan, target, context.raster, cancel, &outcome->stats, &outcome->measure));
    out.Begin(target.scene.revision, cloud.size());
    return out.Cloud(cloud);
  }
  // Ground truth counts instances and per-pixel images need every ray's status: measure more than
  // was asked, then hand on only that.
  ScanPlan counted = plan;
  if (plan.ground_truth) counted.fields = FieldsForGroundTruth(plan.fields, plan.measurement.include_rejected);
  counted.measurement.fields = counted.fields;
  if (plan.pixel_images) counted = WithPixelImageFields(std::move(counted));
  ASSIGN_OR_RETURN(PointCloud cloud,
                   RunScanBackend(counted, target, context.raster, cancel, &outcome->stats, &outcome->measure));
  if (plan.pixel_images) outcome->images = TakePixelImages(plan, cloud);
  if (plan.ground_truth) {
    ASSIGN_OR_RETURN(outcome->objects,
                     ObjectGroundTruth(target, plan.camera, plan.world_from_sensor, cloud, cancel));
  }
  KeepFields(cloud, plan.fields);
  out.Begin(target.scene.revision, cloud.size());
  return out.Cloud(cloud);
}

}  // namespace vscan::service
