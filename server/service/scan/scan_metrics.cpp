#include "service/scan/scan_metrics.h"

#include "observability/server_metrics.h"

namespace vscan::service {
namespace {

const char* BackendLabel(ScanBackend backend) {
  switch (backend) {
    case ScanBackend::kRaycast: return "raycast";
    case ScanBackend::kRasterDepth: return "raster_depth";
    case ScanBackend::kRasterColour: return "raster_colour";
  }
  return "unknown";
}

const char* ResultLabel(const Status& status) {
  if (status.ok()) return "ok";
  return status.code() == StatusCode::kCancelled ? "cancelled" : "error";
}

}  // namespace

void RecordScan(ScanBackend backend, const Status& status, const raycast::ScanStats& stats, double seconds) {
  auto& metrics = observability::Metrics();
  metrics.scans.WithLabels({BackendLabel(backend), ResultLabel(status)}).Increment();
  // Cancelled and failed scans cast rays too.
  metrics.scan_rays.Increment(static_cast<double>(stats.rays));
  if (!status.ok()) return;
  metrics.scan_duration.WithLabels({BackendLabel(backend)}).Observe(seconds);
  if (seconds > 0 && stats.rays > 0) metrics.scan_rays_per_second.Observe(static_cast<double>(stats.rays) / seconds);
}

}  // namespace vscan::service
