// The emitter's light through a whole measured scan: each pixel's electrons against the closed
// form on analytic scenes, the dark and saturated verdicts where the numbers put them, and the
// depth noise that widens as the signal falls.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "capture/returned_light.h"
#include "sensor/structured_light.h"
#include "capture_scenes.h"

namespace vscan::capture {
namespace {

using test::Build;
using test::Code;
using test::Measure;

// A Lambertian reflector: no specular lobe (F0 = 0 makes Schlick's Fresnel zero), so the BRDF is
// albedo / pi.
sensor::Material Lambertian(double albedo) { return {albedo, 0.0, 1.0, 0.0}; }

MeasurementSpec LitSpec(const sensor::Material& plane, double gain_e, double intensity_w_per_sr) {
  MeasurementSpec spec = test::TruthSpec();
  ReturnedLightSpec light;
  light.emitter.radiant_intensity_w_per_sr = intensity_w_per_sr;
  light.pixel.gain_e = gain_e;
  light.pixel.full_well_e = 1e5;
  light.pixel.read_noise_e = 5;
  light.pixel.min_snr = 5;
  light.materials.assign(test::kPlaneId + 1, light.default_material);
  light.materials[test::kPlaneId] = plane;
  spec.returned_light = light;
  spec.include_rejected = true;
  spec.seed = 11;
  return spec;
}

// Electrons the closed form gives a pixel looking at point p on the plane z = const facing the
// camera, lit from the camera: (albedo / pi) I cos(theta) / r^2, times cos^4 of the ray and the gain;
// cos(theta) = z / r for both the light and the ray.
double ClosedFormElectrons(const Eigen::Vector3d& p, double albedo, double intensity, double gain) {
  const double r = p.norm(), cosine = p.z() / r;
  return gain * albedo / std::numbers::pi * intensity * cosine / (r * r) * std::pow(cosine, 4);
}

TEST(ReturnedLight, ALambertianPlanesElectronsFollowAlbedoCosineOverRangeSquared) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(160, 120, 60);
  const double albedo = 0.6, intensity = 0.5, gain = 4e4;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, LitSpec(Lambertian(albedo), gain, intensity), &stats);
  ASSERT_EQ(cloud.size(), 160u * 120u);
  // Each pixel's measured electrons against its closed form, in units of its own noise: a standard
  // normal over the 19 200 pixels.
  double sum = 0, sum2 = 0, lowest = 1e30, highest = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(cloud.statuses[i], Code(PointStatus::kMeasured)) << i;
    const double expected = ClosedFormElectrons(cloud.clean_positions[i].cast<double>(), albedo, intensity, gain);
    const double z = (cloud.intensities[i] - expected) / std::sqrt(expected + 25.0);
    sum += z;
    sum2 += z * z;
    lowest = std::min(lowest, expected);
    highest = std::max(highest, expected);
  }
  const double n = static_cast<double>(cloud.size()), mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sd, 1.0, 0.03);
  // The corners get a third of the centre's light (cos^7 at 36 degrees): the test spans that range.
  EXPECT_LT(lowest, 0.4 * highest);
  EXPECT_EQ(stats.rejected_dark + stats.rejected_saturated, 0u);
}

