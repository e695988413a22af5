#include "raycast/scanner.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "raycast/cloud_append.h"
#include "raycast/ray_bounds.h"
#include "raycast/scan_setup.h"
#include "raycast/strip_tracer.h"

namespace vscan::raycast {
namespace {

// Strip buffers recycled within one scan; at most the pipeline's live tokens exist at once.
class StripPool {
 public:
  explicit StripPool(uint32_t stride) : stride_(stride) {}
  StripHits* Take() {
    std::lock_guard lock(mutex_);
    if (!free_.empty()) {
      StripHits* hits = free_.back();
      free_.pop_back();
      return hits;
    }
    all_.push_back(std::make_unique<StripHits>(stride_));
    return all_.back().get();
  }
  void Give(StripHits* hits) {
    std::lock_guard lock(mutex_);
    free_.push_back(hits);
  }

 private:
  uint32_t stride_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<StripHits>> all_;
  std::vector<StripHits*> free_;
};

struct StripJob {
  uint32_t strip = 0;
  StripHits* hits = nullptr;
};

}  // namespace

StatusOr<PointCloud> Scan(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                          const Pose3& world_from_sensor, const ScanOptions& options, ScanStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, "camera", std::numeric_limits<uint64_t>::max()));
  if (!world_from_sensor.matrix().allFinite()) return InvalidArgument("world_from_sensor: NaN or infinite value");
  // The validated camera bounds the ray directions; this bounds their origin.
  if (!EmbreeAcceptsRay(world_from_sensor.translation().cast<float>(), Eigen::Vector3f::UnitZ(),
                        static_cast<float>(camera.near), static_cast<float>(camera.far))) {
    return InvalidArgument("world_from_sensor: translation beyond the range rays can be cast from");
  }

  const ScanSetup setup = MakeScanSetup(scene.impl(), camera, world_from_sensor, options);
  PointCloud cloud;
  cloud.fields = setup.fields;
  ReserveForEveryPixel(cloud, camera.pixel_count());

  const uint32_t strips = (camera.height + kPacketSide - 1) / kPacketSide;
  const auto threads = static_cast<size_t>(tbb::this_task_arena::max_concurrency());
  StripPool pool(setup.padded_width);
  uint32_t next_strip = 0;
  bool cancelled = false;
  float min_range = std::numeric_limits<float>::infinity();
  float max_range = 0;

  // Strips are numbered in image order, traced in parallel and appended in order; the cancel
  // flag is polled before each strip.
  const auto next = [&](tbb::flow_control& control) -> StripJob {
    if (next_strip == strips || (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed))) {
      cancelled = next_strip != strips;
      control.stop();
      return {};
    }
    return {next_strip++, pool.Take()};
  };
  const auto trace = [&](StripJob job) {
    TraceStrip(setup, job.strip, *job.hits);
    return job;
  };
  const auto append = [&](StripJob job) {
    AppendStrip(*job.hits, cloud);
    if (job.hits->total() > 0) {
      min_range = std::min(min_range, job.hits->min_range);
      max_range = std::max(max_range, job.hits->max_range);
    }
    pool.Give(job.hits);
  };
  tbb::parallel_pipeline(4 * threads, tbb::make_filter<void, StripJob>(tbb::filter_mode::serial_in_order, next) &
                                          tbb::make_filter<StripJob, StripJob>(tbb::filter_mode::parallel, trace) &
                                          tbb::make_filter<StripJob, void>(tbb::filter_mode::serial_in_order, append));
  if (cancelled) return Cancelled("scan cancelled");
  TrimExcess(cloud);

  if (stats != nullptr) {
    stats->rays = camera.pixel_count();
    stats->points = cloud.size();
    stats->min_range = cloud.size() > 0 ? min_range : 0.0;
    stats->max_range = cloud.size() > 0 ? max_range : 0.0;
    stats->elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return cloud;
}

}  // namespace vscan::raycast
