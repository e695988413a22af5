#pragma once
// /api/jobs: recent jobs, one job as JSON, its events as server-sent events while it runs, and its
// artifacts' bytes (api::JobTracker, the store the gRPC JobService reads).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <set>

#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

// The event streams the view has open: at most max_streams at once (more are answered 503), each
// writing a comment line after keep_alive without an event, and all of them ended by Stop.
class JobStreams {
 public:
  explicit JobStreams(int max_streams = 8, std::chrono::milliseconds keep_alive = std::chrono::seconds(10))
      : max_streams_(max_streams), keep_alive_(keep_alive) {}

  // Ends every open stream (each returns within its next wait) and refuses new ones.
  void Stop();
  bool stopped() const { return stopped_.load(); }
  int open() const;
  std::chrono::milliseconds keep_alive() const { return keep_alive_; }

  class Waker {
   public:
    virtual void Wake() = 0;

   protected:
    ~Waker() = default;
  };
  // False when stopped or full; otherwise the caller must Leave.
  bool Enter();
  void Leave();
  void Watch(Waker* waker);
  void Unwatch(Waker* waker);

 private:
  const int max_streams_;
  const std::chrono::milliseconds keep_alive_;
  mutable std::mutex mutex_;
  // Read without the lock: a stream's wait checks it under its own lock, which Stop takes under this one.
  std::atomic<bool> stopped_{false};
  int open_ = 0;
  std::set<Waker*> wakers_;
};

// Artifacts bigger than this are refused (422) rather than sent to a browser.
inline constexpr uint64_t kMaxArtifactBytes = 256ull << 20;
// Jobs listed by /api/jobs at most (?limit=, default 50).
inline constexpr long long kMaxListedJobs = 500;

// segments[0] is "jobs".
WebReply ServeJobs(const WebSources& sources, const std::shared_ptr<JobStreams>& streams, const WebRequest& request);

}  // namespace vscan::web
