#pragma once
// The state of every job: durable rows in the job catalogue, and for jobs that have not ended an
// in-memory event log that watchers follow. Every change is written to the catalogue before it is
// published, so whatever a client saw survives a crash.

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "observability/metrics.h"
#include "store/blob_gc.h"
#include "store/blob_store.h"
#include "service/job/job_events.h"
#include "service/job/job_kind.h"
#include "store/job_catalogue.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

// Something that follows a live job (a WatchJob call). The tracker calls OnJobEvent after each
// event without holding its locks; the watcher then pulls with LiveJob::Next. Reference counted
// so that a notification in flight keeps it alive; the owner drops the first reference.
class JobWatcher {
 public:
  virtual void OnJobEvent() = 0;
  void Ref() { refs_.fetch_add(1); }
  void Unref() {
    if (refs_.fetch_sub(1) == 1) delete this;
  }

 protected:
  virtual ~JobWatcher() = default;

 private:
  std::atomic<int> refs_{1};
};

// One job that has not ended (or just ended, while watchers drain it). Keeps only the events some
// attached watcher has yet to take, so a long job with no slow watcher holds none.
class LiveJob {
 public:
  // first_sequence: the sequence its next event takes (a reopened job continues its numbering).
  explicit LiveJob(v1::Job job, uint64_t first_sequence = 1);

  // The whole job as it is now.
  v1::Job Snapshot() const;
  // Registers a watcher and returns the job as it is plus the sequence of the next event.
  v1::Job Attach(JobWatcher* watcher, uint64_t* next_sequence);
  void Detach(JobWatcher* watcher);

  enum class Next { kReady, kWait, kEnded };
  // kReady with *out the event of that sequence, which the watcher then no longer needs kept;
  // kEnded when the job ended and no event remains.
  Next Get(JobWatcher* watcher, uint64_t sequence, v1::WatchJobResponse* out);
  uint64_t next_sequence() const;
  bool ended() const;
  // The job's kind and its state as a metric label ("queued", "running", "succeeded", ...).
  std::pair<std::string, std::string> KindAndState() const;
  // Events held for watchers that have not taken them yet.
  size_t retained_events() const;
  // Artifacts stored so far, and their bytes.
  std::pair<uint64_t, uint64_t> ArtifactCountAndBytes() const;

 private:
  friend class JobTracker;
  // Applies an event to the job, appends it, and tells the watchers.
  void Publish(v1::WatchJobResponse response, std::optional<v1::Artifact> artifact, bool ended);
  // Drops the events every attached watcher has taken. Needs mutex_.
  void TrimLocked();

  mutable std::mutex mutex_;
  v1::Job job_;
  uint64_t artifact_bytes_ = 0;  // the sum of job_'s artifacts' sizes
  std::deque<v1::WatchJobResponse> events_;  // events_[i] has sequence first_sequence_ + i
  uint64_t first_sequence_ = 1;
  bool ended_ = false;
  // Each attached watcher and the sequence of the next event it will ask for.
  std::map<JobWatcher*, uint64_t> watchers_;
};

using service::JobEventUpdate;

class JobTracker {
 public:
  // A job's artifacts beyond max_artifacts, or past max_artifact_bytes in all, are RESOURCE_EXHAUSTED.
  JobTracker(store::JobCatalogue& catalogue, store::BlobStore& blobs, uint32_t max_artifacts = UINT32_MAX,
             uint64_t max_artifact_bytes = UINT64_MAX)
      : catalogue_(catalogue), blobs_(blobs), max_artifacts_(max_artifacts), max_artifact_bytes_(max_artifact_bytes) {}

  store::JobCatalogue& catalogue() { return catalogue_; }
  // Called with each job Delete removed from the catalogue (its record as it was, artifacts
  // included): what else the job held on disk goes, and the bytes that freed are returned.
  using DeletedJobHook = std::function<uint64_t(const store::JobRecord& deleted)>;
  void OnDeleted(DeletedJobHook hook) { on_deleted_ = std::move(hook); }
  store::BlobStore& blobs() { return blobs_; }

  // Records a QUEUED job of kind, its spec stored as given, and keeps it live.
  StatusOr<v1::Job> Create(service::JobKind kind, const std::string& name, const google::protobuf::MessageLite& spec,
                           uint32_t steps_total);
  // Puts an ended job of kind back to QUEUED and keeps it live again, its next event numbered after
  // its last (JobCatalogue::ReopenJob says what it keeps and refuses). The reports it drops free
  // the blobs nothing else names.
  StatusOr<store::JobRecord> Reopen(const std::string& job_id, const std::string& kind);
  // The job as it is: from memory while live, else from the catalogue.
  StatusOr<v1::Job> Get(const std::string& job_id);
  // Null once the job has ended (ended but not null while its end could not be stored).
  std::shared_ptr<LiveJob> Live(const std::string& job_id);

  // Persists the event, then publishes it.
  Status Record(const std::string& job_id, const JobEventUpdate& update);
  // Stores bytes as a blob (durable), records the artifact with the event, then publishes it.
  // With cloud, the bytes are also a stored cloud: a campaign scan of the job, recorded with the
  // artifact in one transaction.
  StatusOr<v1::Artifact> RecordArtifact(const std::string& job_id, const std::string& name,
                                        const std::string& media_type, const std::string& bytes,
                                        const v1::ScanArtifactInfo* info, const JobEventUpdate& update,
                                        const store::CloudRecord* cloud = nullptr);
  // The final event: update.state must be final. The job stops being live.
  Status End(const std::string& job_id, const JobEventUpdate& update);

  // Live jobs that have not ended, counted by kind and state (the vscan_jobs gauge).
  std::vector<observability::GaugeSample> CountLive();

  // Deletes an ended job, its artifacts and the blobs nothing else names, then calls the hook of
  // OnDeleted. NOT_FOUND for an unknown job, FAILED_PRECONDITION while
  // it is queued or running.
  StatusOr<store::CollectedBlobs> Delete(const std::string& job_id);
  // Deletes the ended jobs last changed before cutoff_ms (retention); returns how many.
  StatusOr<int> DeleteEndedBefore(int64_t cutoff_ms);

 private:
  StatusOr<std::shared_ptr<LiveJob>> RequireLive(const std::string& job_id);
  v1::WatchJobResponse MakeEvent(const std::shared_ptr<LiveJob>& live, const JobEventUpdate& update,
                                 uint64_t sequence, int64_t now_ms) const;

  store::JobCatalogue& catalogue_;
  store::BlobStore& blobs_;
  const uint32_t max_artifacts_;
  const uint64_t max_artifact_bytes_;
  DeletedJobHook on_deleted_;
  std::mutex mutex_;
  // Each job has one writer at a time (its runner thread, or whoever drops it from the queue).
  std::map<std::string, std::shared_ptr<LiveJob>> live_;
};

}  // namespace vscan::api