// A uniform ambient light adds E albedo / pi of radiance to every pixel (no cos / r^2 of its own),
// with its shot noise; where the emitter's share then stands below 5 sigmas of the whole pixel's
// noise the pixel is dark, though its signal alone would decode.
TEST(ReturnedLight, AmbientLightAddsItsElectronsAndNoiseButDoesNotDecode) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(160, 120, 60);
  const double albedo = 0.6, intensity = 0.05, gain = 4e4, ambient = 0.3;
  MeasurementSpec spec = LitSpec(Lambertian(albedo), gain, intensity);
  const PointCloud unlit = Measure(*scene, camera, spec, nullptr);
  spec.returned_light->ambient_irradiance_w_per_m2 = ambient;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  ASSERT_EQ(cloud.size(), unlit.size());
  double sum = 0, sum2 = 0;
  size_t dark = 0, expected_dark = 0, unlit_dark = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.clean_positions[i].cast<double>();
    const double direct = ClosedFormElectrons(p, albedo, intensity, gain);
    const double cos4 = std::pow(p.z() / p.norm(), 4);
    const double ambient_e = gain * albedo / std::numbers::pi * ambient * cos4;
    const double total = direct + ambient_e, noise = std::sqrt(total + 25.0);
    const double z = (cloud.intensities[i] - total) / noise;
    sum += z;
    sum2 += z * z;
    // Stay clear of the bar by a tenth of a sigma, where rounding could go either way.
    if (std::abs(direct / noise - 5.0) < 0.1) continue;
    expected_dark += direct / noise < 5.0;
    dark += cloud.statuses[i] == Code(PointStatus::kRejectedDark);
    unlit_dark += unlit.statuses[i] == Code(PointStatus::kRejectedDark);
    ASSERT_EQ(cloud.statuses[i] == Code(PointStatus::kRejectedDark), direct / noise < 5.0) << i;
  }
  const double n = static_cast<double>(cloud.size()), mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sd, 1.0, 0.03);
  // The scene is chosen so that the ambient light darkens part of the image, not all of it.
  EXPECT_GT(expected_dark, cloud.size() / 10);
  EXPECT_LT(expected_dark, cloud.size() * 9 / 10);
  EXPECT_EQ(dark, expected_dark);
  EXPECT_EQ(unlit_dark, 0u);
  // The depth noise's factor follows SNR = active / sqrt(active + ambient + read^2).
  ReturnedLightSpec light = *spec.returned_light;
  light.reference_e = 1000;
  sensor::PixelSignal signal;
  signal.expected_e = 4000;
  signal.ambient_e = 3000;
  const double reference_snr = 1000 / std::sqrt(1000 + 25.0), snr = 1000 / std::sqrt(4000 + 25.0);
  EXPECT_NEAR(SignalSigmaFactor(light, signal), reference_snr / snr, 1e-12);
}

