// A model job's request checked before any job exists: each bad value is refused with the field it
// names and the right code, and a good one resolves its clouds, scene, mount and defaults.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "service/clouds/cloud_store.h"
#include "service/model/model_plan.h"
#include "service_world.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

class NoCampaigns final : public CampaignRecords {
 public:
  StatusOr<CampaignRecord> Get(const std::string& job_id) override {
    const auto it = records.find(job_id);
    if (it == records.end()) return NotFound("job_id: no job '" + job_id + "'");
    return it->second;
  }
  std::map<std::string, CampaignRecord> records;
};

std::string SmallPly() {
  PointCloud cloud;
  cloud.positions = {{0, 0, 0.5f}, {0.01f, 0, 0.5f}, {0, 0.01f, 0.5f}};
  return EncodePly(cloud).value();
}

class ModelPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = world_.SceneWith(testing::FloorSquare(0.05), Pose3::Identity(), /*table=*/true);
    CloudUpload upload;
    upload.name = "posed";
    upload.frame = store::CloudFrame::kSensor;
    upload.world_from_sensor = Pose3::Identity();
    upload.scene_id = scene_;
    posed_ = ImportCloud(world_.context(), SmallPly(), upload).value().cloud_id;
    CloudUpload bare;
    bare.name = "bare";
    bare_ = ImportCloud(world_.context(), SmallPly(), bare).value().cloud_id;
  }

  ModelRequest Request() const {
    ModelRequest request;
    request.cloud_ids = {posed_};
    return request;
  }

  StatusOr<ModelPlan> Plan(const ModelRequest& request) { return PlanModel(world_.context(), campaigns_, request); }

  void ExpectRefused(const ModelRequest& request, StatusCode code, const std::string& field) {
    const auto plan = Plan(request);
    ASSERT_FALSE(plan.ok()) << "accepted, expected " << field;
    EXPECT_EQ(plan.status().code(), code) << plan.status().ToString();
    EXPECT_EQ(plan.status().field(), field) << plan.status().ToString();
  }

  testing::ServiceWorld world_;
  NoCampaigns campaigns_;
  std::string scene_;
  std::string posed_;
  std::string bare_;
};

TEST_F(ModelPlanTest, AGoodRequestResolvesItsCloudsSceneAndDefaults) {
  ModelRequest request = Request();
  request.cloud_ids.push_back(bare_);
  request.evaluate = true;
  request.reconstruct = true;
  const auto plan = Plan(request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->clouds.size(), 2u);
  EXPECT_EQ(plan->clouds[0].record.cloud_id, posed_);
  EXPECT_EQ(plan->clouds[1].label, "cloud_ids[1]");
  EXPECT_EQ(plan->total_points, 6u);
  ASSERT_TRUE(plan->scene.has_value());
  EXPECT_EQ(plan->scene->scene_id, scene_);  // the only scene the clouds name
  ASSERT_TRUE(plan->clouds[0].table.has_value());
  EXPECT_FALSE(plan->clouds[1].table.has_value());
  EXPECT_DOUBLE_EQ(plan->min_fitness, kDefaultMinFitness);
  EXPECT_EQ(plan->poisson_depth, kDefaultPoissonDepth);
  EXPECT_EQ(plan->reconstruction, ReconstructionKind::kPoisson);  // no camera, no pixels
  // No mount in the scene: evaluation runs, next best views are explained away.
  EXPECT_EQ(plan->next_best_views, 0u);
  EXPECT_FALSE(plan->next_best_views_note.empty());
}

TEST_F(ModelPlanTest, CloudsAreRequiredOnceAndFound) {
  ExpectRefused(ModelRequest{}, StatusCode::kInvalidArgument, "cloud_ids");
  ModelRequest both = Request();
  both.campaign_job_id = "job_0123456789abcdef";
  ExpectRefused(both, StatusCode::kInvalidArgument, "campaign_job_id");
  ModelRequest many;
  many.cloud_ids.assign(kMaxModelClouds + 1, posed_);
  ExpectRefused(many, StatusCode::kInvalidArgument, "cloud_ids");
  ModelRequest twice = Request();
  twice.cloud_ids.push_back(bare_);
  twice.cloud_ids.push_back(posed_);
  ExpectRefused(twice, StatusCode::kInvalidArgument, "cloud_ids[2]");
  ModelRequest unknown = Request();
  unknown.cloud_ids.push_back(bare_);
  unknown.cloud_ids.push_back("cld_00000000deadbeef");
  const auto plan = Plan(unknown);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(plan.status().message(), "cloud_ids[2]: cloud 'cld_00000000deadbeef' not found");
}

TEST_F(ModelPlanTest, LengthsMustBeZeroOrFiniteAndSane) {
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -0.001,
                        1e19, 1e-9};
  for (const double value : bad) {
    SCOPED_TRACE(value);
    ModelRequest voxel = Request();
    voxel.voxel_size = value;
    ExpectRefused(voxel, StatusCode::kInvalidArgument, "alignment.voxel_size");
    ModelRequest distance = Request();
    distance.max_correspondence_distance = value;
    ExpectRefused(distance, StatusCode::kInvalidArgument, "alignment.max_correspondence_distance");
    ModelRequest fusion = Request();
    fusion.reconstruction_voxel_size = value;
    ExpectRefused(fusion, StatusCode::kInvalidArgument, "reconstruction.voxel_size");
    ModelRequest tau = Request();
    tau.tau = value;
    ExpectRefused(tau, StatusCode::kInvalidArgument, "evaluation.tau");
  }
  ModelRequest good = Request();
  good.voxel_size = 0.002;
  good.tau = 0.0005;
  EXPECT_TRUE(Plan(good).ok());
}

