// A picking job whose estimates come from a client: the job stores each step's scan, waits in the
// inbox, and plans on what is delivered; cancellation and the wait's bound end it.

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <thread>

#include "api/reports/proto_report_writer.h"
#include "picking_session_fixture.h"
#include "service/picking/estimates_inbox.h"
#include "service/picking/picking_run.h"
#include "vscan/common/report_json.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::service {
namespace {

using Clock = std::chrono::steady_clock;
constexpr const char* kJob = "job_client";

// The job's events and artifacts in the order they came, readable while the job runs.
class RecordedPicking final : public JobRecorder {
 public:
  Status Record(const JobEventUpdate& update) override {
    std::lock_guard lock(mutex_);
    log_.push_back("event " + update.message);
    return Status::Ok();
  }
  StatusOr<std::string> RecordArtifact(const std::string& name, const std::string&, const std::string& bytes,
                                       const ScanArtifact*, const store::CloudRecord*, const JobEventUpdate&) override {
    std::lock_guard lock(mutex_);
    log_.push_back("artifact " + name);
    files_[name] = bytes;
    return "art_" + name;
  }
  Status End(const JobEventUpdate& update) override {
    std::lock_guard lock(mutex_);
    end_state_ = update.state;
    end_message_ = update.message;
    return Status::Ok();
  }
  const ReportWriter& reports() const override { return reports_; }

  std::vector<std::string> log() const {
    std::lock_guard lock(mutex_);
    return log_;
  }
  std::string file(const std::string& name) const {
    std::lock_guard lock(mutex_);
    const auto found = files_.find(name);
    return found == files_.end() ? "" : found->second;
  }
  std::pair<store::JobState, std::string> end() const {
    std::lock_guard lock(mutex_);
    return {end_state_, end_message_};
  }

 private:
  api::ProtoReportWriter reports_;
  mutable std::mutex mutex_;
  std::vector<std::string> log_;
  std::map<std::string, std::string> files_;
  store::JobState end_state_ = store::JobState::kRunning;
  std::string end_message_;
};

// The true poses of a step's truth file, shifted by offset (world frame).
std::vector<picking::Estimate> TruthEstimates(const std::string& truth_json, const AwaitedStep& awaited,
                                              const Eigen::Vector3d& offset) {
  v1::PickingStepTruth truth;
  EXPECT_TRUE(ParseReport(truth_json, "truth", &truth).ok());
  std::vector<picking::Estimate> out;
  for (const v1::PickingPose& part : truth.parts()) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = part.world_from_part(r * 4 + c);
    Pose3 pose(m);
    pose.translation() += offset;
    size_t type = 0;
    while (type < awaited.part_names.size() && awaited.part_names[type] != part.part()) ++type;
    out.push_back({type, pose, 1.0});
  }
  return out;
}


std::string Numbered(size_t step, const char* suffix) {
  char name[48];
  std::snprintf(name, sizeof(name), "step-%03zu%s", step, suffix);
  return name;
}

class ClientEstimatesTest : public PickingSessionTest {
 protected:
  void SetUp() override {
    PickingSessionTest::SetUp();
    plan_.perception = Perception::kClient;
    client_.inbox = &inbox_;
  }