// Half the plane black anodised, half white: at a power where the closed form puts the black half
// below 5 sigmas of its noise and the white half far above, the black half is dark and nothing else.
TEST(ReturnedLight, ADarkMaterialIsRejectedAsDarkWhereTheSignalIsBelowTheSnr) {
  const auto scene = Build({test::Box({-2, -2, 0.9}, {0, 2, 0.95}), test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(160, 120, 40);
  const double gain = 2000, intensity = 0.5;
  MeasurementSpec spec = LitSpec(Lambertian(0.9), gain, intensity);
  spec.returned_light->materials.assign(test::kBoxId + 1, spec.returned_light->default_material);
  spec.returned_light->materials[test::kPlaneId] = Lambertian(0.9);
  spec.returned_light->materials[test::kBoxId] = Lambertian(0.03);
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  size_t dark = 0, measured = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double albedo = cloud.instance_ids[i] == test::kBoxId ? 0.03 : 0.9;
    const double expected = ClosedFormElectrons(cloud.clean_positions[i].cast<double>(), albedo, intensity, gain);
    const double snr = expected / std::sqrt(expected + 25.0);
    if (cloud.instance_ids[i] == test::kBoxId) {
      ASSERT_LT(snr, 4.0) << i;  // the set-up: every black pixel well under the bar
      EXPECT_EQ(cloud.statuses[i], Code(PointStatus::kRejectedDark)) << i;
      dark += cloud.statuses[i] == Code(PointStatus::kRejectedDark);
    } else {
      ASSERT_GT(snr, 6.0) << i;
      EXPECT_EQ(cloud.statuses[i], Code(PointStatus::kMeasured)) << i;
      measured += cloud.statuses[i] == Code(PointStatus::kMeasured);
    }
  }
  EXPECT_GT(dark, 4000u);
  EXPECT_GT(measured, 4000u);
  EXPECT_EQ(stats.rejected_dark, dark);
  EXPECT_EQ(stats.rejected_saturated, 0u);
}

// A structured-light scanner's emitter is its projector: where a box shadows the plane from the
// projector, the plane's pixels get none of its light (their electrons are the read noise's), and
// the lit pixels beside them follow the closed form from the projector's position.
TEST(ReturnedLight, AProjectorsShadowGetsNoneOfItsLight) {
  const auto scene = Build({test::Box({-0.05, -0.05, 0.7}, {0.05, 0.05, 0.75}), test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(160, 120, 40);
  MeasurementSpec spec = LitSpec(Lambertian(0.9), 4e4, 0.5);
  sensor::StructuredLight projector;
  projector.camera = camera;
  projector.projector_offset = Eigen::Vector3d(0.2, 0, 0);
  projector.projector_hfov_deg = projector.projector_vfov_deg = 120;
  spec.structured_light = projector;
  spec.returned_light->emitter.position = projector.projector_offset;
  const PointCloud cloud = Measure(*scene, camera, spec);
  size_t shadowed = 0, lit = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.instance_ids[i] != test::kPlaneId) continue;
    if (cloud.statuses[i] == Code(PointStatus::kRejectedShadowed)) {
      ++shadowed;
      EXPECT_LT(cloud.intensities[i], 5 * 5.0) << i;  // within 5 sigmas of the read noise, 5 e
    } else if (cloud.statuses[i] == Code(PointStatus::kMeasured)) {
      ++lit;
      const Eigen::Vector3d p = cloud.clean_positions[i].cast<double>();
      const Eigen::Vector3d to_projector = projector.projector_offset - p;
      const double r = p.norm(), d = to_projector.norm();
      const double expected = 4e4 * 0.9 / std::numbers::pi * 0.5 * (-to_projector.z() / d) / (d * d) *
                              std::pow(p.z() / r, 4);
      EXPECT_NEAR(cloud.intensities[i], expected, 6 * std::sqrt(expected + 25.0)) << i;
    }
  }
  EXPECT_GT(shadowed, 200u);
  EXPECT_GT(lit, 5000u);
}

// A polished metal plane facing the camera, lit from the camera: the mirror sends the light back
// only near the axis, where it fills the well; off the axis the lobe falls off and the pixels read.
TEST(ReturnedLight, AMirrorLikePlaneSaturatesOnlyNearTheSpecularDirection) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(161, 121, 60);
  MeasurementSpec spec = LitSpec({0.9, 1.0, 0.15, 0.04}, 1e4, 1.0);
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  double nearest_unsaturated = 1e9, farthest_saturated = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = cloud.clean_positions[i];
    const double off_axis = std::atan2(std::hypot(p.x(), p.y()), p.z());
    if (cloud.statuses[i] == Code(PointStatus::kRejectedSaturated)) {
      farthest_saturated = std::max(farthest_saturated, off_axis);
    } else {
      nearest_unsaturated = std::min(nearest_unsaturated, off_axis);
    }
  }
  EXPECT_GT(stats.rejected_saturated, 10u);
  EXPECT_LT(stats.rejected_saturated, cloud.size() / 4);
  // Saturation is a disc about the axis: every saturated pixel lies nearer the axis than any other.
  EXPECT_LE(farthest_saturated, nearest_unsaturated + 0.01);
}

// With reference_e the depth noise's sigma holds at that signal and widens as SNR(ref) / SNR(signal):
// the depth errors over the plane, each divided by its predicted sigma, are a standard normal.
TEST(ReturnedLight, DepthNoiseWidensAsTheSignalFalls) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(160, 120, 60);
  const double albedo = 0.2, intensity = 0.5, gain = 2e4, sigma = 0.001;
  MeasurementSpec spec = LitSpec(Lambertian(albedo), gain, intensity);
  spec.noise.sigma_a = sigma;
  spec.noise.along_ray = true;
  spec.returned_light->reference_e = 1e4;
  const PointCloud cloud = Measure(*scene, camera, spec);
  const auto snr = [](double e) { return e / std::sqrt(e + 25.0); };
  double sum2 = 0, widest = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(cloud.statuses[i], Code(PointStatus::kMeasured));
    const double expected = ClosedFormElectrons(cloud.clean_positions[i].cast<double>(), albedo, intensity, gain);
    const double predicted = sigma * snr(1e4) / snr(expected);
    const double error = (cloud.positions[i] - cloud.clean_positions[i]).norm();
    sum2 += error * error / (predicted * predicted);
    widest = std::max(widest, predicted);
  }
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(cloud.size())), 1.0, 0.03);
  EXPECT_GT(widest, 3 * sigma);  // the signal is well below the reference: the widening is tested
}

