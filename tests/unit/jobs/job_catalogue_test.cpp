#include "store/job_catalogue.h"

#include <sqlite3.h>

#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

JobRecord Campaign(const std::string& name, uint32_t steps_total) {
  JobRecord job;
  job.kind = "campaign";
  job.name = name;
  job.spec = std::string("\x0a\x03scn\x00\xff", 7);  // opaque bytes, NULs included
  job.message = "queued";
  job.steps_total = steps_total;
  return job;
}

ArtifactRecord Scan(const std::string& job_id, const std::string& name, char sha) {
  ArtifactRecord a;
  a.job_id = job_id;
  a.name = name;
  a.media_type = "model/ply";
  a.sha256 = std::string(64, sha);
  a.size_bytes = 1234;
  a.info = std::string("\x08\x01\x10\x02", 4);
  return a;
}

class JobCatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override { Reopen(); }
  void Reopen() {
    jobs_.reset();
    auto opened = JobCatalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(opened.ok()) << opened.status().ToString();
    jobs_ = std::move(opened).value();
  }

  test::TempDir dir_;
  std::unique_ptr<JobCatalogue> jobs_;
};

TEST_F(JobCatalogueTest, JobsAndArtifactsRoundTrip) {
  auto job = jobs_->InsertJob(Campaign("turntable", 6));
  ASSERT_TRUE(job.ok()) << job.status().ToString();
  EXPECT_EQ(job->job_id.rfind("job_", 0), 0u);
  EXPECT_EQ(job->state, JobState::kQueued);
  EXPECT_GT(job->create_time_ms, 0);

  ASSERT_TRUE(jobs_->UpdateProgress(job->job_id, {JobState::kRunning, "6 scans planned", 0, 1}).ok());
  auto first = jobs_->AddArtifact(Scan(job->job_id, "scan-r00-v00.ply", 'a'),
                                  {JobState::kRunning, "scan 1 captured", 1, 2});
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  auto second = jobs_->AddArtifact(Scan(job->job_id, "scan-r00-v01.ply", 'b'),
                                   {JobState::kRunning, "scan 2 captured", 2, 3});
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(first->ordinal, 0u);
  EXPECT_EQ(second->ordinal, 1u);
  EXPECT_EQ(first->artifact_id.rfind("art_", 0), 0u);

  Reopen();
  auto got = jobs_->GetJob(job->job_id);
  ASSERT_TRUE(got.ok()) << got.status().ToString();
  EXPECT_EQ(got->kind, "campaign");
  EXPECT_EQ(got->name, "turntable");
  EXPECT_EQ(got->spec, Campaign("", 0).spec);
  EXPECT_EQ(got->state, JobState::kRunning);
  EXPECT_EQ(got->message, "scan 2 captured");
  EXPECT_EQ(got->steps_done, 2u);
  EXPECT_EQ(got->steps_total, 6u);
  EXPECT_EQ(got->last_sequence, 3u);
  ASSERT_EQ(got->artifacts.size(), 2u);
  EXPECT_EQ(got->artifacts[0].name, "scan-r00-v00.ply");
  EXPECT_EQ(got->artifacts[1].sha256, std::string(64, 'b'));
  EXPECT_EQ(got->artifacts[1].info, Scan("", "", 'b').info);
  EXPECT_EQ(got->artifacts[1].size_bytes, 1234u);

  auto artifact = jobs_->GetArtifact(job->job_id, second->artifact_id);
  ASSERT_TRUE(artifact.ok());
  EXPECT_EQ(artifact->name, "scan-r00-v01.ply");
  EXPECT_EQ(jobs_->GetArtifact(job->job_id, "art_0000000000000000").status().code(), StatusCode::kNotFound);
  EXPECT_EQ(jobs_->GetArtifact("job_missing", second->artifact_id).status().code(), StatusCode::kNotFound);
}

TEST_F(JobCatalogueTest, EndedJobsRefuseUpdates) {
  auto job = jobs_->InsertJob(Campaign("", 1));
  ASSERT_TRUE(job.ok());
  ASSERT_TRUE(jobs_->UpdateProgress(job->job_id, {JobState::kSucceeded, "done", 1, 1}).ok());
  const Status late = jobs_->UpdateProgress(job->job_id, {JobState::kRunning, "again", 1, 2});
  EXPECT_EQ(late.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(late.message().rfind("job_id:", 0), 0u) << late.message();
  auto artifact = jobs_->AddArtifact(Scan(job->job_id, "x.ply", 'c'), {JobState::kRunning, "late", 1, 2});
  EXPECT_EQ(artifact.status().code(), StatusCode::kFailedPrecondition);
  auto got = jobs_->GetJob(job->job_id);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->state, JobState::kSucceeded);
  EXPECT_TRUE(got->artifacts.empty());
  EXPECT_EQ(jobs_->UpdateProgress("job_missing", {}).code(), StatusCode::kNotFound);
  EXPECT_EQ(jobs_->GetJob("job_missing").status().code(), StatusCode::kNotFound);
}

