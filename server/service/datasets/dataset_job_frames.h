#pragma once
// The frames of a dataset from the engine: for a scene (seed, bin, sensor) the bin is filled under
// the seed, its open box and settled parts become a scene in memory, and the sensor scans it from
// each of the plan's views (ray casting, the preset's measurement model seeded by the scene and
// view), with the scan's ground truth per part. Deterministic for a scene on one build.

#include <atomic>
#include <memory>

#include "service/datasets/format/dataset_run.h"
#include "service/datasets/dataset_job_setup.h"
#include "service/scan/scan_plan.h"

namespace vscan::service {

// world_from_camera of a view of a scene (dataset::SampleViewPose, seeded by the scene and view):
// with the default views, above the floor's centre at the plan's height, x along the bin's x,
// looking down its -z.
Pose3 DatasetCameraPose(const DatasetBinSetup& bin, const dataset::DatasetPlan& plan, const dataset::SceneKey& key,
                        uint32_t view);

// Keeps the latest fills, so that the sensors of one (seed, bin) share one; safe for concurrent
// calls (ShardRun::frames_ahead). cancel, when set, stops the fill and the scan with CANCELLED.
dataset::FrameSource BinFrameSource(std::shared_ptr<const DatasetSetup> setup, const std::atomic<bool>* cancel);

// The scan of a frame by sensor, before its pose and noise seed are set.
ScanPlan DatasetFramePlan(const DatasetSensorSetup& sensor);

// Frames to capture ahead of the one being written: one per further core (at most 7).
size_t DatasetFramesAhead();

}  // namespace vscan::service
