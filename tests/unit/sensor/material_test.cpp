// Materials and the light an active sensor gets back: analytic cases (a Lambertian plane's signal
// goes as albedo cos(theta) / r^2), reciprocity, energy conservation by quadrature, GGX against
// Walter et al.'s equations written out here, a mirror-like surface bright only near its specular
// direction, and shot noise whose spread follows sqrt(signal).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "random/seeded_draws.h"
#include "sensor/brdf.h"
#include "sensor/material.h"
#include "sensor/pixel_radiometry.h"
#include "sensor/returned_signal.h"

namespace vscan::sensor {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Vector3d Direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Directional-hemispherical reflectance: the integral of f cos over the light's hemisphere, for a
// viewer at theta_v. Integrated over half vectors h (l = 2 (h.v) h - v, dw_l = 4 (h.v) dw_h), whose
// lobe sits at the normal whatever v, on a grid dense near it (theta_h = pi/2 t^2), so that narrow
// lobes are resolved. v lies in the xz plane: the half of the azimuths with y >= 0, twice.
double Reflectance(const Material& material, double theta_v) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d v = Direction(theta_v, 0);
  const int steps_t = 600, steps_phi = 180;
  const double d_t = 1.0 / steps_t, d_phi = kPi / steps_phi;
  double sum = 0;
  for (int i = 0; i < steps_t; ++i) {
    const double t = (i + 0.5) * d_t;
    const double theta_h = 0.5 * kPi * t * t, d_theta = kPi * t * d_t;
    for (int j = 0; j < steps_phi; ++j) {
      const Eigen::Vector3d h = Direction(theta_h, (j + 0.5) * d_phi);
      const double h_v = h.dot(v);
      if (h_v <= 0) continue;
      const Eigen::Vector3d l = 2 * h_v * h - v;
      sum += EvaluateBrdf(material, n, l, v) * std::max(0.0, l.z()) * 4 * h_v * std::sin(theta_h) * d_theta * d_phi;
    }
  }
  return 2 * sum;
}

TEST(Material, ALambertianPlanesRadianceIsAlbedoTimesCosOverRSquared) {
  // The emitter at the camera (a ToF illuminator): l == v, so h == v and Schlick's term with F0 = 0
  // is zero; the BRDF is albedo / pi exactly.
  const Eigen::Vector3d camera = Eigen::Vector3d::Zero();
  const Emitter emitter{camera, 2.5};
  for (const double albedo : {0.1, 0.5, 0.9}) {
    for (const double tilt_deg : {0.0, 30.0, 60.0}) {
      for (const double r : {0.3, 1.0, 2.7}) {
        const Material material{albedo, 0.0, 0.7, 0.0};
        const double tilt = tilt_deg * kPi / 180;
        const Eigen::Vector3d point(0, 0, r);
        const Eigen::Vector3d normal(std::sin(tilt), 0, -std::cos(tilt));
        const double expected = albedo / kPi * emitter.radiant_intensity_w_per_sr * std::cos(tilt) / (r * r);
        EXPECT_NEAR(DirectRadiance(material, point, normal, emitter, camera) / expected, 1.0, 1e-12)
            << albedo << " " << tilt_deg << " " << r;
      }
    }
  }
}

