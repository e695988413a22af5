// Deleting jobs: rows go, blob files go when no row of any table names them, and the bytes on
// disk go down.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "store/blob_gc.h"
#include "store/blob_store.h"
#include "store/catalogue.h"
#include "store/database.h"
#include "store/job_catalogue.h"
#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

uint64_t BytesUnder(const std::filesystem::path& dir) {
  uint64_t total = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) total += entry.file_size();
  }
  return total;
}

class JobDeletionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto database = Database::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(database.ok()) << database.status().ToString();
    database_ = *database;
    jobs_ = std::make_unique<JobCatalogue>(database_);
    meshes_ = std::make_unique<Catalogue>(database_);
    ASSERT_TRUE(blobs_.Open().ok());
  }

  // An ended job with one artifact per payload.
  std::string EndedJob(const std::vector<std::string>& payloads, JobState end = JobState::kSucceeded) {
    JobRecord job;
    job.kind = "campaign";
    auto inserted = jobs_->InsertJob(job);
    EXPECT_TRUE(inserted.ok());
    uint64_t sequence = 1;
    for (const std::string& bytes : payloads) {
      auto sha = blobs_.Put(bytes);
      EXPECT_TRUE(sha.ok());
      ArtifactRecord artifact;
      artifact.job_id = inserted->job_id;
      artifact.name = "scan.ply";
      artifact.media_type = "model/ply";
      artifact.sha256 = *sha;
      artifact.size_bytes = bytes.size();
      EXPECT_TRUE(jobs_->AddArtifact(artifact, {JobState::kRunning, "scan", 1, sequence++}).ok());
    }
    EXPECT_TRUE(jobs_->UpdateProgress(inserted->job_id, {end, "ended", 1, sequence}).ok());
    return inserted->job_id;
  }

  StatusOr<CollectedBlobs> Delete(const std::string& job_id) {
    ASSIGN_OR_RETURN(const std::vector<std::string> names, jobs_->DeleteJob(job_id));
    return CollectBlobs(*database_, blobs_, names);
  }

  test::TempDir dir_;
  std::shared_ptr<Database> database_;
  std::unique_ptr<JobCatalogue> jobs_;
  std::unique_ptr<Catalogue> meshes_;
  BlobStore blobs_{dir_.path() / "blobs"};
};

TEST_F(JobDeletionTest, DeletingAJobRemovesItsRowsAndFreesItsBytes) {
  const std::string big(1 << 20, 'x');
  const std::string job_id = EndedJob({big, big + "y"});
  const uint64_t before = BytesUnder(blobs_.root());
  ASSERT_GE(before, 2u << 20);

  auto freed = Delete(job_id);
  ASSERT_TRUE(freed.ok()) << freed.status().ToString();
  EXPECT_EQ(freed->files, 2u);
  EXPECT_EQ(freed->bytes, 2 * big.size() + 1);
  EXPECT_EQ(BytesUnder(blobs_.root()), before - freed->bytes);
  EXPECT_EQ(jobs_->GetJob(job_id).status().code(), StatusCode::kNotFound);
  EXPECT_FALSE(blobs_.Contains(Sha256Hex(big)));
  EXPECT_EQ(jobs_->DeleteJob(job_id).status().code(), StatusCode::kNotFound);
}

TEST_F(JobDeletionTest, ABlobAnotherRowNamesStays) {
  const std::string shared = "shared scan bytes";
  const std::string first = EndedJob({shared, "only in the first"});
  const std::string second = EndedJob({shared});
  MeshRecord mesh;
  mesh.name = "m";
  mesh.sha256 = *blobs_.Put("mesh bytes");
  ASSERT_TRUE(meshes_->InsertMesh(mesh).ok());
  const std::string third = EndedJob({"mesh bytes"});

  auto freed = Delete(first);
  ASSERT_TRUE(freed.ok());
  EXPECT_EQ(freed->files, 1u);
  EXPECT_TRUE(blobs_.Contains(Sha256Hex(shared)));
  EXPECT_FALSE(blobs_.Contains(Sha256Hex("only in the first")));
  auto second_job = jobs_->GetJob(second);
  ASSERT_TRUE(second_job.ok());
  EXPECT_TRUE(blobs_.Get(second_job->artifacts[0].sha256).ok());

  // A mesh's blob outlives the job that happened to produce the same bytes.
  ASSERT_TRUE(Delete(third).ok());
  EXPECT_TRUE(blobs_.Contains(mesh.sha256));
  ASSERT_TRUE(Delete(second).ok());
  EXPECT_FALSE(blobs_.Contains(Sha256Hex(shared)));
}

