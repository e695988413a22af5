#include <gtest/gtest.h>

#include "picking_session_fixture.h"

namespace vscan::service {
namespace {

TEST_F(PickingSessionTest, WithTheTruePosesTheArmEmptiesTheBinAndTheSceneFollows) {
  plan_.perception = Perception::kTruth;
  std::vector<size_t> scene_parts;
  PickingObserver observer;
  observer.stepped = [&](const picking::PickStep&, const std::vector<physics::PlacedPart>&) {
    scene_parts.push_back(PartsInScene());
  };
  const auto result = RunPickingSession(world_.context(), plan_, nullptr, observer);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->end, "empty");
  EXPECT_EQ(result->picked + result->fell_out, 6u);
  for (const picking::PickStep& step : result->steps) EXPECT_EQ(step.outcome, picking::StepOutcome::kPicked) << step.detail;
  // Each step's writes reached the scene before the next step.
  ASSERT_EQ(scene_parts.size(), result->steps.size());
  for (size_t i = 0; i < scene_parts.size(); ++i) EXPECT_EQ(scene_parts[i], result->steps[i].parts_before - 1);
  EXPECT_EQ(PartsInScene(), 0u);
}

TEST_F(PickingSessionTest, WithTheBaselineLocalizerTheArmPicksFromItsScans) {
  plan_.session.max_steps = 3;
  std::vector<size_t> scan_points, estimates;
  PickingObserver observer;
  observer.perceived = [&](const StepView& view) {
    scan_points.push_back(view.scan.size());
    estimates.push_back(view.estimates.size());
  };
  const auto result = RunPickingSession(world_.context(), plan_, nullptr, observer);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  ASSERT_FALSE(result->steps.empty());
  ASSERT_EQ(scan_points.size(), result->steps.size());
  for (size_t i = 0; i < scan_points.size(); ++i) {
    EXPECT_GT(scan_points[i], 10000u);
    EXPECT_GT(estimates[i], 0u);
  }
  EXPECT_GE(result->picked, 2u) << result->end;
  EXPECT_EQ(PartsInScene(), 6u - result->picked - result->fell_out);
}

TEST_F(PickingSessionTest, AMountInAnotherSceneIsRefused) {
  plan_.mount_id = world_.Mount("ur5", world_.EmptyScene(), Placed(0, 0, 0.2));
  const auto result = RunPickingSession(world_.context(), plan_, nullptr);
  EXPECT_EQ(result.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(result.status().message().find("mount_id"), std::string::npos);
  EXPECT_EQ(PartsInScene(), 6u);
}

}  // namespace
}  // namespace vscan::service
