#pragma once
// The durable record of long-running jobs and the files they produced. Lives in the catalogue's
// SQLite file (shared through Database). Every mutation is one transaction. A job's request and an
// artifact's description are stored as opaque bytes (the serialized wire messages), so this layer
// needs no protobuf. Thread-safe: shares the Database's one connection and its lock.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "store/cloud_catalogue.h"
#include "store/database.h"
#include "store/stored_enums.h"
#include "vscan/common/status.h"

struct sqlite3;

namespace vscan::store {

bool IsFinal(JobState state);
// "QUEUED", "RUNNING", ... as reports and logs print a job's state.
const char* JobStateName(JobState state);

struct ArtifactRecord {
  std::string artifact_id;
  std::string job_id;
  uint32_t ordinal = 0;  // order of creation within the job, from 0
  std::string name;
  std::string media_type;
  std::string sha256;  // blob holding the bytes
  uint64_t size_bytes = 0;
  std::string info;  // serialized description (v1::ScanArtifactInfo for campaign scans), may be empty
  int64_t create_time_ms = 0;
};

struct JobRecord;
// Whether a run may continue job as ReopenJob would: FAILED_PRECONDITION naming job_id for a job of
// another kind than kind, one that has not ended, or one that succeeded.
Status CheckResumable(const JobRecord& job, const std::string& kind);

struct JobRecord {
  std::string job_id;
  std::string kind;
  JobState state = JobState::kQueued;
  std::string name;
  std::string spec;  // the serialized request it was started with
  std::string message;
  uint32_t steps_done = 0;
  uint32_t steps_total = 0;
  uint64_t last_sequence = 0;  // sequence of the latest event
  int64_t create_time_ms = 0;
  int64_t update_time_ms = 0;
  std::vector<ArtifactRecord> artifacts;  // by ordinal
};

// What an event changes in a job's row.
struct JobProgress {
  JobState state = JobState::kRunning;
  std::string message;
  uint32_t steps_done = 0;
  uint64_t sequence = 0;
  int64_t time_ms = 0;  // when it happened; 0 means now
};

class JobCatalogue {
 public:
  explicit JobCatalogue(std::shared_ptr<Database> database);
  // Opens or creates the database file with its own Database (tests and tools).
  static StatusOr<std::unique_ptr<JobCatalogue>> Open(const std::filesystem::path& db_path);
  Database& database() { return *database_; }

  // Jobs still QUEUED or RUNNING (left by a server that stopped) become INTERRUPTED with message.
  // Returns how many changed.
  StatusOr<int> InterruptUnfinished(const std::string& message);

  // ids are generated ("job_" + 16 hex digits); the record comes back with id and times set.
  StatusOr<JobRecord> InsertJob(JobRecord job);
  // With its artifacts.
  StatusOr<JobRecord> GetJob(const std::string& job_id);
  // Ordered by id; ids greater than after_id; at most limit (1..1000).
  StatusOr<std::vector<JobRecord>> ListJobs(const std::string& after_id, int limit);
  // Every job of kind, ordered by id, without artifacts.
  StatusOr<std::vector<JobRecord>> ListJobsOfKind(const std::string& kind);
  // NOT_FOUND for an unknown job; FAILED_PRECONDITION when the job already ended.
  Status UpdateProgress(const std::string& job_id, const JobProgress& progress);
  // Records an artifact (id generated, "art_" + 16 hex) and the job's progress in one transaction.
  // The blob it names must already be durable. With scan_cloud the artifact is also a cloud: its
  // row (a campaign scan of the job naming the artifact's blob) goes in the same transaction.
  StatusOr<ArtifactRecord> AddArtifact(ArtifactRecord artifact, const JobProgress& progress,
                                       CloudRecord* scan_cloud = nullptr);
  StatusOr<ArtifactRecord> GetArtifact(const std::string& job_id, const std::string& artifact_id);
  // Puts an ended job of kind back to QUEUED with message, for a run that continues it: keeps
  // the artifacts that describe a scan (their info is set) and deletes the others (its reports,
  // written anew); returns the job as reopened and the blobs the deleted rows named (for
  // CollectBlobs). NOT_FOUND for an unknown job; FAILED_PRECONDITION for another kind, a job that
  // has not ended, or one that succeeded (CheckResumable).
  StatusOr<std::pair<JobRecord, std::vector<std::string>>> ReopenJob(const std::string& job_id,
                                                                     const std::string& kind,
                                                                     const std::string& message);
  // Deletes an ended job and its artifact rows; returns the blobs they named (for CollectBlobs).
  // NOT_FOUND for an unknown job, FAILED_PRECONDITION while it is queued or running.
  StatusOr<std::vector<std::string>> DeleteJob(const std::string& job_id);
  // Ids of ended jobs last changed before cutoff_ms, oldest first, at most limit.
  StatusOr<std::vector<std::string>> ListEndedBefore(int64_t cutoff_ms, int limit);

 private:
  Status UpdateProgressLocked(const std::string& job_id, const JobProgress& progress, int64_t now_ms);
  std::shared_ptr<Database> database_;
  std::mutex& mutex_;
  sqlite3* db_;
};

}  // namespace vscan::store
