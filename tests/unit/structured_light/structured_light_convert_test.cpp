// StructuredLightScanner messages <-> the engine model: round trips and field-named rejections.

#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "api/scan/structured_light_convert.h"
#include "sensor/presets.h"

namespace vscan::api {
namespace {

sensor::PinholeCamera Camera() { return sensor::CameraFromFov(640, 480, 50.0, 0.3, 2.0); }

v1::StructuredLightScanner ValidMessage() {
  v1::StructuredLightScanner m;
  m.mutable_camera()->set_width(640);
  m.mutable_camera()->set_height(480);
  m.mutable_camera()->set_horizontal_fov_deg(50.0);
  m.mutable_projector_offset()->set_x(0.12);
  m.set_projector_horizontal_fov_deg(45);
  m.set_projector_vertical_fov_deg(35);
  m.set_disparity_step_px(0.125);
  m.set_convergence_distance(0.7);
  return m;
}

void ExpectConvertRejected(const v1::StructuredLightScanner& m, const std::string& field,
                           const service::Limits& limits = {}) {
  const auto sl = StructuredLightFromProto(m, Camera(), limits);
  ASSERT_FALSE(sl.ok()) << field;
  EXPECT_TRUE(sl.status().message().starts_with(field)) << sl.status().message();
}

TEST(StructuredLightFromProto, ReadsEveryField) {
  const auto sl = StructuredLightFromProto(ValidMessage(), Camera(), service::Limits{});
  ASSERT_TRUE(sl.ok()) << sl.status().ToString();
  EXPECT_EQ(sl->camera.width, 640u);
  EXPECT_TRUE(sl->projector_offset.isApprox(Eigen::Vector3d(0.12, 0, 0)));
  EXPECT_EQ(sl->projector_hfov_deg, 45);
  EXPECT_EQ(sl->projector_vfov_deg, 35);
  EXPECT_EQ(sl->disparity_step_px, 0.125);
  EXPECT_EQ(sl->convergence_distance, 0.7);
}

TEST(StructuredLightFromProto, RejectsBadFieldsByName) {
  v1::StructuredLightScanner m = ValidMessage();
  m.clear_camera();
  ExpectConvertRejected(m, "sensor.structured_light.camera: required");
  m = ValidMessage();
  m.clear_projector_offset();
  ExpectConvertRejected(m, "sensor.structured_light.projector_offset: required");
  m = ValidMessage();
  m.mutable_projector_offset()->set_x(0);
  ExpectConvertRejected(m, "sensor.structured_light.projector_offset:");
  m = ValidMessage();
  m.mutable_projector_offset()->set_y(std::numeric_limits<double>::infinity());
  ExpectConvertRejected(m, "sensor.structured_light.projector_offset:");
  m = ValidMessage();
  m.set_projector_horizontal_fov_deg(200);
  ExpectConvertRejected(m, "sensor.structured_light.projector_horizontal_fov_deg:");
  m = ValidMessage();
  m.set_projector_vertical_fov_deg(std::numeric_limits<double>::quiet_NaN());
  ExpectConvertRejected(m, "sensor.structured_light.projector_vertical_fov_deg:");
  m = ValidMessage();
  m.set_disparity_step_px(-1);
  ExpectConvertRejected(m, "sensor.structured_light.disparity_step_px:");
  m = ValidMessage();
  m.set_convergence_distance(-0.5);
  ExpectConvertRejected(m, "sensor.structured_light.convergence_distance:");
  service::Limits small;
  small.max_rays_per_scan = 1000;
  const auto too_many = StructuredLightFromProto(ValidMessage(), Camera(), small);
  ASSERT_FALSE(too_many.ok());
  EXPECT_EQ(too_many.status().code(), StatusCode::kResourceExhausted);
  EXPECT_TRUE(too_many.status().message().starts_with("sensor.structured_light.camera.width")) << too_many.status().message();
}

TEST(StructuredLightToProto, PresetsRoundTrip) {
  size_t structured = 0;
  for (const sensor::SensorPreset& preset : sensor::SensorPresets()) {
    if (!preset.structured_light) continue;
    ++structured;
    const sensor::StructuredLight& original = *preset.structured_light;
    v1::StructuredLightScanner m;
    ToProto(original, &m);
    ASSERT_TRUE(m.camera().has_intrinsics());
    EXPECT_EQ(m.camera().intrinsics().fx(), original.camera.fx);
    EXPECT_EQ(m.camera().near(), original.camera.near);
    const auto back = StructuredLightFromProto(m, original.camera, service::Limits{});
    ASSERT_TRUE(back.ok()) << preset.name << ": " << back.status().ToString();
    EXPECT_EQ(back->projector_offset, original.projector_offset);
    EXPECT_EQ(back->projector_hfov_deg, original.projector_hfov_deg);
    EXPECT_EQ(back->projector_vfov_deg, original.projector_vfov_deg);
    EXPECT_EQ(back->disparity_step_px, original.disparity_step_px);
    EXPECT_EQ(back->convergence_distance, original.convergence_distance);
  }
  EXPECT_EQ(structured, 3u);
}

}  // namespace
}  // namespace vscan::api