TEST_F(JobCatalogueTest, UnfinishedJobsBecomeInterruptedOnOpen) {
  auto queued = jobs_->InsertJob(Campaign("queued", 4));
  auto running = jobs_->InsertJob(Campaign("running", 4));
  auto done = jobs_->InsertJob(Campaign("done", 4));
  ASSERT_TRUE(queued.ok() && running.ok() && done.ok());
  ASSERT_TRUE(jobs_->UpdateProgress(running->job_id, {JobState::kRunning, "planned", 0, 1}).ok());
  ASSERT_TRUE(jobs_->AddArtifact(Scan(running->job_id, "scan-r00-v00.ply", 'd'),
                                 {JobState::kRunning, "scan 1 captured", 1, 2})
                  .ok());
  ASSERT_TRUE(jobs_->UpdateProgress(done->job_id, {JobState::kCancelled, "cancelled", 2, 1}).ok());

  Reopen();
  auto changed = jobs_->InterruptUnfinished("server stopped while the job ran");
  ASSERT_TRUE(changed.ok());
  EXPECT_EQ(*changed, 2);
  for (const auto& id : {queued->job_id, running->job_id}) {
    auto job = jobs_->GetJob(id);
    ASSERT_TRUE(job.ok());
    EXPECT_EQ(job->state, JobState::kInterrupted);
    EXPECT_EQ(job->message, "server stopped while the job ran");
  }
  auto kept = jobs_->GetJob(running->job_id);
  ASSERT_EQ(kept->artifacts.size(), 1u);
  EXPECT_EQ(kept->steps_done, 1u);
  auto untouched = jobs_->GetJob(done->job_id);
  EXPECT_EQ(untouched->state, JobState::kCancelled);
  EXPECT_EQ(untouched->message, "cancelled");
  EXPECT_EQ(*jobs_->InterruptUnfinished("again"), 0);
}

TEST_F(JobCatalogueTest, ListPagesInIdOrder) {
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i) ids.push_back(jobs_->InsertJob(Campaign("j" + std::to_string(i), 1))->job_id);
  std::sort(ids.begin(), ids.end());
  auto page = jobs_->ListJobs("", 3);
  ASSERT_TRUE(page.ok());
  ASSERT_EQ(page->size(), 3u);
  auto rest = jobs_->ListJobs(page->back().job_id, 3);
  ASSERT_TRUE(rest.ok());
  ASSERT_EQ(rest->size(), 2u);
  std::vector<std::string> listed;
  for (const auto& j : *page) listed.push_back(j.job_id);
  for (const auto& j : *rest) listed.push_back(j.job_id);
  EXPECT_EQ(listed, ids);
  EXPECT_EQ(jobs_->ListJobs("", 0).status().code(), StatusCode::kInvalidArgument);
}


TEST_F(JobCatalogueTest, ReopenKeepsScansDropsReportsAndContinuesTheSequence) {
  auto job = jobs_->InsertJob(Campaign("resumable", 4));
  ASSERT_TRUE(job.ok());
  const std::string id = job->job_id;
  ASSERT_TRUE(jobs_->AddArtifact(Scan(id, "scan-r00-v00.ply", 'a'), {JobState::kRunning, "scan 1", 1, 2}).ok());
  ASSERT_TRUE(jobs_->AddArtifact(Scan(id, "scan-r00-v01.ply", 'b'), {JobState::kRunning, "scan 2", 2, 3}).ok());
  ArtifactRecord report = Scan(id, "campaign.json", 'c');
  report.info.clear();
  ASSERT_TRUE(jobs_->AddArtifact(report, {JobState::kRunning, "campaign.json written", 2, 4}).ok());
  ASSERT_TRUE(jobs_->UpdateProgress(id, {JobState::kCancelled, "cancelled after 2 of 4 steps", 2, 5}).ok());

  auto reopened = jobs_->ReopenJob(id, "campaign", "queued to resume");
  ASSERT_TRUE(reopened.ok()) << reopened.status().ToString();
  const auto& [record, dropped] = *reopened;
  EXPECT_EQ(record.state, JobState::kQueued);
  EXPECT_EQ(record.message, "queued to resume");
  EXPECT_EQ(record.last_sequence, 5u);
  ASSERT_EQ(record.artifacts.size(), 2u);
  EXPECT_EQ(record.artifacts[0].name, "scan-r00-v00.ply");
  EXPECT_EQ(record.artifacts[1].name, "scan-r00-v01.ply");
  EXPECT_EQ(dropped, std::vector<std::string>{std::string(64, 'c')});

  // The reopened job takes events and artifacts again; a new artifact follows the kept ones.
  ASSERT_TRUE(jobs_->UpdateProgress(id, {JobState::kRunning, "resumed", 2, 6}).ok());
  auto third = jobs_->AddArtifact(Scan(id, "scan-r01-v00.ply", 'd'), {JobState::kRunning, "scan 3", 3, 7});
  ASSERT_TRUE(third.ok());
  EXPECT_EQ(third->ordinal, 2u);
  Reopen();
  auto got = jobs_->GetJob(id);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->state, JobState::kRunning);
  EXPECT_EQ(got->last_sequence, 7u);
  EXPECT_EQ(got->artifacts.size(), 3u);
}

