#include "api/scan_service.h"

#include <atomic>
#include <chrono>
#include <string>

#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "api/scan_backends.h"
#include "api/scan_request.h"
#include "api/scan_target.h"
#include "api/write_watch.h"
#include "vscan/common/grpc_status.h"
#include "vscan/common/point_chunks.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

using Clock = std::chrono::steady_clock;

v1::ScanBackend BackendToProto(ScanBackend backend) {
  switch (backend) {
    case ScanBackend::kRasterDepth: return v1::SCAN_BACKEND_RASTER_DEPTH;
    case ScanBackend::kRasterColour: return v1::SCAN_BACKEND_RASTER_COLOUR;
    case ScanBackend::kRaycast: break;
  }
  return v1::SCAN_BACKEND_RAYCAST;
}

void SetMeasureStatistics(const capture::MeasureStats& m, v1::ScanStatistics& s) {
  s.set_outliers(m.outliers);
  s.set_flying_pixels(m.flying_pixels);
  s.set_rejected_out_of_range(m.rejected_out_of_range);
  s.set_rejected_shadowed(m.rejected_shadowed);
  s.set_rejected_grazing(m.rejected_grazing);
  s.set_rejected_dim(m.rejected_dim);
  s.set_rejected_unlit(m.rejected_unlit);
  s.set_measurement_ms(m.elapsed_ms);
}

double MillisSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// One reactor per Scan call. The worker fills the cloud, then writes proceed one at a time.
class ScanReactor final : public grpc::ServerWriteReactor<v1::ScanResponse> {
 public:
  ScanReactor(const v1::ScanRequest& request, grpc::CallbackServerContext* ctx, ServiceContext& context)
      : context_(context), write_watch_(context.stalled_readers, ctx) {
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
    cancel_.store(true);
    spdlog::info("scan of {}: call cancelled", plan_.scene_id);
  }

  void OnWriteDone(bool ok) override {
    write_watch_.Done();
    if (!ok) {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "client went away"));
      return;
    }
    WriteNext();
  }

  void OnDone() override {
    write_watch_.Release();
    if (holds_slot_) context_.active_scans.fetch_sub(1);
    delete this;
  }

 private:
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
    raycast::ScanStats stats;
    capture::MeasureStats measure;
    auto cloud = RunScanBackend(plan_, *target, context_.raster, &cancel_, &stats, &measure);
    if (!cloud.ok()) {
      Fail(cloud.status());
      return;
    }
    cloud_ = std::move(cloud).value();
    points_per_chunk_ = PointsPerChunk(plan_.fields, plan_.chunk_bytes);
    chunk_count_ = static_cast<uint32_t>((cloud_.size() + points_per_chunk_ - 1) / points_per_chunk_);

    auto* header = response_.mutable_header();
    header->set_scene_id(plan_.scene_id);
    header->set_scene_revision(target->scene.revision);
    ToProto(plan_.world_from_sensor, header->mutable_sensor_pose());
    if (plan_.robot) {
      ToProto(plan_.robot->commanded_world_from_sensor, header->mutable_commanded_sensor_pose());
      const Eigen::VectorXd& q = plan_.robot->achieved_joint_positions;
      header->mutable_achieved_joint_positions()->Assign(q.data(), q.data() + q.size());
    }
    header->set_width(plan_.camera.width);
    header->set_height(plan_.camera.height);
    auto* k = header->mutable_intrinsics();
    k->set_fx(plan_.camera.fx);
    k->set_fy(plan_.camera.fy);
    k->set_cx(plan_.camera.cx);
    k->set_cy(plan_.camera.cy);
    header->set_near(plan_.camera.near);
    header->set_far(plan_.camera.far);
    FieldsToProto(plan_.fields, header->mutable_fields());
    header->set_frame(plan_.frame == raycast::ScanFrame::kSensor ? v1::FRAME_SENSOR : v1::FRAME_WORLD);
    header->set_backend(BackendToProto(plan_.backend));
    header->set_rays(stats.rays);
    header->set_points(cloud_.size());
    header->set_chunk_count(chunk_count_);

    auto& s = statistics_;
    s.set_rays(stats.rays);
    s.set_points(stats.points);
    s.set_hit_ratio(stats.rays ? static_cast<double>(stats.points) / static_cast<double>(stats.rays) : 0.0);
    s.set_min_range(stats.min_range);
    s.set_max_range(stats.max_range);
    s.set_scan_ms(stats.elapsed_ms);
    SetMeasureStatistics(measure, s);
    spdlog::info("scan of {} r{}: {} rays, {} points in {:.1f} ms", plan_.scene_id, target->scene.revision,
                 stats.rays, stats.points, stats.elapsed_ms);
    Write();
  }

  void Write() {
    write_watch_.Started("scan of " + plan_.scene_id);
    StartWrite(&response_);
  }

  void WriteNext() {
    if (cancel_.load()) {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "scan cancelled"));
      return;
    }
    response_.Clear();
    if (next_chunk_ < chunk_count_) {
      const size_t begin = size_t{next_chunk_} * points_per_chunk_;
      const size_t count = std::min(points_per_chunk_, cloud_.size() - begin);
      PackChunk(cloud_, begin, count, next_chunk_, response_.mutable_chunk());
      ++next_chunk_;
      Write();
      return;
    }
    if (!statistics_sent_) {
      statistics_sent_ = true;
      statistics_.set_total_ms(MillisSince(start_));
      *response_.mutable_statistics() = statistics_;
      Write();
      return;
    }
    Finish(grpc::Status::OK);
  }

  void Fail(const Status& status) {
    spdlog::info("Scan -> {}", status.ToString());
    Finish(ToGrpc(status));
  }

  ServiceContext& context_;
  WriteWatch write_watch_;
  const Clock::time_point start_ = Clock::now();
  ScanPlan plan_;
  bool holds_slot_ = false;
  std::atomic<bool> cancel_{false};
  PointCloud cloud_;
  size_t points_per_chunk_ = 1;
  uint32_t chunk_count_ = 0;
  uint32_t next_chunk_ = 0;
  bool statistics_sent_ = false;
  v1::ScanStatistics statistics_;
  v1::ScanResponse response_;
};

}  // namespace

grpc::ServerWriteReactor<v1::ScanResponse>* ScanService::Scan(grpc::CallbackServerContext* ctx,
                                                              const v1::ScanRequest* request) {
  return new ScanReactor(*request, ctx, context_);
}

}  // namespace vscan::api
