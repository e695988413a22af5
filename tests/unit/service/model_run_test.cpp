// Whole model jobs over the scans of campaigns run in a test world (a UR5 beside a rotary table
// with an L-shaped block on it): alignment against the arm's true poses, reconstruction and
// evaluation against the block, next best views that really add coverage when scanned, stops.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "model_test_json.h"
#include "model_test_world.h"
#include "service/model_run.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

using testing::JsonValue;
using testing::ModelWorld;
using testing::StoredJob;

constexpr double kTau = 0.001;

std::vector<CampaignViewpoint> ThreeViewpoints() {
  return {ModelWorld::Viewpoint(0.3, 10), ModelWorld::Viewpoint(0.3, 35), ModelWorld::Viewpoint(0.3, 60)};
}

JsonValue Report(const StoredJob& job) {
  const auto it = job.artifacts.find("model.json");
  if (it == job.artifacts.end()) {
    ADD_FAILURE() << "no model.json";
    return JsonValue();
  }
  return JsonValue::Parse(it->second);
}

ModelRequest Evaluate(const std::string& campaign_job_id) {
  ModelRequest request;
  request.campaign_job_id = campaign_job_id;
  request.evaluate = true;
  request.tau = kTau;
  request.skip_next_best_views = true;
  return request;
}

TEST(ModelRunTest, NoiseFreeScansStayAtTheirTruePosesAndRebuildTheBlock) {
  ModelWorld world;
  const std::string campaign = world.RunCampaign(world.Campaign(ThreeViewpoints(), 4));
  ModelRequest request = Evaluate(campaign);
  request.reconstruct = true;
  const auto job = world.RunModel(request);

  ASSERT_EQ(job->end_state, store::JobState::kSucceeded) << job->end_message;
  EXPECT_TRUE(job->end_message.starts_with("12 of 12 scans aligned")) << job->end_message;
  ASSERT_EQ(job->alignments.size(), 12u);
  for (size_t i = 0; i < job->alignments.size(); ++i) EXPECT_EQ(job->alignments[i].index, i);
  const JsonValue report = Report(*job);
  const JsonValue& alignment = report["alignment"];
  EXPECT_EQ(alignment["aligned"].number(), 12);
  EXPECT_EQ(alignment["initial_pose"].text(), "known");
  for (size_t i = 0; i < 12; ++i) {
    const JsonValue& scan = alignment["scans"][i];
    SCOPED_TRACE(scan["name"].text());
    EXPECT_TRUE(scan["aligned"].boolean());
    // The commanded pose is the true one without encoder noise, and alignment keeps it.
    EXPECT_LT(scan["initial_rotation_error_deg"].number(), 1e-6);
    EXPECT_LT(scan["rotation_error_deg"].number(), 0.01);
    EXPECT_LT(scan["translation_error_m"].number(), 2e-5);
    EXPECT_GT(scan["fitness"].number(), 0.5);
  }
  EXPECT_EQ(report["crop"]["kind"].text(), "cylinder");
  EXPECT_EQ(report["reconstruction"]["method"].text(), "tsdf");
  EXPECT_GT(report["reconstruction"]["triangles"].number(), 1000);

  const JsonValue& evaluation = report["evaluation"];
  EXPECT_EQ(evaluation["tau"].number(), kTau);
  EXPECT_NEAR(evaluation["ground_truth"]["area_m2"].number(), 0.026 - 0.0048 - 0.28 * 0.001, 1e-6);
  // Every scanned point lies on the block; the views from above and the side see most of it.
  EXPECT_GT(evaluation["union"]["precision"].number(), 0.999);
  const double coverage = evaluation["coverage"].number();
  EXPECT_GT(coverage, 0.8);
  EXPECT_LE(coverage, 1.0);
  EXPECT_GT(evaluation["mesh"]["precision"].number(), 0.95);
  EXPECT_GT(evaluation["mesh"]["f_score"].number(), 0.8);

  for (const char* name : {"aligned.ply", "mesh.ply", "uncovered.ply", "coverage.png", "model.json"}) {
    EXPECT_TRUE(job->artifacts.count(name)) << name;
  }
  EXPECT_TRUE(job->artifacts["coverage.png"].starts_with("\x89PNG"));
  const auto uncovered = ParsePly(job->artifacts["uncovered.ply"], "uncovered.ply", 1u << 30);
  ASSERT_TRUE(uncovered.ok());
  EXPECT_NEAR(static_cast<double>(uncovered->size()) / evaluation["ground_truth"]["samples"].number(), 1 - coverage,
              1e-9);
  EXPECT_EQ(job->steps_done.back(), 12u + 3u);
}

}  // namespace
}  // namespace vscan::service