TEST_F(JobCatalogueTest, ReopenRefusesWhatCannotResumeAndChangesNothing) {
  auto succeeded = jobs_->InsertJob(Campaign("done", 1));
  auto running = jobs_->InsertJob(Campaign("running", 1));
  JobRecord model = Campaign("model", 1);
  model.kind = "model";
  auto other = jobs_->InsertJob(model);
  ASSERT_TRUE(succeeded.ok() && running.ok() && other.ok());
  ASSERT_TRUE(
      jobs_->AddArtifact(Scan(succeeded->job_id, "scan-r00-v00.ply", 'a'), {JobState::kRunning, "", 1, 1}).ok());
  ASSERT_TRUE(jobs_->UpdateProgress(succeeded->job_id, {JobState::kSucceeded, "done", 1, 2}).ok());
  ASSERT_TRUE(jobs_->UpdateProgress(running->job_id, {JobState::kRunning, "planned", 0, 1}).ok());
  ASSERT_TRUE(jobs_->UpdateProgress(other->job_id, {JobState::kInterrupted, "stopped", 0, 1}).ok());

  struct Case {
    std::string id;
    const char* says;
  };
  for (const Case& c : {Case{succeeded->job_id, "succeeded"}, Case{running->job_id, "has not ended (RUNNING)"},
                        Case{other->job_id, "is a model job"}}) {
    auto refused = jobs_->ReopenJob(c.id, "campaign", "queued to resume");
    EXPECT_EQ(refused.status().code(), StatusCode::kFailedPrecondition) << c.id;
    EXPECT_NE(refused.status().message().find("job '" + c.id + "' " + c.says), std::string::npos)
        << refused.status().message();
  }
  EXPECT_EQ(jobs_->ReopenJob("job_missing", "campaign", "").status().code(), StatusCode::kNotFound);
  auto kept = jobs_->GetJob(succeeded->job_id);
  ASSERT_TRUE(kept.ok());
  EXPECT_EQ(kept->state, JobState::kSucceeded);
  EXPECT_EQ(kept->artifacts.size(), 1u);
  EXPECT_EQ(jobs_->GetJob(other->job_id)->state, JobState::kInterrupted);
}

// SQLite's own page limit stands in for a full disk: it fails writes with SQLITE_FULL.
TEST_F(JobCatalogueTest, AFullDatabaseIsResourceExhaustedAndKeepsWhatWasStored) {
  std::vector<std::string> stored;
  for (int i = 0; i < 3; ++i) {
    auto job = jobs_->InsertJob(Campaign("before", 1));
    ASSERT_TRUE(job.ok());
    stored.push_back(job->job_id);
  }
  {
    std::lock_guard lock(jobs_->database().mutex());
    sqlite3* db = jobs_->database().handle();
    ASSERT_EQ(sqlite3_exec(db, "PRAGMA wal_checkpoint(TRUNCATE)", nullptr, nullptr, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "PRAGMA max_page_count = 1", nullptr, nullptr, nullptr), SQLITE_OK);
  }
  JobRecord large = Campaign("large", 1);
  large.spec.assign(64 << 10, 'x');
  Status full = Status::Ok();
  for (int i = 0; i < 64 && full.ok(); ++i) {
    auto job = jobs_->InsertJob(large);
    full = job.status();
  }
  EXPECT_EQ(full.code(), StatusCode::kResourceExhausted) << full.ToString();
  EXPECT_NE(full.message().find("no space left"), std::string::npos) << full.message();
  for (const std::string& id : stored) {
    auto job = jobs_->GetJob(id);
    ASSERT_TRUE(job.ok()) << job.status().ToString();
    EXPECT_EQ(job->name, "before");
  }
}

}  // namespace
}  // namespace vscan::store
