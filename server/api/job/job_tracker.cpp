#include "api/job/job_tracker.h"

#include <algorithm>
#include <cctype>
#include <map>

#include <spdlog/spdlog.h>

#include "api/job/job_convert.h"
#include "observability/server_metrics.h"
#include "store/ids.h"

namespace vscan::api {
namespace {

double Progress(uint32_t done, uint32_t total) { return total ? static_cast<double>(done) / total : 0.0; }

// JOB_STATE_RUNNING -> running.
std::string StateLabel(v1::JobState state) {
  std::string name = v1::JobState_Name(state);
  constexpr std::string_view kPrefix = "JOB_STATE_";
  if (name.starts_with(kPrefix)) name.erase(0, kPrefix.size());
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

}  // namespace

LiveJob::LiveJob(v1::Job job, uint64_t first_sequence) : job_(std::move(job)), first_sequence_(first_sequence) {
  for (const v1::Artifact& artifact : job_.artifacts()) artifact_bytes_ += artifact.size_bytes();
}

v1::Job LiveJob::Snapshot() const {
  std::lock_guard lock(mutex_);
  return job_;
}

v1::Job LiveJob::Attach(JobWatcher* watcher, uint64_t* next_sequence) {
  std::lock_guard lock(mutex_);
  *next_sequence = first_sequence_ + events_.size();
  if (!ended_) watchers_[watcher] = *next_sequence;
  return job_;
}

void LiveJob::Detach(JobWatcher* watcher) {
  std::lock_guard lock(mutex_);
  watchers_.erase(watcher);
  TrimLocked();
}

LiveJob::Next LiveJob::Get(JobWatcher* watcher, uint64_t sequence, v1::WatchJobResponse* out) {
  std::lock_guard lock(mutex_);
  if (sequence >= first_sequence_ && sequence < first_sequence_ + events_.size()) {
    *out = events_[sequence - first_sequence_];
    if (auto it = watchers_.find(watcher); it != watchers_.end()) {
      it->second = sequence + 1;
      TrimLocked();
    }
    return Next::kReady;
  }
  return ended_ ? Next::kEnded : Next::kWait;
}

uint64_t LiveJob::next_sequence() const {
  std::lock_guard lock(mutex_);
  return first_sequence_ + events_.size();
}

bool LiveJob::ended() const {
  std::lock_guard lock(mutex_);
  return ended_;
}

std::pair<std::string, std::string> LiveJob::KindAndState() const {
  std::lock_guard lock(mutex_);
  return {job_.kind(), StateLabel(job_.state())};
}

size_t LiveJob::retained_events() const {
  std::lock_guard lock(mutex_);
  return events_.size();
}

std::pair<uint64_t, uint64_t> LiveJob::ArtifactCountAndBytes() const {
  std::lock_guard lock(mutex_);
  return {static_cast<uint64_t>(job_.artifacts_size()), artifact_bytes_};
}

void LiveJob::TrimLocked() {
  uint64_t keep_from = first_sequence_ + events_.size();
  for (const auto& [watcher, next] : watchers_) keep_from = std::min(keep_from, next);
  while (first_sequence_ < keep_from) {
    events_.pop_front();
    ++first_sequence_;
  }
}

void LiveJob::Publish(v1::WatchJobResponse response, std::optional<v1::Artifact> artifact, bool ended) {
  std::vector<JobWatcher*> watchers;
  {
    std::lock_guard lock(mutex_);
    const v1::Job& slim = response.job();
    job_.set_state(slim.state());
    job_.set_progress(slim.progress());
    job_.set_message(slim.message());
    job_.set_steps_done(slim.steps_done());
    *job_.mutable_update_time() = slim.update_time();
    if (artifact) {
      artifact_bytes_ += artifact->size_bytes();
      *job_.add_artifacts() = std::move(*artifact);
    }
    events_.push_back(std::move(response));
    TrimLocked();
    ended_ = ended;
    // Watchers stay registered after the end: they still drain what they have not taken.
    for (const auto& [watcher, next] : watchers_) {
      watcher->Ref();
      watchers.push_back(watcher);
    }
  }
  for (JobWatcher* w : watchers) {
    w->OnJobEvent();
    w->Unref();
  }
}

StatusOr<v1::Job> JobTracker::Create(service::JobKind kind, const std::string& name,
                                     const google::protobuf::MessageLite& spec, uint32_t steps_total) {
  store::JobRecord record;
  record.kind = std::string(service::JobKindName(kind));
  record.state = store::JobState::kQueued;
  record.name = name;
  record.spec = spec.SerializeAsString();
  record.message = "queued";
  record.steps_total = steps_total;
  ASSIGN_OR_RETURN(record, catalogue_.InsertJob(std::move(record)));
  v1::Job job;
  RETURN_IF_ERROR(ToProto(record, &job));
  std::lock_guard lock(mutex_);
  live_[job.job_id()] = std::make_shared<LiveJob>(job);
  return job;
}

StatusOr<store::JobRecord> JobTracker::Reopen(const std::string& job_id, const std::string& kind) {
  ASSIGN_OR_RETURN(auto reopened, catalogue_.ReopenJob(job_id, kind, "queued to resume"));
  auto& [record, dropped] = reopened;
  v1::Job job;
  RETURN_IF_ERROR(ToProto(record, &job));
  {
    std::lock_guard lock(mutex_);
    live_[job_id] = std::make_shared<LiveJob>(job, record.last_sequence + 1);
  }
  // The reopened job no longer names them; a failure leaves files the next collection finds.
  const auto collected = store::CollectBlobs(catalogue_.database(), blobs_, dropped);
  if (!collected.ok()) {
    spdlog::warn("job {}: reports of its earlier run kept: {}", job_id, collected.status().ToString());
  }
  return std::move(record);
}

std::shared_ptr<LiveJob> JobTracker::Live(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  auto it = live_.find(job_id);
  return it == live_.end() ? nullptr : it->second;
}

StatusOr<v1::Job> JobTracker::Get(const std::string& job_id) {
  if (auto live = Live(job_id)) return live->Snapshot();
  ASSIGN_OR_RETURN(const store::JobRecord record, catalogue_.GetJob(job_id));
  v1::Job job;
  RETURN_IF_ERROR(ToProto(record, &job));
  return job;
}

StatusOr<std::shared_ptr<LiveJob>> JobTracker::RequireLive(const std::string& job_id) {
  auto live = Live(job_id);
  if (!live || live->ended()) return FailedPrecondition("job_id: job '" + job_id + "' is not running");
  return live;
}

v1::WatchJobResponse JobTracker::MakeEvent(const std::shared_ptr<LiveJob>& live, const JobEventUpdate& update,
                                           uint64_t sequence, int64_t now_ms) const {
  const v1::Job current = [&] {
    std::lock_guard lock(live->mutex_);
    v1::Job slim;
    slim.set_job_id(live->job_.job_id());
    slim.set_kind(live->job_.kind());
    slim.set_steps_total(live->job_.steps_total());
    *slim.mutable_create_time() = live->job_.create_time();
    return slim;
  }();
  v1::WatchJobResponse response;
  v1::Job* job = response.mutable_job();
  *job = current;
  job->set_state(ToProto(update.state));
  job->set_steps_done(update.steps_done);
  job->set_progress(Progress(update.steps_done, job->steps_total()));
  job->set_message(update.message);
  SetTime(now_ms, job->mutable_update_time());
  v1::JobEvent* event = response.mutable_event();
  event->set_sequence(sequence);
  SetTime(now_ms, event->mutable_time());
  event->set_message(update.message);
  event->set_step(update.step);
  event->set_pose_reached(update.pose_reached);
  if (update.alignment) ToProto(*update.alignment, event->mutable_alignment());
  return response;
}

Status JobTracker::Record(const std::string& job_id, const JobEventUpdate& update) {
  ASSIGN_OR_RETURN(auto live, RequireLive(job_id));
  const uint64_t sequence = live->next_sequence();
  // One time for the stored row and the event, so that GetJob and WatchJob agree.
  const int64_t now_ms = store::NowMs();
  RETURN_IF_ERROR(
      catalogue_.UpdateProgress(job_id, {update.state, update.message, update.steps_done, sequence, now_ms}));
  live->Publish(MakeEvent(live, update, sequence, now_ms), std::nullopt, false);
  return Status::Ok();
}

StatusOr<v1::Artifact> JobTracker::RecordArtifact(const std::string& job_id, const std::string& name,
                                                  const std::string& media_type, const std::string& bytes,
                                                  const v1::ScanArtifactInfo* info, const JobEventUpdate& update,
                                                  const store::CloudRecord* cloud) {
  ASSIGN_OR_RETURN(auto live, RequireLive(job_id));
  const auto [count, stored_bytes] = live->ArtifactCountAndBytes();
  if (count >= max_artifacts_) {
    return ResourceExhausted("job " + job_id + ": " + name + " would be its artifact " + std::to_string(count + 1) +
                             ", past the limit of " + std::to_string(max_artifacts_) + " per job (--max-job-artifacts)");
  }
  if (bytes.size() > max_artifact_bytes_ || stored_bytes > max_artifact_bytes_ - bytes.size()) {
    return ResourceExhausted("job " + job_id + ": " + name + " (" + std::to_string(bytes.size()) +
                             " bytes) would take its artifacts past the limit of " +
                             std::to_string(max_artifact_bytes_ >> 20) + " MiB per job (--max-job-mib)");
  }
  // Pinned until its row is stored, so that deleting another job cannot collect it meanwhile.
  ASSIGN_OR_RETURN(const store::BlobPin pin, blobs_.PutPinned(bytes));
  store::ArtifactRecord record;
  record.job_id = job_id;
  record.name = name;
  record.media_type = media_type;
  record.sha256 = pin.sha256();
  record.size_bytes = bytes.size();
  if (info) record.info = info->SerializeAsString();
  const uint64_t sequence = live->next_sequence();
  std::optional<store::CloudRecord> scan_cloud;
  if (cloud) scan_cloud = *cloud;
  ASSIGN_OR_RETURN(record, catalogue_.AddArtifact(std::move(record),
                                                  {update.state, update.message, update.steps_done, sequence},
                                                  scan_cloud ? &*scan_cloud : nullptr));
  v1::Artifact artifact;
  RETURN_IF_ERROR(ToProto(record, &artifact));
  v1::WatchJobResponse response = MakeEvent(live, update, sequence, record.create_time_ms);
  *response.mutable_event()->mutable_artifact() = artifact;
  live->Publish(std::move(response), artifact, false);
  return artifact;
}

Status JobTracker::End(const std::string& job_id, const JobEventUpdate& update) {
  if (!store::IsFinal(update.state)) return Internal("job " + job_id + ": End needs a final state");
  ASSIGN_OR_RETURN(auto live, RequireLive(job_id));
  const uint64_t sequence = live->next_sequence();
  const int64_t now_ms = store::NowMs();
  const Status stored =
      catalogue_.UpdateProgress(job_id, {update.state, update.message, update.steps_done, sequence, now_ms});
  // Until the end is stored the catalogue still says the job runs: the ended job then stays in
  // memory, so that it does not read as running again (the next start marks it INTERRUPTED).
  // A stored end drops this run's entry before watchers hear of it, so that a client who deletes
  // the job on that news never reads the deleted job back from memory.
  if (stored.ok()) {
    std::lock_guard lock(mutex_);
    if (auto it = live_.find(job_id); it != live_.end() && it->second == live) live_.erase(it);
  }
  // Watchers learn of the end even when it could not be stored; a restart then reports INTERRUPTED.
  live->Publish(MakeEvent(live, update, sequence, now_ms), std::nullopt, true);
  auto [kind, state] = live->KindAndState();
  observability::Metrics().jobs_ended.WithLabels({std::move(kind), std::move(state)}).Increment();
  return stored;
}

std::vector<observability::GaugeSample> JobTracker::CountLive() {
  std::map<std::pair<std::string, std::string>, int> counts;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, live] : live_) {
      if (!live->ended()) ++counts[live->KindAndState()];
    }
  }
  std::vector<observability::GaugeSample> samples;
  for (const auto& [labels, count] : counts) samples.push_back({{labels.first, labels.second}, double(count)});
  return samples;
}