TEST_F(JobDeletionTest, APinnedBlobIsNotCollected) {
  const std::string job_id = EndedJob({"about to be reused"});
  auto pin = blobs_.PutPinned("about to be reused");
  ASSERT_TRUE(pin.ok());
  auto freed = Delete(job_id);
  ASSERT_TRUE(freed.ok());
  EXPECT_EQ(freed->files, 0u);
  EXPECT_TRUE(blobs_.Contains(pin->sha256()));
}

TEST_F(JobDeletionTest, UnfinishedJobsCannotBeDeleted) {
  JobRecord job;
  job.kind = "campaign";
  auto queued = jobs_->InsertJob(job);
  auto running = jobs_->InsertJob(job);
  ASSERT_TRUE(queued.ok() && running.ok());
  ASSERT_TRUE(jobs_->UpdateProgress(running->job_id, {JobState::kRunning, "running", 0, 1}).ok());
  for (const std::string& id : {queued->job_id, running->job_id}) {
    const auto refused = jobs_->DeleteJob(id);
    EXPECT_EQ(refused.status().code(), StatusCode::kFailedPrecondition) << id;
    EXPECT_EQ(refused.status().message().rfind("job_id:", 0), 0u) << refused.status().message();
    EXPECT_TRUE(jobs_->GetJob(id).ok());
  }
  EXPECT_EQ(jobs_->DeleteJob("job_missing").status().code(), StatusCode::kNotFound);
}

TEST_F(JobDeletionTest, ListsEndedJobsOlderThanACutoff) {
  JobRecord job;
  job.kind = "campaign";
  auto running = jobs_->InsertJob(job);
  ASSERT_TRUE(running.ok());
  ASSERT_TRUE(jobs_->UpdateProgress(running->job_id, {JobState::kRunning, "r", 0, 1, 1000}).ok());
  const std::string old_id = EndedJob({});
  ASSERT_TRUE(jobs_->DeleteJob(old_id).ok());
  auto old_job = jobs_->InsertJob(job);
  auto recent = jobs_->InsertJob(job);
  ASSERT_TRUE(jobs_->UpdateProgress(old_job->job_id, {JobState::kFailed, "f", 0, 1, 2000}).ok());
  ASSERT_TRUE(jobs_->UpdateProgress(recent->job_id, {JobState::kCancelled, "c", 0, 1, 9000}).ok());

  auto expired = jobs_->ListEndedBefore(5000, 10);
  ASSERT_TRUE(expired.ok()) << expired.status().ToString();
  EXPECT_EQ(*expired, std::vector<std::string>{old_job->job_id});
}

TEST_F(JobDeletionTest, TheStartupSweepRemovesOnlyOldOrphans) {
  const std::string job_id = EndedJob({"kept by its job"});
  auto orphan = blobs_.Put("left by a crash after the row went");
  auto young = blobs_.Put("written a moment ago");
  ASSERT_TRUE(orphan.ok() && young.ok());
  const auto path_of = [&](const std::string& sha) { return blobs_.root() / sha.substr(0, 2) / sha; };
  const auto old_time = std::filesystem::file_time_type::clock::now() - std::chrono::hours(1);
  std::filesystem::last_write_time(path_of(*orphan), old_time);
  const std::string kept = Sha256Hex("kept by its job");
  std::filesystem::last_write_time(path_of(kept), old_time);
  const auto temp = blobs_.root() / kept.substr(0, 2) / ("." + kept + ".tmp.abcdef");
  { std::ofstream(temp) << "half written"; }
  std::filesystem::last_write_time(temp, old_time);

  auto swept = SweepOrphanBlobs(*database_, blobs_, std::chrono::minutes(5));
  ASSERT_TRUE(swept.ok()) << swept.status().ToString();
  EXPECT_EQ(swept->files, 2u);
  EXPECT_FALSE(blobs_.Contains(*orphan));
  EXPECT_FALSE(std::filesystem::exists(temp));
  EXPECT_TRUE(blobs_.Contains(*young));
  EXPECT_TRUE(blobs_.Contains(kept));
  EXPECT_TRUE(jobs_->GetJob(job_id).ok());
}

}  // namespace
}  // namespace vscan::store
