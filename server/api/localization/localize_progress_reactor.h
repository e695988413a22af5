#pragma once
// LocalizeWithProgress's stream. The search runs on a worker; its progress callback only replaces
// the latest unsent progress and starts a write when none is in flight, so the search never waits
// on the client and a client that stops reading holds one message at most (the stalled-reader
// watchdog then cancels the call). Cancelling the call or its deadline sets the search's cancel
// flag; the stream ends with the response, or with the search's status, once the search returned.

#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

#include <grpcpp/support/server_callback.h>

#include "api/transport/write_watch.h"
#include "guards/stall_watchdog.h"
#include "jobs/worker_pool.h"
#include "localization/baseline_localizer.h"
#include "vscan/common/status.h"
#include "vscan/v1/localization.pb.h"

namespace vscan::api {

class LocalizeProgressReactor final : public grpc::ServerWriteReactor<v1::LocalizeWithProgressResponse> {
 public:
  // Runs on a worker: fills response, or returns the failure the stream ends with.
  using Search = std::function<Status(const std::atomic<bool>& cancel,
                                      const localization::LocalizeProgressCallback& progress,
                                      v1::LocalizeResponse* response)>;

  // Checks the token and posts the search; the reactor deletes itself once the call is done and
  // the search has returned.
  static LocalizeProgressReactor* Start(grpc::CallbackServerContext* ctx, const std::string& token,
                                        jobs::WorkerPool& workers, guards::StallWatchdog* stalled_readers,
                                        Search search);

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  LocalizeProgressReactor(grpc::CallbackServerContext* ctx, guards::StallWatchdog* stalled_readers)
      : write_watch_(stalled_readers, ctx) {}

  void RunSearch(const Search& search);  // on the worker
  void OnProgress(const localization::LocalizeProgress& progress);
  void SearchEnded(Status status);
  // Starts the next write, or finishes the call, when nothing is in flight.
  void Pump();
  void Unref();

  WriteWatch write_watch_;
  std::atomic<bool> cancel_{false};
  // gRPC's reference (until OnDone) and the search's (until it returned).
  std::atomic<int> references_{2};

  std::mutex mutex_;
  std::optional<v1::LocalizeProgress> progress_;  // the latest, not yet written
  std::optional<Status> search_status_;           // set once the search returned
  v1::LocalizeResponse response_;                 // the search's answer, when it succeeded
  bool response_sent_ = false;
  bool writing_ = false;
  bool finished_ = false;
  bool client_gone_ = false;  // cancelled, or a write failed
  v1::LocalizeWithProgressResponse message_;  // the one in flight
};

}  // namespace vscan::api