TEST_F(ModelPlanTest, CountsAndSharesStayInTheirRanges) {
  ModelRequest fitness = Request();
  fitness.min_fitness = 1.5;
  ExpectRefused(fitness, StatusCode::kInvalidArgument, "alignment.min_fitness");
  fitness.min_fitness = std::numeric_limits<double>::quiet_NaN();
  ExpectRefused(fitness, StatusCode::kInvalidArgument, "alignment.min_fitness");
  ModelRequest depth = Request();
  depth.poisson_depth = kMaxPoissonDepth + 1;
  ExpectRefused(depth, StatusCode::kInvalidArgument, "reconstruction.poisson_depth");
  ModelRequest views = Request();
  views.next_best_views = kMaxNextBestViews + 1;
  ExpectRefused(views, StatusCode::kInvalidArgument, "evaluation.next_best_views");
  views.next_best_views = kMaxNextBestViews;
  EXPECT_TRUE(Plan(views).ok());
}

TEST_F(ModelPlanTest, ACropIsAFiniteBoxWithMinBelowMax) {
  ModelRequest crop = Request();
  crop.crop = ModelBox{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 0)};
  ExpectRefused(crop, StatusCode::kInvalidArgument, "crop");
  crop.crop->min.x() = std::numeric_limits<double>::quiet_NaN();
  ExpectRefused(crop, StatusCode::kInvalidArgument, "crop.min");
  crop.crop = ModelBox{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1e19)};
  ExpectRefused(crop, StatusCode::kInvalidArgument, "crop.max");
  crop.crop = ModelBox{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  EXPECT_TRUE(Plan(crop).ok());
}

TEST_F(ModelPlanTest, EvaluationNeedsASceneWithObjects) {
  ModelRequest request;
  request.cloud_ids = {bare_};
  request.evaluate = true;
  ExpectRefused(request, StatusCode::kFailedPrecondition, "scene_id");
  request.scene_id = "scn_00000000deadbeef";
  ExpectRefused(request, StatusCode::kNotFound, "scene_id");
  request.scene_id = world_.EmptyScene();
  ExpectRefused(request, StatusCode::kFailedPrecondition, "scene_id");
  request.scene_id = scene_;
  EXPECT_TRUE(Plan(request).ok());
}

TEST_F(ModelPlanTest, WhatTheCloudsCannotGiveIsAFailedPrecondition) {
  ModelRequest tsdf = Request();
  tsdf.reconstruct = true;
  tsdf.reconstruction = ReconstructionKind::kTsdf;
  ExpectRefused(tsdf, StatusCode::kFailedPrecondition, "reconstruction.method");
  ModelRequest known;
  known.cloud_ids = {posed_, bare_};
  known.initial_pose = InitialPoseMode::kKnown;
  ExpectRefused(known, StatusCode::kFailedPrecondition, "cloud_ids[1]");
  known.initial_pose = InitialPoseMode::kAuto;
  EXPECT_TRUE(Plan(known).ok());
}

TEST_F(ModelPlanTest, MountsMustExistInTheScene) {
  ModelRequest request = Request();
  request.mount_id = "mnt_00000000deadbeef";
  ExpectRefused(request, StatusCode::kNotFound, "mount_id");
  const std::string elsewhere = world_.Mount("ur5", world_.EmptyScene());
  request.mount_id = elsewhere;
  request.scene_id = scene_;
  ExpectRefused(request, StatusCode::kFailedPrecondition, "mount_id");
  request.mount_id = world_.Mount("ur5", scene_);
  request.evaluate = true;
  const auto plan = Plan(request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->mount_id, request.mount_id);
  EXPECT_EQ(plan->next_best_views, kDefaultNextBestViews);
}

TEST_F(ModelPlanTest, ACampaignMustExistBeACampaignAndHaveEnded) {
  ModelRequest request;
  request.campaign_job_id = "job_00000000deadbeef";
  ExpectRefused(request, StatusCode::kNotFound, "campaign_job_id");
  CampaignRecord running;
  running.job_id = "job_00000000000000aa";
  running.kind = "campaign";
  running.state = store::JobState::kRunning;
  campaigns_.records[running.job_id] = running;
  request.campaign_job_id = running.job_id;
  ExpectRefused(request, StatusCode::kFailedPrecondition, "campaign_job_id");
  CampaignRecord model = running;
  model.job_id = "job_00000000000000bb";
  model.kind = "model";
  model.state = store::JobState::kSucceeded;
  campaigns_.records[model.job_id] = model;
  request.campaign_job_id = model.job_id;
  ExpectRefused(request, StatusCode::kInvalidArgument, "campaign_job_id");
  CampaignRecord empty = running;
  empty.job_id = "job_00000000000000cc";
  empty.state = store::JobState::kSucceeded;
  campaigns_.records[empty.job_id] = empty;
  request.campaign_job_id = empty.job_id;
  ExpectRefused(request, StatusCode::kFailedPrecondition, "campaign_job_id");
}

}  // namespace
}  // namespace vscan::service