TEST(Material, TheBrdfIsReciprocalAndZeroBelowTheHorizon) {
  random::SplitMix64Stream draws(7);
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  for (int k = 0; k < 2000; ++k) {
    const Material material{draws.Uniform(), draws.Uniform(), draws.Uniform(), draws.Uniform()};
    const Eigen::Vector3d a = Direction(0.5 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
    const Eigen::Vector3d b = Direction(0.5 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
    const double ab = EvaluateBrdf(material, n, a, b), ba = EvaluateBrdf(material, n, b, a);
    EXPECT_GE(ab, 0);
    EXPECT_NEAR(ab, ba, 1e-12 * std::max(1.0, ab));
    const Eigen::Vector3d below(a.x(), a.y(), -a.z());
    EXPECT_EQ(EvaluateBrdf(material, n, below, b), 0);
    EXPECT_EQ(EvaluateBrdf(material, n, b, below), 0);
  }
}

TEST(Material, NoMaterialReflectsMoreLightThanArrives) {
  std::vector<Material> materials;
  for (const MaterialPreset& preset : MaterialPresets()) materials.push_back(preset.material);
  // The brightest of each kind: white, F0 of a dielectric or 1, over the blend and the roughness
  // from below the floor to 1.
  for (const double roughness : {0.0, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0}) {
    for (const double metallic : {0.0, 0.5, 1.0}) {
      for (const double f0 : {0.04, 1.0}) materials.push_back({1.0, metallic, roughness, f0});
    }
  }
  for (const Material& material : materials) {
    for (const double theta_v : {0.0, 0.6, 1.2, 1.45}) {
      EXPECT_LE(Reflectance(material, theta_v), 1.0 + 1e-3)
          << material.albedo << " " << material.metallic << " " << material.roughness << " "
          << material.specular_reflectance << " at " << theta_v;
    }
  }
  // The quadrature resolves the narrowest lobe: a white mirror at the roughness floor returns all
  // but the little its masking takes.
  EXPECT_GE(Reflectance({1.0, 1.0, 0.0, 0.04}, 0.0), 0.99);
  EXPECT_GE(Reflectance({1.0, 1.0, 0.0, 0.04}, 1.2), 0.97);
}

TEST(Material, ADielectricWithoutSpecularReflectanceIsLambertian) {
  // F0 = 0: no Fresnel term at any angle, so the reflectance is the albedo from every direction and
  // the BRDF is albedo / pi for every pair of directions.
  random::SplitMix64Stream draws(5);
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  for (const double albedo : {0.2, 0.6, 1.0}) {
    for (const double roughness : {0.0, 0.5, 1.0}) {
      const Material lambertian{albedo, 0.0, roughness, 0.0};
      for (const double theta_v : {0.0, 0.7, 1.4}) {
        EXPECT_NEAR(Reflectance(lambertian, theta_v), albedo, 1e-4) << albedo << " " << roughness << " " << theta_v;
      }
      for (int k = 0; k < 100; ++k) {
        const Eigen::Vector3d l = Direction(0.5 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
        const Eigen::Vector3d v = Direction(0.5 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
        EXPECT_NEAR(EvaluateBrdf(lambertian, n, l, v), albedo / kPi, 1e-15);
      }
    }
  }
}

TEST(Material, TheBrdfIsWaltersGgxOverLambert) {
  // D and G1 as Walter et al. (2007) write them, in tangents (eqs. 33 and 34).
  const auto d_walter = [](double cos_h, double alpha) {
    const double tan2 = (1 - cos_h * cos_h) / (cos_h * cos_h);
    const double a2 = alpha * alpha;
    return 1 / (kPi * a2 * std::pow(cos_h, 4) * std::pow(1 + tan2 / a2, 2));
  };
  const auto g1_walter = [](double cos_v, double alpha) {
    const double tan2 = (1 - cos_v * cos_v) / (cos_v * cos_v);
    return 2 / (1 + std::sqrt(1 + alpha * alpha * tan2));
  };
  // Schlick (1994) with the grazing reflectance Schuler (2009) takes from F0.
  const auto schlick = [](double f0, double cos_d) {
    const double f90 = f0 >= 0.02 ? 1.0 : f0 / 0.02;
    return f0 + (f90 - f0) * std::pow(1 - cos_d, 5);
  };
  random::SplitMix64Stream draws(11);
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  for (int k = 0; k < 4000; ++k) {
    const double roughness = 0.05 + 0.95 * draws.Uniform();
    // Every other material a metal (no diffuse term, F0 = albedo); the rest blended dielectrics,
    // some with an F0 below the 0.02 where the grazing reflectance falls.
    const double albedo = draws.Uniform(), metallic = k % 2 == 0 ? 1.0 : draws.Uniform();
    const double f0_dielectric = k % 4 == 1 ? 0.02 * draws.Uniform() : draws.Uniform();
    const Material material{albedo, metallic, roughness, f0_dielectric};
    const Eigen::Vector3d l = Direction(0.49 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
    const Eigen::Vector3d v = Direction(0.49 * kPi * draws.Uniform(), 2 * kPi * draws.Uniform());
    const Eigen::Vector3d h = (l + v).normalized();
    const double alpha = roughness * roughness;
    const double f0 = metallic * albedo + (1 - metallic) * f0_dielectric;
    const double fresnel = schlick(f0, h.dot(v));
    const double expected =
        d_walter(h.z(), alpha) * g1_walter(l.z(), alpha) * g1_walter(v.z(), alpha) * fresnel / (4 * l.z() * v.z()) +
        (1 - metallic) * (1 - schlick(f0, l.z())) * (1 - schlick(f0, v.z())) * albedo / kPi;
    EXPECT_NEAR(EvaluateBrdf(material, n, l, v), expected, 1e-9 * std::max(1.0, expected));
  }
}

TEST(Material, AMirrorLikeSurfaceSaturatesOnlyNearItsSpecularDirection) {
  // A camera at the origin, a projector 10 cm to its right, a plane 0.5 m ahead turned about y.
  // The pixel's gain is PinholePixel's default (3 um pixels, 8 mm f/2 lens, 10 ms, QE 0.3 at
  // 850 nm), the projector sends 0.1 W/sr (50 mW over half a steradian): a matte grey plane
  // facing the camera fills a tenth of the full well or so.
  const Eigen::Vector3d camera = Eigen::Vector3d::Zero();
  const Emitter projector{Eigen::Vector3d(0.1, 0, 0), 0.1};
  const Eigen::Vector3d point(0, 0, 0.5);
  const Material& grey = FindMaterialPreset("matte-grey")->material;
  PixelResponse response;
  response.gain_e = PixelGain(PinholePixel{});
  const double grey_facing = DirectRadiance(grey, point, -Eigen::Vector3d::UnitZ(), projector, camera);
  ASSERT_GT(response.gain_e * grey_facing, 0.05 * response.full_well_e);
  ASSERT_LT(response.gain_e * grey_facing, 0.3 * response.full_well_e);
  // The plane's normal bisects the directions to the camera and the projector at this turn.
  const double mirror_deg = 0.5 * std::atan2(0.1, 0.5) * 180 / kPi;
  const Material& steel = FindMaterialPreset("polished-steel")->material;
  double widest_saturated_deg = 0;
  int dark = 0, turns = 0;
  for (double turn_deg = -40; turn_deg <= 40; turn_deg += 0.25) {
    const double turn = turn_deg * kPi / 180;
    const Eigen::Vector3d normal(std::sin(turn), 0, -std::cos(turn));
    const PixelSignal signal = RespondToRadiance(DirectRadiance(steel, point, normal, projector, camera), response, 1,
                                                 static_cast<uint64_t>(turns++));
    if (signal.verdict == SignalVerdict::kSaturated) {
      widest_saturated_deg = std::max(widest_saturated_deg, std::abs(turn_deg - mirror_deg));
    }
    if (signal.verdict == SignalVerdict::kDark) ++dark;
  }
  EXPECT_GT(widest_saturated_deg, 0) << "the highlight never saturated";
  EXPECT_LT(widest_saturated_deg, 5);
  // Away from the highlight the polished steel returns too little to decode.
  EXPECT_GT(dark, turns / 2);
  // The grey plane decodes at every one of those turns.
  for (double turn_deg = -40; turn_deg <= 40; turn_deg += 5) {
    const double turn = turn_deg * kPi / 180;
    const Eigen::Vector3d normal(std::sin(turn), 0, -std::cos(turn));
    EXPECT_EQ(RespondToRadiance(DirectRadiance(grey, point, normal, projector, camera), response, 1, 0).verdict,
              SignalVerdict::kMeasured)
        << turn_deg;
  }
}

TEST(ReturnedSignal, ShotNoiseSpreadFollowsTheSquareRootOfTheSignal) {
  PixelResponse response;
  response.gain_e = 1;
  response.full_well_e = 1e9;
  response.read_noise_e = 5;
  for (const double signal : {100.0, 1000.0, 20000.0}) {
    const int n = 20000;
    double sum = 0, sum2 = 0;
    for (int k = 0; k < n; ++k) {
      const double e = RespondToRadiance(signal, response, 3, static_cast<uint64_t>(k)).measured_e;
      sum += e;
      sum2 += e * e;
    }
    const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
    const double expected_sigma = std::sqrt(signal + 25);
    // The mean within 4 standard errors, the spread within 3% (its standard error is 0.5%).
    EXPECT_NEAR(mean, signal, 4 * expected_sigma / std::sqrt(n)) << signal;
    EXPECT_NEAR(sigma / expected_sigma, 1.0, 0.03) << signal;
  }
  // The same (seed, key) gives the same draw; another key another.
  EXPECT_EQ(RespondToRadiance(500, response, 9, 4).measured_e, RespondToRadiance(500, response, 9, 4).measured_e);
  EXPECT_NE(RespondToRadiance(500, response, 9, 4).measured_e, RespondToRadiance(500, response, 9, 5).measured_e);
}

TEST(ReturnedSignal, DarkBelowTheDecodableContrastSaturatedAtTheFullWell) {
  PixelResponse response;
  response.gain_e = 1;
  response.full_well_e = 10000;
  response.read_noise_e = 10;
  response.min_snr = 5;
  // SNR(S) = S / sqrt(S + 100) crosses 5 at S = (25 + sqrt(625 + 10000)) / 2 = 64.04 electrons.
  EXPECT_EQ(RespondToRadiance(63, response, 1, 0).verdict, SignalVerdict::kDark);
  EXPECT_EQ(RespondToRadiance(65, response, 1, 0).verdict, SignalVerdict::kMeasured);
  EXPECT_EQ(RespondToRadiance(9999, response, 1, 0).verdict, SignalVerdict::kMeasured);
  const PixelSignal full = RespondToRadiance(10000, response, 1, 0);
  EXPECT_EQ(full.verdict, SignalVerdict::kSaturated);
  EXPECT_LE(full.measured_e, response.full_well_e);
  EXPECT_EQ(RespondToRadiance(0, response, 1, 0).verdict, SignalVerdict::kDark);
}

TEST(ReturnedSignal, DepthNoiseGrowsAsTheSignalFalls) {
  EXPECT_DOUBLE_EQ(SignalDepthSigma(0.001, 4000, 4000, 5), 0.001);
  // Shot-noise limited (no read noise): a quarter of the signal doubles the sigma.
  EXPECT_NEAR(SignalDepthSigma(0.001, 4000, 1000, 0), 0.002, 1e-15);
  EXPECT_GT(SignalDepthSigma(0.001, 4000, 100, 5), SignalDepthSigma(0.001, 4000, 100, 0));
  EXPECT_TRUE(std::isinf(SignalDepthSigma(0.001, 4000, 0, 5)));
}

TEST(Material, PresetsAreValidAndBadValuesAreRefusedNamingTheField) {
  ASSERT_FALSE(MaterialPresets().empty());
  EXPECT_EQ(MaterialPresets().front().name, "matte-grey");
  for (const MaterialPreset& preset : MaterialPresets()) {
    EXPECT_TRUE(ValidateMaterial(preset.material, "material").ok()) << preset.name;
    EXPECT_EQ(FindMaterialPreset(preset.name), &preset);
  }
  EXPECT_EQ(FindMaterialPreset("unobtainium"), nullptr);

  Material bad;
  bad.albedo = std::nan("");
  EXPECT_EQ(ValidateMaterial(bad, "objects[2].material").field(), "objects[2].material.albedo");
  bad = Material{};
  bad.metallic = 1.5;
  EXPECT_EQ(ValidateMaterial(bad, "material").field(), "material.metallic");
  bad = Material{};
  bad.roughness = -0.1;
  EXPECT_EQ(ValidateMaterial(bad, "material").field(), "material.roughness");
  bad = Material{};
  bad.specular_reflectance = INFINITY;
  EXPECT_EQ(ValidateMaterial(bad, "material").code(), StatusCode::kInvalidArgument);

  PixelResponse response;
  EXPECT_TRUE(ValidatePixelResponse(response, "response").ok());
  response.gain_e = 0;
  EXPECT_EQ(ValidatePixelResponse(response, "response").field(), "response.gain_e");
  response = PixelResponse{};
  response.read_noise_e = -1;
  EXPECT_EQ(ValidatePixelResponse(response, "response").field(), "response.read_noise_e");
}

}  // namespace
}  // namespace vscan::sensor
