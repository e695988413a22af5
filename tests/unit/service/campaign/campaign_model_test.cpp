// Campaigns that align their scans as they capture them, then reconstruct and evaluate: each scan
// is aligned before the arm moves on, the result equals a model job run afterwards on the same
// scans, and model.json sits beside campaign.json.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "model_test_json.h"
#include "model_test_world.h"
#include "service/model/model_run.h"

namespace vscan::service {
namespace {

using testing::JsonValue;
using testing::ModelWorld;

constexpr double kCampaignTau = 0.001;

CampaignPlan AligningCampaign(ModelWorld& world, bool evaluate) {
  CampaignPlan plan = world.Campaign({world.Viewpoint(0.3, 10), world.Viewpoint(0.3, 35), world.Viewpoint(0.3, 60)},
                                     4, /*encoder_noise=*/true);
  ModelRequest request;
  request.evaluate = evaluate;
  request.reconstruct = evaluate;
  request.tau = kCampaignTau;
  request.skip_next_best_views = true;
  auto model = PlanCampaignModel(world.world.context(), request, plan.scene_id, plan.mount_id, true);
  EXPECT_TRUE(model.ok()) << model.status().ToString();
  if (model.ok()) plan.model = std::move(model).value();
  plan.model_steps = plan.model ? CampaignModelSteps(*plan.model) : 0;
  return plan;
}

JsonValue Artifact(const testing::StoredJob& job, const std::string& name) {
  const auto it = job.artifacts.find(name);
  if (it == job.artifacts.end()) {
    ADD_FAILURE() << "no " << name;
    return JsonValue();
  }
  return JsonValue::Parse(it->second);
}

size_t MessageIndex(const std::vector<std::string>& messages, const std::string& prefix) {
  for (size_t i = 0; i < messages.size(); ++i) {
    if (messages[i].starts_with(prefix)) return i;
  }
  ADD_FAILURE() << "no message starts with '" << prefix << "'";
  return messages.size();
}

TEST(CampaignModelTest, EachScanIsAlignedBeforeTheNextIsCaptured) {
  ModelWorld world(/*encoder_sigma=*/0.001, testing::Bunny(), testing::BunnyUpright());
  const CampaignPlan plan = AligningCampaign(world, /*evaluate=*/true);
  ASSERT_TRUE(plan.model);
  EXPECT_EQ(plan.model->reconstruction, ReconstructionKind::kTsdf);
  const auto job = world.RunCampaignJob(plan);
  ASSERT_EQ(job->end_state, store::JobState::kSucceeded) << job->end_message;
  EXPECT_NE(job->end_message.find("12 scans captured, 0 steps skipped; 12 of 12 scans aligned"), std::string::npos)
      << job->end_message;

  // Scan k's alignment is reported after its capture and before scan k+1 is captured.
  ASSERT_EQ(job->alignments.size(), 12u);
  for (int k = 1; k < 12; ++k) {
    const size_t captured = MessageIndex(job->messages, "scan " + std::to_string(k) + " captured");
    const size_t aligned = MessageIndex(job->messages, "scan " + std::to_string(k) + " (");
    const size_t next = MessageIndex(job->messages, "scan " + std::to_string(k + 1) + " captured");
    EXPECT_LT(captured, aligned);
    EXPECT_LT(aligned, next);
    EXPECT_TRUE(job->alignments[k - 1].has_error);
    // The union grows as the scans come (a scan seeing only what is there already adds little).
    EXPECT_GE(job->alignments[k].union_points, job->alignments[k - 1].union_points);
  }
  EXPECT_GT(job->alignments.back().union_points, 2 * job->alignments.front().union_points);
  // The steps run on past the scans: the union, the mesh and the evaluation.
  EXPECT_EQ(job->steps_done.back(), plan.steps_total());
  EXPECT_EQ(plan.steps_total(), 12u + 3u);

  const JsonValue campaign = Artifact(*job, "campaign.json");
  EXPECT_EQ(campaign["steps_total"].number(), 12);
  const JsonValue report = Artifact(*job, "model.json");
  EXPECT_EQ(report["state"].text(), "SUCCEEDED");
  EXPECT_EQ(report["alignment"]["aligned"].number(), 12);
  const JsonValue& scans = report["alignment"]["scans"];
  for (size_t i = 0; i < scans.size(); ++i) EXPECT_FALSE(scans[i]["cloud_id"].text().empty());
  EXPECT_LT(report["alignment"]["rotation_error_deg"]["mean"].number(),
            report["alignment"]["initial_rotation_error_deg"]["mean"].number());
  EXPECT_EQ(report["reconstruction"]["method"].text(), "tsdf");
  EXPECT_GT(report["evaluation"]["coverage"].number(), 0.8);
  EXPECT_TRUE(job->artifacts.count("aligned.ply"));
  EXPECT_TRUE(job->artifacts.count("mesh.ply"));
  EXPECT_TRUE(job->artifacts.count("coverage.png"));
}

TEST(CampaignModelTest, AligningWhileScanningEqualsAModelJobAfterwards) {
  ModelWorld world(/*encoder_sigma=*/0.001, testing::Bunny(), testing::BunnyUpright());
  const auto campaign = world.RunCampaignJob(AligningCampaign(world, /*evaluate=*/false));
  ASSERT_EQ(campaign->end_state, store::JobState::kSucceeded) << campaign->end_message;
  ModelRequest request;
  request.campaign_job_id = campaign->job_id;
  const auto later = world.RunModel(request);
  ASSERT_EQ(later->end_state, store::JobState::kSucceeded) << later->end_message;

  const JsonValue during = Artifact(*campaign, "model.json")["alignment"]["scans"];
  const JsonValue after = Artifact(*later, "model.json")["alignment"]["scans"];
  ASSERT_EQ(during.size(), 12u);
  ASSERT_EQ(after.size(), 12u);
  for (size_t i = 0; i < during.size(); ++i) {
    EXPECT_EQ(during[i]["name"].text(), after[i]["name"].text());
    EXPECT_EQ(during[i]["cloud_id"].text(), after[i]["cloud_id"].text());
    EXPECT_NEAR(during[i]["rotation_error_deg"].number(), after[i]["rotation_error_deg"].number(), 1e-6);
    EXPECT_NEAR(during[i]["translation_error_m"].number(), after[i]["translation_error_m"].number(), 1e-8);
  }
}

// Range noise of 0.5 mm on the small L-block, from an arm without encoder noise: the commanded
// poses are exact and the pose graph, which knows it, keeps them although the noisy scans alone
// would pull them apart by several tenths of a millimetre.
TEST(CampaignModelTest, NoisyScansFromAnExactArmKeepTheirExactPoses) {
  ModelWorld world;
  CampaignPlan plan = AligningCampaign(world, /*evaluate=*/false);
  plan.apply_encoder_noise = false;
  plan.scan.measurement.noise.sigma_a = 0.0005;
  plan.scan.measurement.noise.along_ray = true;
  const auto job = world.RunCampaignJob(plan);
  ASSERT_EQ(job->end_state, store::JobState::kSucceeded) << job->end_message;
  const JsonValue report = Artifact(*job, "model.json");
  ASSERT_EQ(report["alignment"]["aligned"].number(), 12);
  EXPECT_LT(report["alignment"]["rotation_error_deg"]["max"].number(), 0.005);
  EXPECT_LT(report["alignment"]["translation_error_m"]["max"].number(), 5e-5);
  // What the scans alone made of them, as each was added against the union.
  double moved = 0;
  for (const auto& scan : job->alignments) moved = std::max(moved, scan.translation_error_m);
  EXPECT_GT(moved, 1e-4);
}

TEST(CampaignModelTest, AStoppedCampaignStillWritesModelJson) {
  ModelWorld world;
  const CampaignPlan plan = AligningCampaign(world, /*evaluate=*/true);
  jobs::JobControl control;
  control.RequestStop(jobs::StopReason::kCancelled);
  const auto job = world.RunCampaignJob(plan, &control);
  EXPECT_EQ(job->end_state, store::JobState::kCancelled);
  EXPECT_EQ(Artifact(*job, "model.json")["state"].text(), "CANCELLED");
}

TEST(CampaignModelTest, BadOptionsAreRefusedByName) {
  ModelWorld world;
  ModelRequest request;
  request.voxel_size = -1;
  auto plan = PlanCampaignModel(world.world.context(), request, world.scene_id, world.mount_id, true);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().field(), "alignment.voxel_size");
  request = ModelRequest();
  request.reconstruct = true;
  request.reconstruction = ReconstructionKind::kTsdf;
  plan = PlanCampaignModel(world.world.context(), request, world.scene_id, world.mount_id, /*pixels=*/false);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(plan.status().field(), "reconstruction.method");
  request.reconstruction = ReconstructionKind::kAuto;
  plan = PlanCampaignModel(world.world.context(), request, world.scene_id, world.mount_id, /*pixels=*/false);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->reconstruction, ReconstructionKind::kPoisson);
}

}  // namespace
}  // namespace vscan::service
