#include "api/scan_service.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "api/chunk_packer.h"
#include "api/scan_backends.h"
#include "api/scan_messages.h"
#include "api/scan_outbox.h"
#include "api/scan_request.h"
#include "api/scan_target.h"
#include "api/write_watch.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/grpc_status.h"
#include "vscan/common/point_chunks.h"

namespace vscan::api {
namespace {

using Clock = std::chrono::steady_clock;

double MillisSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Packed chunks that may wait for the client, about 8 MiB of them.
size_t ChunkWindow(size_t chunk_bytes) { return std::max<size_t>(2, (8u << 20) / std::max<size_t>(1, chunk_bytes)); }

std::unique_ptr<v1::ScanResponse> Message() { return std::make_unique<v1::ScanResponse>(); }

// One reactor per Scan call. A worker thread produces the messages (the ray caster packs chunks as
// rows finish; other backends pack their finished cloud) into a bounded outbox that gRPC drains.
class ScanReactor final : public grpc::ServerWriteReactor<v1::ScanResponse> {
 public:
  ScanReactor(const v1::ScanRequest& request, grpc::CallbackServerContext* ctx, ServiceContext& context)
      : context_(context),
        write_watch_(context.stalled_readers, ctx),
        outbox_(
            ChunkWindow(request.chunk_bytes() ? request.chunk_bytes() : kDefaultChunkBytes),
            [this](const v1::ScanResponse* message) {
              write_watch_.Started("scan of " + plan_.scene_id);
              StartWrite(message);
            },
            [this](const grpc::Status& status) { Finish(status); }) {
    Status status = CheckToken(*ctx, context.options.token);
    if (!status.ok()) {
      Fail(status);
      return;
    }
    auto plan = ParseScanRequest(request, context.options.limits, context.robots);
    if (!plan.ok()) {
      Fail(plan.status());
      return;
    }
    plan_ = std::move(plan).value();
    points_per_chunk_ = PointsPerChunk(plan_.fields, plan_.chunk_bytes);
    if (request.chunk_bytes() == 0) points_per_chunk_ = std::min(points_per_chunk_, kDefaultChunkPoints);
    if (context_.active_scans.fetch_add(1) >= context_.options.limits.max_concurrent_scans) {
      context_.active_scans.fetch_sub(1);
      Fail(ResourceExhausted("scan: " + std::to_string(context.options.limits.max_concurrent_scans) +
                             " scans already running; retry later"));
      return;
    }
    holds_slot_ = true;
    if (!context_.workers.Post([this] { Run(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnCancel() override {
    StopProducing();
    spdlog::info("scan of {}: call cancelled", plan_.scene_id);
  }

  void OnWriteDone(bool ok) override {
    write_watch_.Done();
    if (!ok) StopProducing();
    outbox_.WriteDone(ok);
  }

  void OnDone() override {
    write_watch_.Release();
    if (holds_slot_) context_.active_scans.fetch_sub(1);
    delete this;
  }

 private:
  void StopProducing() {
    int64_t none = 0;
    cancelled_at_.compare_exchange_strong(none, Clock::now().time_since_epoch().count());
    cancel_.store(true);
    outbox_.Cancel();
  }

  // On a worker thread; its last act is closing the outbox.
  void Run() {
    // Queued behind other work while the call was cancelled (server shutdown, client gone).
    if (cancel_.load()) {
      Fail(Cancelled("scan cancelled"));
      return;
    }
    auto target = PrepareScanTarget(context_, plan_);
    if (!target.ok()) {
      Fail(target.status());
      return;
    }
    const bool streamed = plan_.backend == ScanBackend::kRaycast && !plan_.measurement.any() &&
                          !context_.options.whole_cloud_scans;
    const Status status = streamed ? Stream(*target) : SendWholeCloud(*target);
    if (!status.ok()) {
      Fail(status);
      return;
    }
    outbox_.Close(grpc::Status::OK);
  }

  // Rows are packed into chunks as the cast finishes them; the header goes first.
  Status Stream(const scenes::ScanTarget& target) {
    auto header = Message();
    FillScanHeader(plan_, target.scene.revision, header->mutable_header());
    outbox_.Push(std::move(header));
    ChunkPacker packer(plan_.fields, points_per_chunk_, outbox_);
    raycast::ScanOptions options;
    options.fields = plan_.fields;
    options.frame = plan_.frame;
    options.cancel = &cancel_;
    raycast::ScanStats stats;
    const Status cast = raycast::ScanRows(*target.raycast, plan_.camera, plan_.world_from_sensor, options, packer, &stats);
    if (cast.code() == StatusCode::kCancelled) {
      const auto since = Clock::now() - Clock::time_point(Clock::duration(cancelled_at_.load()));
      spdlog::info("scan of {}: cancelled after {} of {} rows; the cast stopped {:.1f} ms after the cancel",
                   plan_.scene_id, stats.rows, plan_.camera.height,
                   std::chrono::duration<double, std::milli>(since).count());
    }
    RETURN_IF_ERROR(cast);
    packer.Flush();
    SendStatistics(target, stats, capture::MeasureStats{}, packer.points(), packer.chunks());
    return Status::Ok();
  }

  // Stages that need neighbours (the measurement model) and the raster backends finish the cloud,
  // then it is packed here, a window of chunks at a time.
  Status SendWholeCloud(const scenes::ScanTarget& target) {
    raycast::ScanStats stats;
    capture::MeasureStats measure;
    ASSIGN_OR_RETURN(PointCloud cloud, RunScanBackend(plan_, target, context_.raster, &cancel_, &stats, &measure));
    const size_t per_chunk = points_per_chunk_;
    const auto chunks = static_cast<uint32_t>((cloud.size() + per_chunk - 1) / per_chunk);
    auto header = Message();
    FillScanHeader(plan_, target.scene.revision, header->mutable_header());
    header->mutable_header()->set_points(cloud.size());
    header->mutable_header()->set_chunk_count(chunks);
    outbox_.Push(std::move(header));
    for (uint32_t i = 0; i < chunks; ++i) {
      if (!outbox_.HasRoom()) outbox_.WaitForRoom();
      if (cancel_.load()) return Cancelled("scan cancelled");
      const size_t begin = size_t{i} * per_chunk;
      auto message = Message();
      PackChunk(cloud, begin, std::min(per_chunk, cloud.size() - begin), i, message->mutable_chunk());
      outbox_.Push(std::move(message));
    }
    SendStatistics(target, stats, measure, cloud.size(), chunks);
    return Status::Ok();
  }

  void SendStatistics(const scenes::ScanTarget& target, const raycast::ScanStats& stats,
                      const capture::MeasureStats& measure, uint64_t streamed_points, uint32_t chunks) {
    auto message = Message();
    v1::ScanStatistics* s = message->mutable_statistics();
    FillScanStatistics(stats, measure, s);
    s->set_streamed_points(streamed_points);
    s->set_chunk_count(chunks);
    s->set_total_ms(MillisSince(start_));
    spdlog::info("scan of {} r{}: {} rays, {} points in {:.1f} ms", plan_.scene_id, target.scene.revision,
                 stats.rays, stats.points, stats.elapsed_ms);
    outbox_.Push(std::move(message));
  }

  void Fail(const Status& status) {
    spdlog::info("Scan -> {}", status.ToString());
    outbox_.Close(ToGrpc(status));
  }

  ServiceContext& context_;
  WriteWatch write_watch_;
  const Clock::time_point start_ = Clock::now();
  ScanPlan plan_;
  size_t points_per_chunk_ = 1;
  bool holds_slot_ = false;
  std::atomic<bool> cancel_{false};
  // When the call was cancelled (steady clock ticks; 0: not cancelled).
  std::atomic<int64_t> cancelled_at_{0};
  ScanOutbox outbox_;
};

}  // namespace

grpc::ServerWriteReactor<v1::ScanResponse>* ScanService::Scan(grpc::CallbackServerContext* ctx,
                                                              const v1::ScanRequest* request) {
  return new ScanReactor(*request, ctx, context_);
}

}  // namespace vscan::api