TEST(ReturnedLight, AnAmbientLightOutOfRangeIsRefusedNamingIt) {
  ReturnedLightSpec light;
  for (const double bad : {-1.0, 2e4, std::numeric_limits<double>::quiet_NaN()}) {
    light.ambient_irradiance_w_per_m2 = bad;
    const Status status = ValidateReturnedLight(light, "returned_light");
    EXPECT_EQ(status.field(), "returned_light.ambient_irradiance_w_per_m2") << bad;
  }
}

TEST(ReturnedLight, TheSameSeedGivesTheSameBitsAndBadValuesNameTheirField) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(64, 48, 60);
  const MeasurementSpec spec = LitSpec(Lambertian(0.5), 4e4, 0.5);
  const PointCloud a = Measure(*scene, camera, spec), b = Measure(*scene, camera, spec);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.intensities, b.intensities);
  ReturnedLightSpec bad = *spec.returned_light;
  bad.materials[test::kPlaneId].roughness = std::nan("");
  EXPECT_EQ(ValidateReturnedLight(bad, "light").message().rfind("light.materials[1].roughness", 0), 0u);
  bad = *spec.returned_light;
  bad.reference_e = -1;
  EXPECT_EQ(ValidateReturnedLight(bad, "light").message().rfind("light.reference_e", 0), 0u);
  bad = *spec.returned_light;
  bad.pixel.full_well_e = 1e19 * 0;
  EXPECT_FALSE(ValidateReturnedLight(bad, "light").ok());
}

}  // namespace
}  // namespace vscan::capture

namespace vscan::capture {
namespace {

// A direct radiance evaluated elsewhere (the raster shaders) replaces the per-point DirectRadiance:
// the CPU's own values (rounded to float) give the same mean electrons, doubled ones double them, a
// hidden emitter still gives none, and a radiance array of the wrong length is refused.
TEST(ReturnedLight, AGivenDirectRadianceReplacesTheCpuEvaluation) {
  const auto scene = test::Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(80, 60, 60);
  const MeasurementSpec spec = LitSpec(Lambertian(0.6), 4e4, 0.5);
  raycast::ScanOptions options;
  options.fields = CleanFieldsFor(spec);
  options.frame = raycast::ScanFrame::kSensor;
  auto clean = raycast::Scan(*scene, camera, Pose3::Identity(), options);
  ASSERT_TRUE(clean.ok()) << clean.status().ToString();
  ASSERT_EQ(clean->size(), 80u * 60u);
  const ReturnedLightSpec& light = *spec.returned_light;
  std::vector<float> cpu(clean->size()), doubled(clean->size());
  for (size_t i = 0; i < clean->size(); ++i) {
    Eigen::Vector3d n = clean->normals[i].cast<double>();
    const Eigen::Vector3d p = clean->positions[i].cast<double>();
    if (n.dot(p) > 0) n = -n;
    const double radiance =
        sensor::DirectRadiance(light.materials[test::kPlaneId], p, n, light.emitter, Eigen::Vector3d::Zero());
    cpu[i] = static_cast<float>(radiance);
    doubled[i] = static_cast<float>(2 * radiance);
  }
  const auto own = ReturnedSignals(*clean, light, 3);
  const auto given = ReturnedSignals(*clean, light, 3, {}, {}, cpu);
  const auto twice = ReturnedSignals(*clean, light, 3, {}, {}, doubled);
  // A projector's shadow (emitter_hidden) still takes the emitter's light away.
  const std::vector<uint8_t> hidden(clean->size(), 1);
  const auto shadowed = ReturnedSignals(*clean, light, 3, {}, hidden, cpu);
  for (size_t i = 0; i < own.size(); ++i) {
    EXPECT_EQ(shadowed[i].expected_e, 0.0) << i;
    // The float rounding of the given radiance is all that differs.
    EXPECT_NEAR(given[i].expected_e, own[i].expected_e, 1e-6 * own[i].expected_e) << i;
    EXPECT_NEAR(twice[i].expected_e, 2 * own[i].expected_e, 1e-6 * own[i].expected_e) << i;
    EXPECT_GT(own[i].expected_e, 0.0);
  }
  auto refused = MeasureScan(*scene, camera, Pose3::Identity(), *clean, spec, nullptr, nullptr,
                             std::span<const float>(cpu).first(cpu.size() - 1));
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("direct_radiance"), std::string::npos);
}

}  // namespace
}  // namespace vscan::capture
