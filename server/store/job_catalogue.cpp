#include "store/job_catalogue.h"

#include <algorithm>
#include <utility>

#include "store/ids.h"
#include "store/list_page.h"
#include "store/sqlite_statement.h"

namespace vscan::store {
namespace {

using sqlite::Statement;

// Appends column 0 of every row the statement yields.
Status AppendFirstColumn(Statement& statement, std::vector<std::string>& out) {
  for (;;) {
    ASSIGN_OR_RETURN(bool row, statement.Step());
    if (!row) return Status::Ok();
    out.push_back(statement.Text(0));
  }
}

constexpr std::string_view kJobColumns =
    "job_id, kind, state, name, spec, message, steps_done, steps_total, last_sequence, create_time_ms, update_time_ms";
constexpr std::string_view kArtifactColumns =
    "artifact_id, job_id, ordinal, name, media_type, sha256, size_bytes, info, create_time_ms";

std::string Select(std::string_view columns, std::string_view table, std::string_view where) {
  std::string sql = "SELECT ";
  sql.append(columns).append(" FROM ").append(table).append(" ").append(where);
  return sql;
}

StatusOr<JobState> StateFromCode(int64_t code, const std::string& job_id) {
  return FromStoredCode(kJobStateCodes, code, "jobs.state of '" + job_id + "'");
}

int64_t Code(JobState state) { return StoredCode(kJobStateCodes, state); }

StatusOr<JobRecord> ReadJob(const Statement& s) {
  JobRecord j;
  j.job_id = s.Text(0);
  j.kind = s.Text(1);
  ASSIGN_OR_RETURN(j.state, StateFromCode(s.Int(2), j.job_id));
  j.name = s.Text(3);
  j.spec = std::string(s.Blob(4));
  j.message = s.Text(5);
  j.steps_done = static_cast<uint32_t>(s.Int(6));
  j.steps_total = static_cast<uint32_t>(s.Int(7));
  j.last_sequence = static_cast<uint64_t>(s.Int(8));
  j.create_time_ms = s.Int(9);
  j.update_time_ms = s.Int(10);
  return j;
}

ArtifactRecord ReadArtifact(const Statement& s) {
  ArtifactRecord a;
  a.artifact_id = s.Text(0);
  a.job_id = s.Text(1);
  a.ordinal = static_cast<uint32_t>(s.Int(2));
  a.name = s.Text(3);
  a.media_type = s.Text(4);
  a.sha256 = s.Text(5);
  a.size_bytes = static_cast<uint64_t>(s.Int(6));
  a.info = std::string(s.Blob(7));
  a.create_time_ms = s.Int(8);
  return a;
}

Status JobNotFound(const std::string& job_id) { return NotFound("job_id: no job '" + job_id + "'"); }

// The job's id, kind and state; NOT_FOUND for an unknown job.
StatusOr<JobRecord> FindKindAndState(sqlite3* db, const std::string& job_id) {
  ASSIGN_OR_RETURN(Statement find, Statement::Prepare(db, "SELECT kind, state FROM jobs WHERE job_id = ?1"));
  find.Bind(1, job_id);
  ASSIGN_OR_RETURN(bool found, find.Step());
  if (!found) return JobNotFound(job_id);
  JobRecord job;
  job.job_id = job_id;
  job.kind = find.Text(0);
  ASSIGN_OR_RETURN(job.state, StateFromCode(find.Int(1), job_id));
  return job;
}

Status ReadArtifacts(sqlite3* db, JobRecord& job) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, Select(kArtifactColumns, "job_artifacts",
                                                              "WHERE job_id = ?1 ORDER BY ordinal")));
  s.Bind(1, job.job_id);
  for (;;) {
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return Status::Ok();
    job.artifacts.push_back(ReadArtifact(s));
  }
}

// The job's row and its artifacts, inside the caller's transaction.
StatusOr<JobRecord> ReadJobWithArtifacts(sqlite3* db, const std::string& job_id) {
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db, Select(kJobColumns, "jobs", "WHERE job_id = ?1")));
  s.Bind(1, job_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return JobNotFound(job_id);
  ASSIGN_OR_RETURN(JobRecord job, ReadJob(s));
  RETURN_IF_ERROR(ReadArtifacts(db, job));
  return job;
}

}  // namespace

