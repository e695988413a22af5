// The server's campaign validation with validate_only: the same verdict on every value as a real
// start, without a scene or a mount; the ids it is given are still checked.

#include <gtest/gtest.h>

#include <cmath>

#include <functional>
#include <memory>
#include <string>

#include "api/campaign/campaign_spec.h"
#include "service_world.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

v1::Vector3 V(double x, double y, double z) { return ToProto(Eigen::Vector3d(x, y, z)); }

v1::CampaignSpec Good() {
  v1::CampaignSpec spec;
  v1::PinholeCamera* pinhole = spec.mutable_sensor()->mutable_pinhole();
  pinhole->set_width(64);
  pinhole->set_height(48);
  pinhole->set_horizontal_fov_deg(60);
  pinhole->set_near(0.05);
  pinhole->set_far(3);
  v1::Viewpoint* viewpoint = spec.add_viewpoints();
  *viewpoint->mutable_position() = V(0.4, 0, 0.3);
  *viewpoint->mutable_target() = V(0, 0, 0);
  spec.set_rotations(3);
  spec.set_rotation_step_deg(120);
  return spec;
}

struct BadSpec {
  const char* name;
  std::function<void(v1::CampaignSpec*)> edit;
  // The start of the message, naming the field.
  const char* field;
};

void PrintTo(const BadSpec& bad, std::ostream* os) { *os << bad.name; }

class CampaignValidateTest : public ::testing::Test {
 protected:
  std::string Scene(bool table) { return world_.EmptyScene(table); }
  std::string Mount(const std::string& scene_id) { return world_.Mount("panda", scene_id); }

  StatusOr<service::CampaignPlan> DryRun(const v1::CampaignSpec& spec) { return ValidateCampaign(spec, world_.context(), true); }

  service::testing::ServiceWorld world_;
};

TEST_F(CampaignValidateTest, DryRunAcceptsAGoodSpecWithoutIds) {
  const auto plan = DryRun(Good());
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->steps_total(), 3u);
}

TEST_F(CampaignValidateTest, RealStartStillNeedsTheScene) {
  const auto plan = ValidateCampaign(Good(), world_.context());
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(plan.status().message(), "spec.scene_id: required");
}

TEST_F(CampaignValidateTest, DryRunChecksTheIdsItIsGiven) {
  v1::CampaignSpec spec = Good();
  spec.set_scene_id("scn_0000000000000000");
  EXPECT_EQ(DryRun(spec).status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(DryRun(spec).status().message().starts_with("spec.scene_id:")) << DryRun(spec).status().message();

  // A scene without a table cannot turn: known once the scene is named.
  spec.set_scene_id(Scene(false));
  EXPECT_EQ(DryRun(spec).status().code(), StatusCode::kFailedPrecondition);
  EXPECT_TRUE(DryRun(spec).status().message().starts_with("spec.rotations:")) << DryRun(spec).status().message();

  spec.set_scene_id(Scene(true));
  EXPECT_TRUE(DryRun(spec).ok()) << DryRun(spec).status().ToString();
  spec.set_mount_id("mnt_0000000000000000");
  EXPECT_EQ(DryRun(spec).status().code(), StatusCode::kNotFound);

  spec.set_scene_id("");
  EXPECT_EQ(DryRun(spec).status().message(), "spec.scene_id: required");
}

TEST_F(CampaignValidateTest, NegativeStepTurnsTheTableTheOtherWay) {
  v1::CampaignSpec spec = Good();
  spec.set_rotation_step_deg(-30);
  const auto plan = DryRun(spec);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_DOUBLE_EQ(plan->AngleDeg(2), -60.0);
}

class BadCampaignSpec : public CampaignValidateTest, public ::testing::WithParamInterface<BadSpec> {};

// The dry run and a real start with a scene and a mount give the very same verdict.
TEST_P(BadCampaignSpec, DryRunGivesTheVerdictOfARealStart) {
  v1::CampaignSpec spec = Good();
  GetParam().edit(&spec);
  const auto dry = DryRun(spec);
  ASSERT_FALSE(dry.ok());
  EXPECT_TRUE(dry.status().message().starts_with(GetParam().field)) << dry.status().message();

  spec.set_scene_id(Scene(true));
  spec.set_mount_id(Mount(spec.scene_id()));
  const auto real = ValidateCampaign(spec, world_.context());
  ASSERT_FALSE(real.ok());
  EXPECT_EQ(real.status().code(), dry.status().code());
  EXPECT_EQ(real.status().message(), dry.status().message());
}

INSTANTIATE_TEST_SUITE_P(
    CampaignValidate, BadCampaignSpec,
    testing::Values(
        BadSpec{"rotations_above_3600", [](v1::CampaignSpec* s) { s->set_rotations(3601); }, "spec.rotations:"},
        BadSpec{"width_0", [](v1::CampaignSpec* s) { s->mutable_sensor()->mutable_pinhole()->set_width(0); },
                "spec.sensor.pinhole.width:"},
        BadSpec{"width_100000",
                [](v1::CampaignSpec* s) { s->mutable_sensor()->mutable_pinhole()->set_width(100000); },
                "spec.sensor.pinhole"},
        BadSpec{"step_0", [](v1::CampaignSpec* s) { s->set_rotation_step_deg(0); }, "spec.rotation_step_deg:"},
        BadSpec{"step_1e300", [](v1::CampaignSpec* s) { s->set_rotation_step_deg(1e300); },
                "spec.rotation_step_deg:"},
        BadSpec{"viewpoint_beyond_10_km",
                [](v1::CampaignSpec* s) { *s->mutable_viewpoints(0)->mutable_position() = V(2e4, 0, 0.3); },
                "spec.viewpoints[0].position:"},
        BadSpec{"target_at_position",
                [](v1::CampaignSpec* s) { *s->mutable_viewpoints(0)->mutable_target() = V(0.4, 0, 0.3); },
                "spec.viewpoints[0].target:"},
        BadSpec{"up_along_view",
                [](v1::CampaignSpec* s) { *s->mutable_viewpoints(0)->mutable_up() = V(-0.4, 0, -0.3); },
                "spec.viewpoints[0].up:"},
        BadSpec{"no_viewpoints", [](v1::CampaignSpec* s) { s->clear_viewpoints(); }, "spec.viewpoints:"},
        BadSpec{"negative_noise", [](v1::CampaignSpec* s) { s->mutable_noise()->set_sigma_a(-1); }, "spec.noise"},
        BadSpec{"unknown_preset", [](v1::CampaignSpec* s) { s->mutable_sensor()->set_preset("nope"); },
                "spec.sensor.preset:"},
        BadSpec{"unknown_frame", [](v1::CampaignSpec* s) { s->set_frame(static_cast<v1::Frame>(42)); },
                "spec.frame:"},
        BadSpec{"light_exposure_nan",
                [](v1::CampaignSpec* s) { s->mutable_returned_light()->set_exposure_s(std::nan("")); },
                "spec.returned_light.exposure_s:"},
        BadSpec{"light_half_angle_270",
                [](v1::CampaignSpec* s) { s->mutable_returned_light()->set_emitter_half_angle_deg(270); },
                "spec.returned_light.emitter_half_angle_deg:"}),
    [](const testing::TestParamInfo<BadSpec>& info) { return info.param.name; });

}  // namespace
}  // namespace vscan::api
