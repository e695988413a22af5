#pragma once
// One scan from a checked plan to its points: the scene (and visible robot links) it casts
// against, then either rows streamed while the cast runs or, for stages that need the whole image
// (the measurement model, the raster backends), the finished cloud.

#include <atomic>
#include <cstdint>
#include <optional>

#include "capture/measure_scan.h"
#include "capture/pixel_images.h"
#include "raycast/row_sink.h"
#include "raycast/scanner.h"
#include "service/scan/scan_ground_truth.h"
#include "service/scan/scan_plan.h"
#include "service/context/service_context.h"

namespace vscan::service {

// Where a scan's points go. Its RowSink side receives streamed rows and paces the cast.
class ScanConsumer : public raycast::RowSink {
 public:
  // Before any point: the scene revision cast, and the point count when the cloud is finished
  // before it is handed over (unknown while streaming).
  virtual void Begin(uint64_t scene_revision, std::optional<uint64_t> points) = 0;
  // The finished cloud; returns once it has been handed on, or CANCELLED.
  virtual Status Cloud(const PointCloud& cloud) = 0;
};

struct ScanOutcome {
  raycast::ScanStats stats;       // rows cast, rays, points (filled as far as the scan got)
  capture::MeasureStats measure;  // all zero on the clean path
  bool streamed = false;
  // With plan.ground_truth: the scene objects in view.
  std::vector<ObjectTruth> objects;
  // With plan.pixel_images: why each pixel has or lacks a point, and the grey image.
  std::optional<capture::PixelImages> images;
};

// Whether plan's points can leave row by row as they are cast (the clean ray caster).
bool StreamsRows(const ScanPlan& plan, const ServerOptions& options);

// Runs plan into out; stops with CANCELLED soon after *cancel is set. outcome is filled even when
// the scan fails.
Status RunScan(ServiceContext& context, const ScanPlan& plan, const std::atomic<bool>* cancel, ScanConsumer& out,
               ScanOutcome* outcome);

}  // namespace vscan::service
