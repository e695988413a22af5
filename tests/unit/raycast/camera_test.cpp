#include "sensor/camera.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

namespace vscan::sensor {
namespace {

constexpr uint64_t kMaxRays = 10'000'000;

PinholeCamera Valid() { return CameraFromFov(640, 480, 60.0, 0.1, 5.0); }

TEST(CameraTest, FromFovPutsThePrincipalPointAtTheCentre) {
  const PinholeCamera c = CameraFromFov(640, 480, 90.0, 0.1, 5.0);
  EXPECT_NEAR(c.fx, 320.0, 1e-9);
  EXPECT_EQ(c.fx, c.fy);
  EXPECT_EQ(c.cx, 320.0);
  EXPECT_EQ(c.cy, 240.0);
  EXPECT_EQ(c.near, 0.1);
  EXPECT_EQ(c.far, 5.0);
  // The outer edge of the image sits at the half field of view.
  const double half_fov = std::atan((c.width - c.cx) / c.fx) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(half_fov, 45.0, 1e-9);
}

TEST(CameraTest, RayThroughPixelHitsThePixelCentreAtUnitDepth) {
  const PinholeCamera c = CameraFromFov(4, 2, 90.0, 0.1, 5.0);
  const Eigen::Vector3f d = c.RayThroughPixel(3, 1);
  EXPECT_FLOAT_EQ(d.x(), (3.5f - 2.0f) / 2.0f);
  EXPECT_FLOAT_EQ(d.y(), (1.5f - 1.0f) / 2.0f);
  EXPECT_FLOAT_EQ(d.z(), 1.0f);
}

TEST(CameraTest, AcceptsAValidCamera) { EXPECT_TRUE(ValidateCamera(Valid(), "sensor.pinhole", kMaxRays).ok()); }

TEST(CameraTest, RejectsZeroWidthAndHeight) {
  PinholeCamera c = Valid();
  c.width = 0;
  Status s = ValidateCamera(c, "sensor.pinhole", kMaxRays);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind("sensor.pinhole.width", 0), 0u) << s.message();
  c = Valid();
  c.height = 0;
  s = ValidateCamera(c, "sensor.pinhole", kMaxRays);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind("sensor.pinhole.height", 0), 0u) << s.message();
}

TEST(CameraTest, AbsurdResolutionIsResourceExhausted) {
  PinholeCamera c = Valid();
  c.width = c.height = 16384;  // 268M rays, over the 10M budget
  Status s = ValidateCamera(c, "sensor.pinhole", kMaxRays);
  EXPECT_EQ(s.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(s.message().find("sensor.pinhole.width"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("sensor.pinhole.height"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("10000000"), std::string::npos) << s.message();

  c = Valid();
  c.width = 20000;  // over the per-side limit even with a huge budget
  s = ValidateCamera(c, "sensor.pinhole", std::numeric_limits<uint64_t>::max());
  EXPECT_EQ(s.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(s.message().rfind("sensor.pinhole.width", 0), 0u) << s.message();
  EXPECT_NE(s.message().find("16384"), std::string::npos) << s.message();
}

TEST(CameraTest, RejectsNearNotBelowFar) {
  PinholeCamera c = Valid();
  c.near = c.far = 2.0;
  Status s = ValidateCamera(c, "sensor.pinhole", kMaxRays);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "sensor.pinhole.near must be less than far");
  c.near = 3.0;
  EXPECT_EQ(ValidateCamera(c, "sensor.pinhole", kMaxRays).code(), StatusCode::kInvalidArgument);
}

TEST(CameraTest, RejectsBadIntrinsicsAndRange) {
  const auto code_of = [](auto mutate) {
    PinholeCamera c = Valid();
    mutate(c);
    return ValidateCamera(c, "cam", kMaxRays);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(code_of([](PinholeCamera& c) { c.fx = 0; }).message().rfind("cam.fx", 0), 0u);
  EXPECT_EQ(code_of([&](PinholeCamera& c) { c.fy = nan; }).message().rfind("cam.fy", 0), 0u);
  EXPECT_EQ(code_of([&](PinholeCamera& c) { c.cx = inf; }).message().rfind("cam.cx", 0), 0u);
  EXPECT_EQ(code_of([&](PinholeCamera& c) { c.cy = nan; }).message().rfind("cam.cy", 0), 0u);
  EXPECT_EQ(code_of([](PinholeCamera& c) { c.near = 0; }).message().rfind("cam.near", 0), 0u);
  EXPECT_EQ(code_of([&](PinholeCamera& c) { c.far = inf; }).message().rfind("cam.far", 0), 0u);
  EXPECT_EQ(code_of([](PinholeCamera& c) { c.fx = -1; }).code(), StatusCode::kInvalidArgument);
}

TEST(CameraTest, RejectsBadLighting) {
  const auto check = [](auto mutate) {
    PinholeCamera c = Valid();
    mutate(c.lighting);
    const Status s = ValidateCamera(c, "cam", kMaxRays);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(s.message().rfind("cam.lighting", 0), 0u) << s.message();
  };
  check([](Lighting& l) { l.power = -1; });
  check([](Lighting& l) { l.linear = -0.1; });
  check([](Lighting& l) { l.quadratic = std::numeric_limits<double>::quiet_NaN(); });
  check([](Lighting& l) { l.constant = l.linear = l.quadratic = 0; });
}

TEST(CameraTest, IntensityFollowsTheAttenuationFormula) {
  const Lighting l{2.0, 0.5, 0.25, 0.125};
  EXPECT_DOUBLE_EQ(Intensity(l, 2.0, 0.5), 2.0 * 0.5 / (0.5 + 0.25 * 2.0 + 0.125 * 4.0));
  EXPECT_DOUBLE_EQ(Intensity(l, 0.0, 1.0), 4.0);
  EXPECT_EQ(Intensity(l, 1.0, -0.3), 0.0);  // light arriving from behind the surface
}

}  // namespace
}  // namespace vscan::sensor
