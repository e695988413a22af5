// JobService.WatchJob: the job as it is, then one response per event until the job ends.

#include <functional>
#include <mutex>

#include <spdlog/spdlog.h>

#include "api/server/auth.h"
#include "api/server/call_observer.h"
#include "api/job/job_service.h"
#include "api/transport/validate.h"
#include "api/transport/write_watch.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {
namespace {

// Follows a live job as a JobWatcher: the tracker pokes it after each event and it pulls the next
// one whenever no write is in flight. Writes and Finish happen outside its lock.
class WatchReactor final : public grpc::ServerWriteReactor<v1::WatchJobResponse>, public JobWatcher {
 public:
  // annotate adds to each response's job what the event log does not hold.
  WatchReactor(grpc::CallbackServerContext* ctx, const v1::WatchJobRequest& request, const std::string& token,
               JobTracker& tracker, guards::StallWatchdog* stalled_readers, std::function<void(v1::Job*)> annotate)
      : write_watch_(stalled_readers, ctx), annotate_(std::move(annotate)) {
    Status status = CheckToken(*ctx, token);
    if (status.ok()) status = RequireId(request.job_id(), "job_id");
    if (!status.ok()) {
      Fail(status);
      return;
    }
    writing_ = true;
    live_ = tracker.Live(request.job_id());
    if (live_) {
      *response_.mutable_job() = live_->Attach(this, &next_);
      attached_ = true;
    } else {
      auto job = tracker.Get(request.job_id());
      if (!job.ok()) {
        Fail(job.status());
        return;
      }
      *response_.mutable_job() = std::move(job).value();
    }
    annotate_(response_.mutable_job());
    write_watch_.Started("WatchJob");
    StartWrite(&response_);
  }

  void OnJobEvent() override { Pump(); }

  void OnWriteDone(bool ok) override {
    write_watch_.Done();
    {
      std::lock_guard lock(mutex_);
      writing_ = false;
      if (!ok) {
        finished_ = true;
      }
    }
    if (!ok) {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "watcher went away"));
      return;
    }
    Pump();
  }

  void OnCancel() override {
    {
      std::lock_guard lock(mutex_);
      cancelled_ = true;
      // A write in flight may still complete ok; its OnWriteDone then finishes the call.
      if (writing_ || finished_) return;
      finished_ = true;
    }
    Finish(grpc::Status(grpc::StatusCode::CANCELLED, "watch cancelled"));
  }

  void OnDone() override {
    write_watch_.Release();
    if (attached_) live_->Detach(this);
    Unref();
  }

 private:
  void Fail(const Status& status) {
    spdlog::info("WatchJob -> {}", status.ToString());
    finished_ = true;
    Finish(ToGrpc(status));
  }

  void Pump() {
    enum class Action { kNone, kWrite, kEnd, kCancel } action = Action::kNone;
    {
      std::lock_guard lock(mutex_);
      if (writing_ || finished_) return;
      if (cancelled_) {
        action = Action::kCancel;
      } else {
        const LiveJob::Next next = live_ ? live_->Get(this, next_, &response_) : LiveJob::Next::kEnded;
        if (next == LiveJob::Next::kWait) return;
        action = next == LiveJob::Next::kReady ? Action::kWrite : Action::kEnd;
      }
      if (action == Action::kWrite) {
        annotate_(response_.mutable_job());
        ++next_;
        writing_ = true;
      } else {
        finished_ = true;
      }
    }
    if (action == Action::kWrite) {
      write_watch_.Started("WatchJob");
      StartWrite(&response_);
    } else if (action == Action::kEnd) {
      Finish(grpc::Status::OK);
    } else {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "watch cancelled"));
    }
  }

  WriteWatch write_watch_;
  std::function<void(v1::Job*)> annotate_;
  std::mutex mutex_;
  std::shared_ptr<LiveJob> live_;
  bool attached_ = false;
  bool writing_ = false;
  bool finished_ = false;
  bool cancelled_ = false;
  uint64_t next_ = 1;
  v1::WatchJobResponse response_;
};

}  // namespace

grpc::ServerWriteReactor<v1::WatchJobResponse>* JobService::WatchJob(grpc::CallbackServerContext* ctx,
                                                                     const v1::WatchJobRequest* request) {
  CallScope scope(ctx);
  return new WatchReactor(ctx, *request, context_.options.token, tracker_, stalled_readers_,
                          [this](v1::Job* job) { ShowAwaitedEstimates(job); });
}

}  // namespace vscan::api