bool IsFinal(JobState state) { return state != JobState::kQueued && state != JobState::kRunning; }

const char* JobStateName(JobState state) {
  switch (state) {
    case JobState::kQueued: return "QUEUED";
    case JobState::kRunning: return "RUNNING";
    case JobState::kSucceeded: return "SUCCEEDED";
    case JobState::kFailed: return "FAILED";
    case JobState::kCancelled: return "CANCELLED";
    case JobState::kInterrupted: return "INTERRUPTED";
  }
  return "UNKNOWN";
}

Status CheckResumable(const JobRecord& job, const std::string& kind) {
  const std::string named = "job_id: job '" + job.job_id + "' ";
  if (job.kind != kind) return FailedPrecondition(named + "is a " + job.kind + " job; only " + kind + " jobs resume");
  if (!IsFinal(job.state)) return FailedPrecondition(named + "has not ended (" + JobStateName(job.state) + ")");
  if (job.state == JobState::kSucceeded) return FailedPrecondition(named + "succeeded; nothing is left to resume");
  return Status::Ok();
}

JobCatalogue::JobCatalogue(std::shared_ptr<Database> database)
    : database_(std::move(database)), mutex_(database_->mutex()), db_(database_->handle()) {}

StatusOr<std::unique_ptr<JobCatalogue>> JobCatalogue::Open(const std::filesystem::path& db_path) {
  ASSIGN_OR_RETURN(std::shared_ptr<Database> database, Database::Open(db_path));
  return std::make_unique<JobCatalogue>(std::move(database));
}

StatusOr<int> JobCatalogue::InterruptUnfinished(const std::string& message) {
  std::lock_guard lock(mutex_);
  int changed = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_,
                                                     "UPDATE jobs SET state = ?1, message = ?2, update_time_ms = ?3 "
                                                     "WHERE state IN (?4, ?5)"));
    s.Bind(1, Code(JobState::kInterrupted)).Bind(2, message).Bind(3, NowMs());
    s.Bind(4, Code(JobState::kQueued)).Bind(5, Code(JobState::kRunning));
    RETURN_IF_ERROR(s.Run());
    changed = sqlite3_changes(db_);
    return Status::Ok();
  }));
  return changed;
}

StatusOr<JobRecord> JobCatalogue::InsertJob(JobRecord job) {
  if (job.kind.empty()) return InvalidArgument("kind: required");
  std::lock_guard lock(mutex_);
  job.job_id = NewId("job_");
  job.create_time_ms = NowMs();
  job.update_time_ms = job.create_time_ms;
  job.artifacts.clear();
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    std::string sql = "INSERT INTO jobs (";
    sql.append(kJobColumns).append(") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, sql));
    s.Bind(1, job.job_id).Bind(2, job.kind).Bind(3, Code(job.state)).Bind(4, job.name);
    s.BindBlob(5, job.spec).Bind(6, job.message).Bind(7, int64_t{job.steps_done}).Bind(8, int64_t{job.steps_total});
    s.Bind(9, static_cast<int64_t>(job.last_sequence)).Bind(10, job.create_time_ms).Bind(11, job.update_time_ms);
    return s.Run();
  }));
  return job;
}

StatusOr<JobRecord> JobCatalogue::GetJob(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  JobRecord job;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    ASSIGN_OR_RETURN(job, ReadJobWithArtifacts(db_, job_id));
    return Status::Ok();
  }));
  return job;
}

StatusOr<std::vector<JobRecord>> JobCatalogue::ListJobs(const std::string& after_id, int limit) {
  if (limit <= 0) return InvalidArgument("limit: must be positive, got " + std::to_string(limit));
  std::lock_guard lock(mutex_);
  std::vector<JobRecord> jobs;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Select(kJobColumns, "jobs",
                                                                "WHERE job_id > ?1 ORDER BY job_id LIMIT ?2")));
    s.Bind(1, after_id).Bind(2, int64_t{std::min(limit, kMaxListLimit)});
    for (;;) {
      ASSIGN_OR_RETURN(bool row, s.Step());
      if (!row) break;
      ASSIGN_OR_RETURN(JobRecord job, ReadJob(s));
      jobs.push_back(std::move(job));
    }
    for (JobRecord& job : jobs) RETURN_IF_ERROR(ReadArtifacts(db_, job));
    return Status::Ok();
  }));
  return jobs;
}

