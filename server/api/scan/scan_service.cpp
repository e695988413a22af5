#include "api/scan/scan_service.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "api/server/auth.h"
#include "api/server/call_observer.h"
#include "api/scan/scan_outbox.h"
#include "api/scan/scan_request.h"
#include "api/scan/scan_writer.h"
#include "api/transport/write_watch.h"
#include "service/scan/scan_run.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/point_chunks.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {
namespace {

using Clock = std::chrono::steady_clock;

double MillisSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Packed chunks that may wait for the client, about 8 MiB of them.
size_t ChunkWindow(size_t chunk_bytes) { return std::max<size_t>(2, (8u << 20) / std::max<size_t>(1, chunk_bytes)); }

// One reactor per Scan call. A worker thread runs the scan through the service layer, whose
// points the writer packs into a bounded outbox that gRPC drains.
class ScanReactor final : public grpc::ServerWriteReactor<v1::ScanResponse> {
 public:
  ScanReactor(const v1::ScanRequest& request, grpc::CallbackServerContext* ctx, service::ServiceContext& context,
              guards::StallWatchdog* stalled_readers)
      : context_(context),
        request_id_(RequestIdOf(ctx)),
        write_watch_(stalled_readers, ctx),
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
    auto slot = context_.scans.Admit();
    if (!slot.ok()) {
      Fail(slot.status());
      return;
    }
    slot_ = std::move(slot).value();
    if (!context_.workers.Post([this] { Run(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnCancel() override {
    observability::RequestIdScope scope(request_id_);
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
    ScanWriter writer(plan_, points_per_chunk_, outbox_, cancel_);
    service::ScanOutcome outcome;
    const Status status = service::RunScan(context_, plan_, &cancel_, writer, &outcome);
    if (status.code() == StatusCode::kCancelled && outcome.streamed) {
      const auto since = Clock::now() - Clock::time_point(Clock::duration(cancelled_at_.load()));
      spdlog::info("scan of {}: cancelled after {} of {} rows; the cast stopped {:.1f} ms after the cancel",
                   plan_.scene_id, outcome.stats.rows, plan_.camera.height,
                   std::chrono::duration<double, std::milli>(since).count());
    }
    if (!status.ok()) {
      Fail(status);
      return;
    }
    if (outcome.images) {
      const Status sent = writer.Images(*outcome.images);
      if (!sent.ok()) {
        Fail(sent);
        return;
      }
    }
    writer.Finish(outcome, MillisSince(start_));
    spdlog::info("scan of {}: {} rays, {} points in {:.1f} ms", plan_.scene_id, outcome.stats.rays,
                 outcome.stats.points, outcome.stats.elapsed_ms);
    outbox_.Close(grpc::Status::OK);
  }

  void Fail(const Status& status) {
    spdlog::info("Scan -> {}", status.ToString());
    outbox_.Close(ToGrpc(status));
  }

  service::ServiceContext& context_;
  const std::string request_id_;
  WriteWatch write_watch_;
  const Clock::time_point start_ = Clock::now();
  ScanPlan plan_;
  service::ScanSlot slot_;
  size_t points_per_chunk_ = 1;
  std::atomic<bool> cancel_{false};
  // When the call was cancelled (steady clock ticks; 0: not cancelled).
  std::atomic<int64_t> cancelled_at_{0};
  ScanOutbox outbox_;
};

}  // namespace

grpc::ServerWriteReactor<v1::ScanResponse>* ScanService::Scan(grpc::CallbackServerContext* ctx,
                                                              const v1::ScanRequest* request) {
  CallScope scope(ctx);  // the worker pool carries it into the scan
  return new ScanReactor(*request, ctx, context_, stalled_readers_);
}

}  // namespace vscan::api
