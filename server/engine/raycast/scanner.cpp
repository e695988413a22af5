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

// Appends every block to a cloud reserved for every pixel; never pauses.
class CloudSink final : public RowSink {
 public:
  CloudSink(uint32_t fields, size_t pixels) {
    cloud.fields = fields;
    ReserveForEveryPixel(cloud, pixels);
  }
  void Accept(const RowBlock& block) override { AppendRows(block, cloud); }
  bool HasRoom() override { return true; }
  void WaitForRoom() override {}

  PointCloud cloud;
};

Status CheckInputs(const sensor::PinholeCamera& camera, const Pose3& world_from_sensor) {
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, "camera", std::numeric_limits<uint64_t>::max()));
  if (!world_from_sensor.matrix().allFinite()) return InvalidArgument("world_from_sensor: NaN or infinite value");
  // The validated camera bounds the ray directions; this bounds their origin.
  if (!EmbreeAcceptsRay(world_from_sensor.translation().cast<float>(), Eigen::Vector3f::UnitZ(),
                        static_cast<float>(camera.near), static_cast<float>(camera.far))) {
    return InvalidArgument("world_from_sensor: translation beyond the range rays can be cast from");
  }
  return Status::Ok();
}

// Casts every strip in image order through the sink; false when cancelled.
bool CastStrips(const ScanSetup& setup, const std::atomic<bool>* cancel, RowSink& sink, ScanStats& stats) {
  const uint32_t strips = (setup.height + kPacketSide - 1) / kPacketSide;
  const auto threads = static_cast<size_t>(tbb::this_task_arena::max_concurrency());
  StripPool pool(setup.padded_width);
  uint32_t next_strip = 0;
  bool cancelled = false;
  float min_range = std::numeric_limits<float>::infinity();
  float max_range = 0;

  // Strips are numbered in image order, traced in parallel and delivered in order; the cancel
  // flag and the sink's room are polled before each strip. A full sink ends this pipeline, which
  // restarts at the next strip once the sink has room.
  const auto trace = [&](StripJob job) {
    TraceStrip(setup, job.strip, *job.hits);
    return job;
  };
  const auto deliver = [&](StripJob job) {
    sink.Accept(job.hits->Block());
    stats.points += job.hits->total();
    stats.rows += job.hits->rows;
    if (job.hits->total() > 0) {
      min_range = std::min(min_range, job.hits->min_range);
      max_range = std::max(max_range, job.hits->max_range);
    }
    pool.Give(job.hits);
  };
  while (next_strip < strips && !cancelled) {
    bool paused = false;
    const auto next = [&](tbb::flow_control& control) -> StripJob {
      if (next_strip == strips) {
        control.stop();
        return {};
      }
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
        cancelled = true;
        control.stop();
        return {};
      }
      if (!sink.HasRoom()) {
        paused = true;
        control.stop();
        return {};
      }
      return {next_strip++, pool.Take()};
    };
    tbb::parallel_pipeline(4 * threads,
                           tbb::make_filter<void, StripJob>(tbb::filter_mode::serial_in_order, next) &
                               tbb::make_filter<StripJob, StripJob>(tbb::filter_mode::parallel, trace) &
                               tbb::make_filter<StripJob, void>(tbb::filter_mode::serial_in_order, deliver));
    if (paused) sink.WaitForRoom();
  }
  stats.min_range = stats.points > 0 ? min_range : 0.0;
  stats.max_range = stats.points > 0 ? max_range : 0.0;
  return !cancelled;
}

double MillisSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

StatusOr<PointCloud> Scan(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                          const Pose3& world_from_sensor, const ScanOptions& options, ScanStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  RETURN_IF_ERROR(CheckInputs(camera, world_from_sensor));
  const ScanSetup setup = MakeScanSetup(scene, camera, world_from_sensor, options);
  CloudSink sink(setup.fields, camera.pixel_count());
  ScanStats local;
  local.rays = camera.pixel_count();
  if (!CastStrips(setup, options.cancel, sink, local)) return Cancelled("scan cancelled");
  TrimExcess(sink.cloud);
  local.elapsed_ms = MillisSince(start);
  if (stats != nullptr) *stats = local;
  return std::move(sink.cloud);
}

Status ScanRows(const RaycastScene& scene, const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                const ScanOptions& options, RowSink& sink, ScanStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  RETURN_IF_ERROR(CheckInputs(camera, world_from_sensor));
  const ScanSetup setup = MakeScanSetup(scene, camera, world_from_sensor, options);
  ScanStats local;
  local.rays = camera.pixel_count();
  const bool finished = CastStrips(setup, options.cancel, sink, local);
  local.elapsed_ms = MillisSince(start);
  if (stats != nullptr) *stats = local;
  return finished ? Status::Ok() : Cancelled("scan cancelled");
}

}  // namespace vscan::raycast