StatusOr<std::vector<JobRecord>> JobCatalogue::ListJobsOfKind(const std::string& kind) {
  std::lock_guard lock(mutex_);
  std::vector<JobRecord> jobs;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Select(kJobColumns, "jobs", "WHERE kind = ?1 ORDER BY job_id")));
    s.Bind(1, kind);
    for (;;) {
      ASSIGN_OR_RETURN(bool row, s.Step());
      if (!row) break;
      ASSIGN_OR_RETURN(JobRecord job, ReadJob(s));
      jobs.push_back(std::move(job));
    }
    return Status::Ok();
  }));
  return jobs;
}

Status JobCatalogue::UpdateProgressLocked(const std::string& job_id, const JobProgress& progress, int64_t now_ms) {
  ASSIGN_OR_RETURN(const JobRecord found, FindKindAndState(db_, job_id));
  if (IsFinal(found.state)) return FailedPrecondition("job_id: job '" + job_id + "' has already ended");
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_,
                                                   "UPDATE jobs SET state = ?2, message = ?3, steps_done = ?4, "
                                                   "last_sequence = ?5, update_time_ms = ?6 WHERE job_id = ?1"));
  s.Bind(1, job_id).Bind(2, Code(progress.state)).Bind(3, progress.message);
  s.Bind(4, int64_t{progress.steps_done}).Bind(5, static_cast<int64_t>(progress.sequence)).Bind(6, now_ms);
  return s.Run();
}

Status JobCatalogue::UpdateProgress(const std::string& job_id, const JobProgress& progress) {
  std::lock_guard lock(mutex_);
  const int64_t time_ms = progress.time_ms ? progress.time_ms : NowMs();
  return sqlite::InTransaction(db_, true, [&]() { return UpdateProgressLocked(job_id, progress, time_ms); });
}

StatusOr<ArtifactRecord> JobCatalogue::AddArtifact(ArtifactRecord artifact, const JobProgress& progress,
                                                   CloudRecord* scan_cloud) {
  if (artifact.sha256.size() != 64) return InvalidArgument("sha256: not a SHA-256 hex digest");
  std::lock_guard lock(mutex_);
  artifact.artifact_id = NewId("art_");
  artifact.create_time_ms = NowMs();
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    RETURN_IF_ERROR(UpdateProgressLocked(artifact.job_id, progress, artifact.create_time_ms));
    ASSIGN_OR_RETURN(Statement next, Statement::Prepare(db_,
                                                        "SELECT coalesce(max(ordinal) + 1, 0) FROM job_artifacts "
                                                        "WHERE job_id = ?1"));
    next.Bind(1, artifact.job_id);
    ASSIGN_OR_RETURN(bool row, next.Step());
    artifact.ordinal = row ? static_cast<uint32_t>(next.Int(0)) : 0;
    std::string sql = "INSERT INTO job_artifacts (";
    sql.append(kArtifactColumns).append(") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, sql));
    s.Bind(1, artifact.artifact_id).Bind(2, artifact.job_id).Bind(3, int64_t{artifact.ordinal});
    s.Bind(4, artifact.name).Bind(5, artifact.media_type).Bind(6, artifact.sha256);
    s.Bind(7, static_cast<int64_t>(artifact.size_bytes)).BindBlob(8, artifact.info).Bind(9, artifact.create_time_ms);
    RETURN_IF_ERROR(s.Run());
    if (!scan_cloud) return Status::Ok();
    scan_cloud->origin = CloudOrigin::kCampaignScan;
    scan_cloud->job_id = artifact.job_id;
    scan_cloud->sha256 = artifact.sha256;
    scan_cloud->size_bytes = artifact.size_bytes;
    return InsertCloudRow(db_, *scan_cloud);
  }));
  return artifact;
}

