// Sampled dataset views: straight down by default, within the plan's cone and distances otherwise,
// spread over the cone as a uniform cap is, always aimed at the bin floor's centre.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "service/datasets/format/view_poses.h"

namespace vscan::service::dataset {
namespace {

DatasetPlan PlanWith(const DatasetViews& views) {
  DatasetPlan plan;
  plan.camera_height_m = 0.75;
  plan.views = views;
  return plan;
}

double TiltDeg(const Pose3& bin_from_camera) {
  return std::acos(-bin_from_camera.linear()(2, 2)) * 180.0 / std::numbers::pi;
}

TEST(ViewPoses, TheDefaultViewIsExactlyStraightDownFromTheCameraHeight) {
  const DatasetPlan plan = PlanWith({});
  for (uint32_t view = 0; view < 5; ++view) {
    const Pose3 pose = SampleViewPose(plan, ViewPoseSeed(42, view));
    Eigen::Matrix3d down;
    down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    EXPECT_EQ(pose.linear(), down);
    EXPECT_EQ(pose.translation(), Eigen::Vector3d(0, 0, 0.75));
  }
}

TEST(ViewPoses, SampledViewsStayInTheConeAndRangeAndLookAtTheFloorCentre) {
  const DatasetPlan plan = PlanWith({8, 40.0, 0.5, 0.9});
  double cos_tilt_sum = 0, max_tilt = 0, min_distance = 1e9, max_distance = 0;
  int east = 0;
  const int samples = 4000;
  for (int i = 0; i < samples; ++i) {
    const Pose3 pose = SampleViewPose(plan, ViewPoseSeed(7, uint32_t(i)));
    const Eigen::Matrix3d r = pose.linear();
    EXPECT_NEAR((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    const double distance = pose.translation().norm();
    // The optical axis runs from the camera through the origin.
    EXPECT_LT((r.col(2) + pose.translation() / distance).norm(), 1e-12);
    // Image x is the bin's x on the image plane: no part of it along x cross the axis.
    EXPECT_NEAR(r.col(0).dot(Eigen::Vector3d::UnitX().cross(r.col(2))), 0, 1e-12);
    EXPECT_GT(r(0, 0), 0);
    const double tilt = TiltDeg(pose);
    EXPECT_LE(tilt, 40.0 + 1e-9);
    max_tilt = std::max(max_tilt, tilt);
    cos_tilt_sum += -r(2, 2);
    min_distance = std::min(min_distance, distance);
    max_distance = std::max(max_distance, distance);
    east += pose.translation().x() > 0;
  }
  // Uniform over the cap: cos(tilt) uniform in [cos 40, 1], mean (1 + cos 40) / 2.
  const double expected_mean = (1 + std::cos(40.0 * std::numbers::pi / 180.0)) / 2;
  const double sd_of_mean = (1 - std::cos(40.0 * std::numbers::pi / 180.0)) / std::sqrt(12.0 * samples);
  EXPECT_NEAR(cos_tilt_sum / samples, expected_mean, 5 * sd_of_mean);
  EXPECT_GT(max_tilt, 38.0);
  EXPECT_GE(min_distance, 0.5);
  EXPECT_LE(max_distance, 0.9);
  EXPECT_LT(min_distance, 0.52);
  EXPECT_GT(max_distance, 0.88);
  EXPECT_NEAR(east, samples / 2, 5 * std::sqrt(samples / 4.0));
}

TEST(ViewPoses, ViewsAreDeterministicAndDistinct) {
  const DatasetPlan plan = PlanWith({3, 25.0, 0.6, 0.8});
  EXPECT_TRUE(SampleViewPose(plan, ViewPoseSeed(9, 1)).isApprox(SampleViewPose(plan, ViewPoseSeed(9, 1)), 0));
  EXPECT_FALSE(SampleViewPose(plan, ViewPoseSeed(9, 1)).isApprox(SampleViewPose(plan, ViewPoseSeed(9, 2))));
  EXPECT_NE(ViewPoseSeed(9, 1), ViewPoseSeed(10, 1));
}

}  // namespace
}  // namespace vscan::service::dataset
