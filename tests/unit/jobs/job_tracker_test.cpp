#include "api/job/job_tracker.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <cstdint>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include <google/protobuf/util/time_util.h>

#include "store/blob_store.h"
#include "store/cloud_catalogue.h"
#include "store/ids.h"
#include "vscan/common/point_cloud.h"
#include "vscan_test/temp_dir.h"

namespace vscan::api {
namespace {

using namespace std::chrono_literals;

// A watcher that a test thread drives: OnJobEvent only counts pokes, the thread pulls with Get.
class PullingWatcher final : public JobWatcher {
 public:
  void OnJobEvent() override {
    {
      std::lock_guard lock(mutex_);
      ++pokes_;
    }
    poked_.notify_all();
  }
  uint64_t pokes() {
    std::lock_guard lock(mutex_);
    return pokes_;
  }
  // Waits until poked more than seen times (or a while, so a lost poke shows as slowness, not a hang).
  void WaitBeyond(uint64_t seen) {
    std::unique_lock lock(mutex_);
    poked_.wait_for(lock, 5s, [&] { return pokes_ > seen; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable poked_;
  uint64_t pokes_ = 0;
};

// What one watcher saw from attaching until the job ended.
struct Seen {
  uint64_t first_sequence = 0;
  std::vector<uint64_t> sequences;
  v1::JobState last_state = v1::JOB_STATE_UNSPECIFIED;
};

// Follows the job until it ends, or only for `limit` events.
Seen Follow(LiveJob& live, size_t limit = SIZE_MAX) {
  auto* watcher = new PullingWatcher;
  Seen seen;
  uint64_t next = 0;
  seen.last_state = live.Attach(watcher, &next).state();
  seen.first_sequence = next;
  while (seen.sequences.size() < limit) {
    const uint64_t pokes = watcher->pokes();
    v1::WatchJobResponse response;
    const LiveJob::Next got = live.Get(watcher, next, &response);
    if (got == LiveJob::Next::kEnded) break;
    if (got == LiveJob::Next::kWait) {
      watcher->WaitBeyond(pokes);
      continue;
    }
    seen.sequences.push_back(response.event().sequence());
    seen.last_state = response.job().state();
    ++next;
  }
  live.Detach(watcher);
  watcher->Unref();
  return seen;
}

JobEventUpdate Running(uint32_t step) {
  JobEventUpdate update;
  update.message = "step " + std::to_string(step);
  update.steps_done = step;
  update.step = step;
  return update;
}

class JobTrackerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto opened = store::JobCatalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(opened.ok()) << opened.status().ToString();
    catalogue_ = std::move(opened).value();
    ASSERT_TRUE(blobs_.Open().ok());
    tracker_ = std::make_unique<JobTracker>(*catalogue_, blobs_);
  }

  std::string Create(uint32_t steps_total) {
    v1::CampaignSpec spec;
    spec.set_name("tracked");
    auto job = tracker_->Create(service::JobKind::kCampaign, spec.name(), spec, steps_total);
    EXPECT_TRUE(job.ok()) << job.status().ToString();
    return job.ok() ? job->job_id() : "";
  }

  test::TempDir dir_;
  std::unique_ptr<store::JobCatalogue> catalogue_;
  store::BlobStore blobs_{dir_.path() / "blobs"};
  std::unique_ptr<JobTracker> tracker_;
};

TEST_F(JobTrackerTest, KeepsNoEventsWhenNobodyWatches) {
  const std::string id = Create(300);
  auto live = tracker_->Live(id);
  ASSERT_NE(live, nullptr);
  for (uint32_t step = 1; step <= 300; ++step) ASSERT_TRUE(tracker_->Record(id, Running(step)).ok());
  EXPECT_EQ(live->retained_events(), 0u);
  EXPECT_EQ(live->next_sequence(), 301u);
  // The job itself is whole: state, progress and the latest message.
  const v1::Job job = live->Snapshot();
  EXPECT_EQ(job.steps_done(), 300u);
  EXPECT_DOUBLE_EQ(job.progress(), 1.0);
  EXPECT_EQ(job.message(), "step 300");
}

TEST_F(JobTrackerTest, WatchersAndTheCatalogueAgreeOnEachUpdateTime) {
  const std::string id = Create(40);
  auto live = tracker_->Live(id);
  ASSERT_NE(live, nullptr);
  for (uint32_t step = 1; step <= 40; ++step) {
    JobEventUpdate update = Running(step);
    if (step == 40) update.state = store::JobState::kSucceeded;
    ASSERT_TRUE((step == 40 ? tracker_->End(id, update) : tracker_->Record(id, update)).ok());
    auto stored = catalogue_->GetJob(id);
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    EXPECT_EQ(google::protobuf::util::TimeUtil::TimestampToMilliseconds(live->Snapshot().update_time()),
              stored->update_time_ms)
        << "step " << step;
  }
}

TEST_F(JobTrackerTest, KeepsEventsOnlyUntilTheSlowestWatcherHasTakenThem) {
  const std::string id = Create(10);
  auto live = tracker_->Live(id);
  ASSERT_NE(live, nullptr);
  auto* slow = new PullingWatcher;
  uint64_t slow_next = 0;
  live->Attach(slow, &slow_next);
  EXPECT_EQ(slow_next, 1u);
  for (uint32_t step = 1; step <= 5; ++step) ASSERT_TRUE(tracker_->Record(id, Running(step)).ok());
  EXPECT_EQ(live->retained_events(), 5u);
  v1::WatchJobResponse response;
  for (uint64_t sequence = 1; sequence <= 3; ++sequence) {
    ASSERT_EQ(live->Get(slow, sequence, &response), LiveJob::Next::kReady);
    EXPECT_EQ(response.event().sequence(), sequence);
    EXPECT_EQ(response.event().message(), "step " + std::to_string(sequence));
  }
  EXPECT_EQ(live->retained_events(), 2u);

  auto* late = new PullingWatcher;
  uint64_t late_next = 0;
  live->Attach(late, &late_next);
  EXPECT_EQ(late_next, 6u);
  ASSERT_TRUE(tracker_->Record(id, Running(6)).ok());
  EXPECT_EQ(live->retained_events(), 3u);  // 4 and 5 for slow, 6 for both
  live->Detach(slow);
  slow->Unref();
  EXPECT_EQ(live->retained_events(), 1u);
  ASSERT_EQ(live->Get(late, 6, &response), LiveJob::Next::kReady);
  EXPECT_EQ(live->retained_events(), 0u);
  EXPECT_EQ(live->Get(late, 7, &response), LiveJob::Next::kWait);

  // The end stays readable by the watcher that has not taken it, though the job is no longer live.
  JobEventUpdate end = Running(6);
  end.state = store::JobState::kSucceeded;
  ASSERT_TRUE(tracker_->End(id, end).ok());
  EXPECT_EQ(tracker_->Live(id), nullptr);
  ASSERT_EQ(live->Get(late, 7, &response), LiveJob::Next::kReady);
  EXPECT_EQ(response.job().state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(live->Get(late, 8, &response), LiveJob::Next::kEnded);
  live->Detach(late);
  late->Unref();
}

TEST_F(JobTrackerTest, AnEndThatCannotBeStoredStillReadsAsEnded) {
  const std::string id = Create(4);
  ASSERT_TRUE(tracker_->Record(id, Running(1)).ok());
  // Another connection holds the database's write lock past the catalogue's busy timeout.
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open((dir_.path() / "catalogue.sqlite").c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  JobEventUpdate end = Running(1);
  end.state = store::JobState::kCancelled;
  end.message = "cancelled";
  EXPECT_FALSE(tracker_->End(id, end).ok());
  sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(other);

  auto job = tracker_->Get(id);
  ASSERT_TRUE(job.ok()) << job.status().ToString();
  EXPECT_EQ(job->state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(job->message(), "cancelled");
  // It takes no more events.
  const Status late = tracker_->Record(id, Running(2));
  EXPECT_EQ(late.code(), StatusCode::kFailedPrecondition) << late.ToString();
  // A watcher gets the job as it ended and nothing more.
  auto live = tracker_->Live(id);
  ASSERT_NE(live, nullptr);
  const Seen seen = Follow(*live);
  EXPECT_EQ(seen.last_state, v1::JOB_STATE_CANCELLED);
  EXPECT_TRUE(seen.sequences.empty());
}

// The runner thread records events and artifacts while watchers come and go and readers take
// snapshots: every watcher sees consecutive events from where it joined, and those that stay see
// the end.
TEST_F(JobTrackerTest, WatchersThatComeAndGoSeeConsecutiveEventsWhileTheJobRuns) {
  constexpr uint32_t kSteps = 120;
  const std::string id = Create(kSteps);
  auto live = tracker_->Live(id);
  ASSERT_NE(live, nullptr);

  std::vector<Seen> stayed(3), left(3);
  std::vector<std::thread> threads;
  std::thread runner([&] {
    for (uint32_t step = 1; step <= kSteps; ++step) {
      if (step % 10 == 0) {
        const std::string bytes = "scan " + std::to_string(step);
        auto artifact = tracker_->RecordArtifact(id, "scan-" + std::to_string(step) + ".ply", "model/ply", bytes,
                                                 nullptr, Running(step));
        ASSERT_TRUE(artifact.ok()) << artifact.status().ToString();
      } else {
        ASSERT_TRUE(tracker_->Record(id, Running(step)).ok());
      }
    }
    JobEventUpdate end = Running(kSteps);
    end.state = store::JobState::kSucceeded;
    ASSERT_TRUE(tracker_->End(id, end).ok());
  });
  for (size_t i = 0; i < stayed.size(); ++i) {
    threads.emplace_back([&, i] {
      std::this_thread::sleep_for(std::chrono::milliseconds(5 * i));
      stayed[i] = Follow(*live);
    });
    threads.emplace_back([&, i] {
      std::this_thread::sleep_for(std::chrono::milliseconds(3 * i));
      left[i] = Follow(*live, 7);
    });
  }
  threads.emplace_back([&] {
    for (int i = 0; i < 50; ++i) {
      auto job = tracker_->Get(id);
      ASSERT_TRUE(job.ok()) << job.status().ToString();
      EXPECT_LE(job->steps_done(), kSteps);
    }
  });
  runner.join();
  for (auto& t : threads) t.join();

  const uint64_t last = kSteps + 1;  // the end event
  for (const Seen& seen : stayed) {
    EXPECT_EQ(seen.last_state, v1::JOB_STATE_SUCCEEDED);
    for (size_t k = 0; k < seen.sequences.size(); ++k) EXPECT_EQ(seen.sequences[k], seen.first_sequence + k);
    if (!seen.sequences.empty()) {
      EXPECT_EQ(seen.sequences.back(), last);
    }
  }
  for (const Seen& seen : left) {
    EXPECT_LE(seen.sequences.size(), 7u);
    for (size_t k = 0; k < seen.sequences.size(); ++k) EXPECT_EQ(seen.sequences[k], seen.first_sequence + k);
  }
  EXPECT_EQ(live->retained_events(), 0u);
  auto stored = catalogue_->GetJob(id);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(stored->state, store::JobState::kSucceeded);
  EXPECT_EQ(stored->last_sequence, last);
  EXPECT_EQ(stored->artifacts.size(), kSteps / 10);
}

}  // namespace
}  // namespace vscan::api

namespace vscan::api {
namespace {

JobEventUpdate Ended(store::JobState state) {
  JobEventUpdate update;
  update.state = state;
  update.message = "ended";
  return update;
}

TEST_F(JobTrackerTest, DeletesAnEndedJobWithItsFilesButNotALiveOne) {
  const std::string id = Create(1);
  auto artifact = tracker_->RecordArtifact(id, "scan-r00-v00.ply", "model/ply", std::string(4096, 's'), nullptr,
                                           Running(1));
  ASSERT_TRUE(artifact.ok()) << artifact.status().ToString();
  const std::string sha = store::Sha256Hex(std::string(4096, 's'));
  ASSERT_TRUE(blobs_.Contains(sha));

  const auto refused = tracker_->Delete(id);
  EXPECT_EQ(refused.status().code(), StatusCode::kFailedPrecondition) << refused.status().ToString();
  EXPECT_TRUE(blobs_.Contains(sha));

  ASSERT_TRUE(tracker_->End(id, Ended(store::JobState::kSucceeded)).ok());
  const auto deleted = tracker_->Delete(id);
  ASSERT_TRUE(deleted.ok()) << deleted.status().ToString();
  EXPECT_EQ(deleted->files, 1u);
  EXPECT_EQ(deleted->bytes, 4096u);
  EXPECT_FALSE(blobs_.Contains(sha));
  EXPECT_EQ(tracker_->Get(id).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(tracker_->Delete(id).status().code(), StatusCode::kNotFound);
}

TEST_F(JobTrackerTest, AScanRecordedWithItsCloudIsACloudUntilTheJobGoes) {
  auto clouds = store::CloudCatalogue::Open(dir_.path() / "catalogue.sqlite");
  ASSERT_TRUE(clouds.ok()) << clouds.status().ToString();
  const std::string id = Create(1);
  store::CloudRecord scan;
  scan.name = "scan-r00-v00.ply";
  scan.points = 7;
  scan.fields = kFieldPosition;
  scan.scene_id = "scn_0123456789abcdef";
  scan.world_from_sensor = Eigen::Matrix4d::Identity();
  scan.table_angle_deg = 45.0;
  const std::string bytes(2048, 'p');
  ASSERT_TRUE(tracker_->RecordArtifact(id, scan.name, "model/ply", bytes, nullptr, Running(1), &scan).ok());
  const auto listed = (*clouds)->List("", 10, id);
  ASSERT_TRUE(listed.ok()) << listed.status().ToString();
  ASSERT_EQ(listed->size(), 1u);
  const store::CloudRecord& cloud = listed->front();
  EXPECT_EQ(cloud.origin, store::CloudOrigin::kCampaignScan);
  EXPECT_EQ(cloud.sha256, store::Sha256Hex(bytes));
  EXPECT_EQ(cloud.size_bytes, bytes.size());
  EXPECT_EQ(cloud.points, 7u);
  EXPECT_EQ(cloud.table_angle_deg, 45.0);

  ASSERT_TRUE(tracker_->End(id, Ended(store::JobState::kSucceeded)).ok());
  const auto deleted = tracker_->Delete(id);
  ASSERT_TRUE(deleted.ok()) << deleted.status().ToString();
  EXPECT_EQ(deleted->files, 1u);
  EXPECT_EQ((*clouds)->Get(cloud.cloud_id).status().code(), StatusCode::kNotFound);
}

TEST_F(JobTrackerTest, RetentionDeletesOnlyJobsThatEndedBeforeTheCutoff) {
  const std::string old_job = Create(1);
  const std::string running = Create(1);
  ASSERT_TRUE(tracker_->RecordArtifact(old_job, "a.ply", "model/ply", "old bytes", nullptr, Running(1)).ok());
  ASSERT_TRUE(tracker_->End(old_job, Ended(store::JobState::kFailed)).ok());
  ASSERT_TRUE(tracker_->Record(running, Running(0)).ok());
  std::this_thread::sleep_for(20ms);
  const int64_t cutoff = store::NowMs();
  std::this_thread::sleep_for(20ms);
  const std::string recent = Create(1);
  ASSERT_TRUE(tracker_->End(recent, Ended(store::JobState::kCancelled)).ok());

  const auto deleted = tracker_->DeleteEndedBefore(cutoff);
  ASSERT_TRUE(deleted.ok()) << deleted.status().ToString();
  EXPECT_EQ(*deleted, 1);
  EXPECT_EQ(tracker_->Get(old_job).status().code(), StatusCode::kNotFound);
  EXPECT_FALSE(blobs_.Contains(store::Sha256Hex("old bytes")));
  EXPECT_TRUE(tracker_->Get(running).ok());
  EXPECT_TRUE(tracker_->Get(recent).ok());
  // Nothing older remains: a second pass deletes nothing.
  EXPECT_EQ(*tracker_->DeleteEndedBefore(cutoff), 0);
}

}  // namespace
}  // namespace vscan::api