StatusOr<ArtifactRecord> JobCatalogue::GetArtifact(const std::string& job_id, const std::string& artifact_id) {
  std::lock_guard lock(mutex_);
  {
    ASSIGN_OR_RETURN(Statement job, Statement::Prepare(db_, "SELECT 1 FROM jobs WHERE job_id = ?1"));
    job.Bind(1, job_id);
    ASSIGN_OR_RETURN(bool found, job.Step());
    if (!found) return JobNotFound(job_id);
  }
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, Select(kArtifactColumns, "job_artifacts",
                                                              "WHERE job_id = ?1 AND artifact_id = ?2")));
  s.Bind(1, job_id).Bind(2, artifact_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return NotFound("artifact_id: job '" + job_id + "' has no artifact '" + artifact_id + "'");
  return ReadArtifact(s);
}

StatusOr<std::pair<JobRecord, std::vector<std::string>>> JobCatalogue::ReopenJob(const std::string& job_id,
                                                                                const std::string& kind,
                                                                                const std::string& message) {
  std::lock_guard lock(mutex_);
  JobRecord job;
  std::vector<std::string> blobs;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(const JobRecord found_job, FindKindAndState(db_, job_id));
    RETURN_IF_ERROR(CheckResumable(found_job, kind));
    ASSIGN_OR_RETURN(Statement names, Statement::Prepare(db_, "SELECT DISTINCT sha256 FROM job_artifacts "
                                                              "WHERE job_id = ?1 AND coalesce(length(info), 0) = 0"));
    names.Bind(1, job_id);
    RETURN_IF_ERROR(AppendFirstColumn(names, blobs));
    ASSIGN_OR_RETURN(Statement drop, Statement::Prepare(db_, "DELETE FROM job_artifacts "
                                                             "WHERE job_id = ?1 AND coalesce(length(info), 0) = 0"));
    drop.Bind(1, job_id);
    RETURN_IF_ERROR(drop.Run());
    ASSIGN_OR_RETURN(Statement reopen, Statement::Prepare(db_, "UPDATE jobs SET state = ?2, message = ?3, "
                                                               "update_time_ms = ?4 WHERE job_id = ?1"));
    reopen.Bind(1, job_id).Bind(2, Code(JobState::kQueued)).Bind(3, message).Bind(4, NowMs());
    RETURN_IF_ERROR(reopen.Run());
    ASSIGN_OR_RETURN(job, ReadJobWithArtifacts(db_, job_id));
    return Status::Ok();
  }));
  return std::make_pair(std::move(job), std::move(blobs));
}

StatusOr<std::vector<std::string>> JobCatalogue::DeleteJob(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  std::vector<std::string> blobs;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(const JobRecord found, FindKindAndState(db_, job_id));
    const JobState state = found.state;
    if (!IsFinal(state)) {
      return FailedPrecondition("job_id: job '" + job_id + "' is still " +
                                (state == JobState::kQueued ? "queued" : "running") + "; cancel it first");
    }
    ASSIGN_OR_RETURN(Statement names, Statement::Prepare(db_, "SELECT DISTINCT sha256 FROM job_artifacts "
                                                              "WHERE job_id = ?1"));
    names.Bind(1, job_id);
    RETURN_IF_ERROR(AppendFirstColumn(names, blobs));
    // Its artifact rows go with it (ON DELETE CASCADE).
    ASSIGN_OR_RETURN(Statement del, Statement::Prepare(db_, "DELETE FROM jobs WHERE job_id = ?1"));
    del.Bind(1, job_id);
    return del.Run();
  }));
  return blobs;
}

StatusOr<std::vector<std::string>> JobCatalogue::ListEndedBefore(int64_t cutoff_ms, int limit) {
  if (limit <= 0) return InvalidArgument("limit: must be positive, got " + std::to_string(limit));
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_,
                                                   "SELECT job_id FROM jobs WHERE state NOT IN (?1, ?2) AND "
                                                   "update_time_ms < ?3 ORDER BY update_time_ms LIMIT ?4"));
  s.Bind(1, Code(JobState::kQueued)).Bind(2, Code(JobState::kRunning)).Bind(3, cutoff_ms);
  s.Bind(4, int64_t{std::min(limit, kMaxListLimit)});
  std::vector<std::string> ids;
  for (;;) {
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return ids;
    ids.push_back(s.Text(0));
  }
}

}  // namespace vscan::store
