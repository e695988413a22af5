#include "api/localization/localize_progress_reactor.h"

#include <exception>
#include <string>
#include <utility>

#include <spdlog/spdlog.h>

#include "api/server/auth.h"
#include "api/server/call_observer.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {
namespace {

constexpr const char* kMethod = "LocalizeWithProgress";

}  // namespace

LocalizeProgressReactor* LocalizeProgressReactor::Start(grpc::CallbackServerContext* ctx, const std::string& token,
                                                        jobs::WorkerPool& workers,
                                                        guards::StallWatchdog* stalled_readers, Search search) {
  CallScope scope(ctx);  // the pool carries it onto the worker
  auto* reactor = new LocalizeProgressReactor(ctx, stalled_readers);
  Status status = CheckToken(*ctx, token);
  if (status.ok()) {
    const bool posted = workers.Post([reactor, search = std::move(search)] { reactor->RunSearch(search); });
    if (!posted) status = Unavailable("server is shutting down");
  }
  if (!status.ok()) reactor->SearchEnded(status);  // no search runs: ends the call with status
  return reactor;
}

void LocalizeProgressReactor::RunSearch(const Search& search) {
  Status status = Status::Ok();
  v1::LocalizeResponse response;
  try {
    status = search(cancel_, [this](const localization::LocalizeProgress& p) { OnProgress(p); }, &response);
  } catch (const std::exception& e) {
    status = Internal(std::string("unexpected error: ") + e.what());
  }
  {
    std::lock_guard lock(mutex_);
    response_ = std::move(response);
  }
  SearchEnded(status);
}

void LocalizeProgressReactor::OnProgress(const localization::LocalizeProgress& progress) {
  {
    std::lock_guard lock(mutex_);
    if (client_gone_) return;
    v1::LocalizeProgress& latest = progress_.emplace();
    latest.set_fraction(progress.fraction);
    latest.set_found(progress.found);
    latest.set_stage(progress.stage);
  }
  Pump();
}

void LocalizeProgressReactor::SearchEnded(Status status) {
  {
    std::lock_guard lock(mutex_);
    // A progress update not yet sent still goes before the answer (the search's last, at 100%).
    if (!status.ok()) progress_.reset();
    search_status_ = std::move(status);
  }
  Pump();
  Unref();  // nothing of this reactor is touched by the search after this
}

void LocalizeProgressReactor::Pump() {
  enum class Action { kNone, kWrite, kFinish } action = Action::kNone;
  grpc::Status finish = grpc::Status::OK;
  std::string failure;  // for the log, as the unary calls write it
  {
    std::lock_guard lock(mutex_);
    if (writing_ || finished_) return;
    if (search_status_) {
      if (!search_status_->ok()) {
        finish = ToGrpc(*search_status_);
        failure = search_status_->ToString();
        action = Action::kFinish;
      } else if (client_gone_) {
        finish = grpc::Status(grpc::StatusCode::CANCELLED, "the client went away before the response");
        failure = "CANCELLED: " + finish.error_message();
        action = Action::kFinish;
      } else if (progress_) {
        *message_.mutable_progress() = std::move(*progress_);
        progress_.reset();
        action = Action::kWrite;
      } else if (!response_sent_) {
        message_.mutable_response()->Swap(&response_);
        response_sent_ = true;
        action = Action::kWrite;
      } else {
        action = Action::kFinish;
      }
    } else if (progress_ && !client_gone_) {
      *message_.mutable_progress() = std::move(*progress_);
      progress_.reset();
      action = Action::kWrite;
    }
    if (action == Action::kWrite) writing_ = true;
    if (action == Action::kFinish) finished_ = true;
  }
  if (action == Action::kWrite) {
    write_watch_.Started(kMethod);
    StartWrite(&message_);
  } else if (action == Action::kFinish) {
    if (!finish.ok()) spdlog::info("{} -> {}", kMethod, failure);
    Finish(finish);
  }
}

void LocalizeProgressReactor::OnWriteDone(bool ok) {
  write_watch_.Done();
  {
    std::lock_guard lock(mutex_);
    writing_ = false;
    if (!ok) {
      client_gone_ = true;
      progress_.reset();
    }
  }
  if (!ok) cancel_.store(true);
  Pump();
}

void LocalizeProgressReactor::OnCancel() {
  cancel_.store(true);
  {
    std::lock_guard lock(mutex_);
    client_gone_ = true;
    progress_.reset();
  }
  Pump();
}

void LocalizeProgressReactor::OnDone() {
  write_watch_.Release();
  Unref();
}

void LocalizeProgressReactor::Unref() {
  if (references_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
}

}  // namespace vscan::api