StatusOr<store::CollectedBlobs> JobTracker::Delete(const std::string& job_id) {
  // The catalogue refuses a job it records as unfinished; one whose end could not be stored is
  // live and ended here but still running there, and is refused too.
  store::JobRecord record;
  if (on_deleted_) {
    ASSIGN_OR_RETURN(record, catalogue_.GetJob(job_id));
  }
  ASSIGN_OR_RETURN(const std::vector<std::string> blobs, catalogue_.DeleteJob(job_id));
  ASSIGN_OR_RETURN(store::CollectedBlobs collected, store::CollectBlobs(catalogue_.database(), blobs_, blobs));
  if (on_deleted_) collected.bytes += on_deleted_(record);
  return collected;
}

StatusOr<int> JobTracker::DeleteEndedBefore(int64_t cutoff_ms) {
  constexpr int kBatch = 100;
  int deleted = 0;
  for (;;) {
    ASSIGN_OR_RETURN(const std::vector<std::string> ids, catalogue_.ListEndedBefore(cutoff_ms, kBatch));
    for (const std::string& id : ids) {
      const auto freed = Delete(id);
      // A job deleted by a client meanwhile is not an error.
      if (!freed.ok() && freed.status().code() != StatusCode::kNotFound) return freed.status();
      if (freed.ok()) ++deleted;
    }
    if (static_cast<int>(ids.size()) < kBatch) return deleted;
  }
}

}  // namespace vscan::api