  // Runs the job on a thread; answer(awaited) is called on the test's thread for each awaited
  // step and returns false to stop answering.
  void Run(const std::function<bool(const AwaitedStep&)>& answer) {
    std::thread job([&] { RunPicking(world_.context(), recorder_, kJob, "client", "job_bin", plan_, control_, &client_); });
    while (recorder_.end().first == store::JobState::kRunning) {
      const auto awaited = inbox_.Awaiting(kJob);
      if (awaited && awaited->step != answered_) {
        answered_ = awaited->step;
        if (!answer(*awaited)) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    job.join();
  }

  // Claims and delivers the step's estimates as SubmitPickingEstimates does.
  void Deliver(const AwaitedStep& awaited, std::vector<picking::Estimate> estimates) {
    ASSERT_TRUE(inbox_.Claim(kJob, awaited.step).ok());
    EXPECT_EQ(inbox_.Claim(kJob, awaited.step).code(), StatusCode::kAlreadyExists);
    EXPECT_TRUE(inbox_.Deliver(kJob, awaited.step, std::move(estimates)));
  }

  EstimatesInbox inbox_;
  ClientEstimates client_;
  RecordedPicking recorder_;
  jobs::JobControl control_;
  size_t answered_ = SIZE_MAX;
};

TEST_F(ClientEstimatesTest, TheTruePosesSentBackEmptyTheBinAsTheTruthPerceptionDoes) {
  std::vector<std::string> log_when_awaited;
  Run([&](const AwaitedStep& awaited) {
    log_when_awaited = recorder_.log();
    EXPECT_EQ(awaited.scan_artifact, Numbered(awaited.step, ".ply"));
    EXPECT_EQ(awaited.part_names, std::vector<std::string>{"block"});
    EXPECT_EQ(inbox_.Claim(kJob, awaited.step + 1).code(), StatusCode::kFailedPrecondition);
    Deliver(awaited, TruthEstimates(recorder_.file(Numbered(awaited.step, "-truth.json")), awaited, {0, 0, 0}));
    return true;
  });
  const auto [state, message] = recorder_.end();
  EXPECT_EQ(state, store::JobState::kSucceeded) << message;
  EXPECT_EQ(message.rfind("empty: 6 of 6 parts picked in 6 steps", 0), 0u) << message;
  EXPECT_NE(recorder_.file("picking.json").find(R"("outcomes":{"picked":6})"), std::string::npos);
  EXPECT_EQ(PartsInScene(), 0u);
  // The scan was stored before the job said it awaits.
  ASSERT_GE(log_when_awaited.size(), 2u);
  const std::string last_scan = "artifact " + Numbered(answered_, ".ply");
  EXPECT_NE(std::find(log_when_awaited.begin(), log_when_awaited.end(), last_scan), log_when_awaited.end());
  EXPECT_EQ(log_when_awaited.back(), "event step " + std::to_string(answered_) + ": awaiting estimates");
}

TEST_F(ClientEstimatesTest, EstimatesTwentyMillimetresOffPickNothing) {
  plan_.session.max_failures_in_a_row = 2;
  Run([&](const AwaitedStep& awaited) {
    Deliver(awaited, TruthEstimates(recorder_.file(Numbered(awaited.step, "-truth.json")), awaited, {0.02, 0, 0}));
    return true;
  });
  const auto [state, message] = recorder_.end();
  EXPECT_EQ(state, store::JobState::kSucceeded) << message;
  EXPECT_EQ(message.rfind("failures in a row: 0 of 6 parts picked", 0), 0u) << message;
  const std::string picking_json = recorder_.file("picking.json");
  EXPECT_NE(picking_json.find(R"("outcomes":{"wrong_pose":2})"), std::string::npos) << picking_json;
  EXPECT_EQ(PartsInScene(), 6u);
}

TEST_F(ClientEstimatesTest, ACancelWhileAwaitingEndsTheJobPromptly) {
  plan_.estimates_timeout = std::chrono::minutes(10);
  Clock::time_point cancelled;
  Run([&](const AwaitedStep&) {
    cancelled = Clock::now();
    control_.RequestStop(jobs::StopReason::kCancelled);
    return false;
  });
  const double seconds = std::chrono::duration<double>(Clock::now() - cancelled).count();
  EXPECT_LT(seconds, 1.0);
  EXPECT_EQ(recorder_.end().first, store::JobState::kCancelled) << recorder_.end().second;
  EXPECT_FALSE(inbox_.Awaiting(kJob).has_value());
  EXPECT_EQ(PartsInScene(), 6u);
}

TEST_F(ClientEstimatesTest, NoEstimatesWithinTheBoundFailTheJobNamingTheStep) {
  plan_.estimates_timeout = std::chrono::milliseconds(300);
  const Clock::time_point start = Clock::now();
  Run([&](const AwaitedStep&) { return true; });
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 30.0);
  const auto [state, message] = recorder_.end();
  EXPECT_EQ(state, store::JobState::kFailed);
  EXPECT_EQ(message, "step 0: no estimates came within 0.3 s (spec.estimates_timeout_s)");
  EXPECT_FALSE(inbox_.Awaiting(kJob).has_value());
}

TEST_F(ClientEstimatesTest, EstimatesStoredForTheSamePileAreUsedWithoutWaiting) {
  client_.first_step = [] { return size_t{4}; };
  std::vector<size_t> done;
  client_.step_done = [&](size_t step) { done.push_back(step); };
  size_t asked = 0;
  client_.stored = [&](const AwaitedStep& awaited) -> std::optional<std::vector<picking::Estimate>> {
    ++asked;
    EXPECT_EQ(awaited.step, 4u);
    EXPECT_EQ(awaited.pile.size(), 6u);
    return TruthEstimates(recorder_.file(Numbered(4, "-truth.json")), awaited, {0, 0, 0});
  };
  plan_.session.max_steps = 1;
  plan_.estimates_timeout = std::chrono::seconds(2);
  Run([&](const AwaitedStep&) {
    ADD_FAILURE() << "the job waited for estimates it had";
    return false;
  });
  EXPECT_EQ(asked, 1u);
  EXPECT_EQ(done, std::vector<size_t>{4});
  EXPECT_EQ(recorder_.end().first, store::JobState::kSucceeded) << recorder_.end().second;
  EXPECT_EQ(recorder_.end().second.rfind("step bound: 1 of 6 parts picked in 1 steps", 0), 0u) << recorder_.end().second;
  EXPECT_NE(recorder_.file("picking.json").find(R"("step":4)"), std::string::npos);
  EXPECT_EQ(PartsInScene(), 5u);
}

TEST(EstimatesInbox, ASendForAnotherStepIsRefusedNamingTheStepAwaited) {
  EstimatesInbox inbox;
  EXPECT_EQ(inbox.Claim("job_a", 0).code(), StatusCode::kFailedPrecondition);
  AwaitedStep awaited;
  awaited.step = 3;
  inbox.Open("job_a", awaited);
  const Status other = inbox.Claim("job_a", 2);
  EXPECT_EQ(other.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(other.message().find("awaits the estimates of step 3"), std::string::npos) << other.message();
  ASSERT_TRUE(inbox.Claim("job_a", 3).ok());
  inbox.Release("job_a", 3);  // a store that failed gives the step back
  ASSERT_TRUE(inbox.Claim("job_a", 3).ok());
  std::thread sender([&] { EXPECT_TRUE(inbox.Deliver("job_a", 3, {{0, Pose3::Identity(), 0.5}})); });
  const auto got = inbox.Wait("job_a", std::chrono::seconds(10), nullptr);
  sender.join();
  ASSERT_TRUE(got.ok()) << got.status().ToString();
  EXPECT_EQ(got->size(), 1u);
  EXPECT_FALSE(inbox.Awaiting("job_a").has_value());
  EXPECT_FALSE(inbox.Deliver("job_a", 3, {}));
}

}  // namespace
}  // namespace vscan::service
