// The returned signal at the pixel: the gain from a pixel's physical numbers, the cos^4 fall-off
// against the exact solid angle of a square pixel, a Lambertian surface's electrons as albedo
// cos(theta) / r^2 factor by factor, the emitter's cone, and the fields the checks name.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sensor/material.h"
#include "sensor/pixel_radiometry.h"
#include "sensor/returned_signal.h"

namespace vscan::sensor {
namespace {

using std::numbers::pi;

TEST(PixelRadiometry, TheGainCountsThePhotonsOfOneExposure) {
  // 3 um pixels behind an 8 mm f/2 lens, 10 ms at QE 0.3 and 850 nm; the figure worked out apart.
  PinholePixel pixel;
  pixel.aperture_area_m2 = pi * 0.002 * 0.002;
  pixel.pixel_solid_angle_sr = std::pow(3e-6 / 8e-3, 2);
  pixel.exposure_s = 0.01;
  pixel.quantum_efficiency = 0.3;
  pixel.wavelength_m = 850e-9;
  EXPECT_NEAR(PixelGain(pixel) / 22684.846638410123, 1.0, 1e-12);
  // Linear in each factor; inverse in the photon's energy.
  PinholePixel longer = pixel;
  longer.exposure_s *= 3;
  EXPECT_NEAR(PixelGain(longer) / PixelGain(pixel), 3.0, 1e-12);
  PinholePixel bluer = pixel;
  bluer.wavelength_m = 425e-9;
  EXPECT_NEAR(PixelGain(bluer) / PixelGain(pixel), 0.5, 1e-12);
}

// The exact solid angle of the rectangle [x0, x1] x [y0, y1] on the plane z = f, seen from the origin.
double RectangleSolidAngle(double x0, double x1, double y0, double y1, double f) {
  const auto corner = [f](double x, double y) { return std::atan(x * y / (f * std::sqrt(x * x + y * y + f * f))); };
  return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

TEST(PixelRadiometry, OffAxisPixelsCollectCosToTheFourth) {
  // A small aperture at the origin and 3 um pixels on the sensor plane 8 mm behind it (mirrored in
  // front here): a pixel collects L x (aperture area x cos) x (its solid angle).
  const double f = 8e-3, half = 1.5e-6;
  const double on_axis = RectangleSolidAngle(-half, half, -half, half, f);
  EXPECT_NEAR(on_axis / std::pow(2 * half / f, 2), 1.0, 1e-6);
  for (const auto& [x, y] :
       {std::pair{2e-3, 0.0}, std::pair{0.0, -5e-3}, std::pair{4e-3, 3e-3}, std::pair{-9e-3, 9e-3}}) {
    const double cos_axis = f / std::sqrt(x * x + y * y + f * f);
    const double collected = RectangleSolidAngle(x - half, x + half, y - half, y + half, f) * cos_axis;
    EXPECT_NEAR(OffAxisFalloff(Eigen::Vector3d(x, y, f)) / (collected / on_axis), 1.0, 1e-6) << x << " " << y;
    // Any length of ray.
    EXPECT_NEAR(OffAxisFalloff(Eigen::Vector3d(x, y, f) * 250), std::pow(cos_axis, 4), 1e-12);
  }
  EXPECT_EQ(OffAxisFalloff(Eigen::Vector3d(0, 0, 1)), 1.0);
  EXPECT_EQ(OffAxisFalloff(Eigen::Vector3d(1, 0, 0)), 0.0);
  EXPECT_EQ(OffAxisFalloff(Eigen::Vector3d(0, 0, -1)), 0.0);
}

// Electrons from a Lambertian (F0 = 0) point at `point` with normal `normal`, lit by a projector
// at point + r u that points its cone at it, seen by a camera at the origin.
double LambertianElectrons(double albedo, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                           const Eigen::Vector3d& u, double r, const PixelResponse& response) {
  const Emitter emitter{point + r * u, 0.2, -u, 20 * pi / 180};
  const Material lambertian{albedo, 0.0, 0.6, 0.0};
  const double radiance = DirectRadiance(lambertian, point, normal, emitter, Eigen::Vector3d::Zero());
  return ExpectedElectrons(radiance, OffAxisFalloff(point), response);
}

TEST(ReturnedSignal, ALambertianSurfacesElectronsGoAsAlbedoCosOverRSquaredFactorByFactor) {
  PixelResponse response;
  response.gain_e = PixelGain(PinholePixel{});
  const Eigen::Vector3d point(0.05, -0.03, 0.6);
  const Eigen::Vector3d u = Eigen::Vector3d(0.3, 0.1, -1).normalized();  // towards the projector
  const Eigen::Vector3d across = Eigen::Vector3d::UnitY().cross(u).normalized();  // tilts towards the camera
  const auto tilted = [&](double theta) { return Eigen::Vector3d(std::cos(theta) * u + std::sin(theta) * across); };
  const double albedo = 0.4, theta = 0.3, r = 0.5;
  const double reference = LambertianElectrons(albedo, point, tilted(theta), u, r, response);
  // The whole equation once: gain x albedo / pi x I cos(theta) / r^2 x cos^4(off axis).
  const double cos_axis = point.normalized().z();
  EXPECT_NEAR(reference / (response.gain_e * albedo / pi * 0.2 * std::cos(theta) / (r * r) * std::pow(cos_axis, 4)),
              1.0, 1e-12);
  for (const double other : {0.05, 0.8, 1.0}) {
    EXPECT_NEAR(LambertianElectrons(other, point, tilted(theta), u, r, response) / reference, other / albedo, 1e-9);
  }
  for (const double other : {0.0, 0.7, 1.2}) {
    EXPECT_NEAR(LambertianElectrons(albedo, point, tilted(other), u, r, response) / reference,
                std::cos(other) / std::cos(theta), 1e-9)
        << other;
  }
  for (const double other : {0.2, 1.0, 3.0}) {
    EXPECT_NEAR(LambertianElectrons(albedo, point, tilted(theta), u, other, response) / reference,
                (r * r) / (other * other), 1e-9);
  }
  // The same surface and projector moved across the camera's field: only the fall-off changes.
  const Eigen::Vector3d moved = point + Eigen::Vector3d(0.25, 0.1, 0);
  EXPECT_NEAR(LambertianElectrons(albedo, moved, tilted(theta), u, r, response) / reference,
              std::pow(moved.normalized().z() / cos_axis, 4), 1e-9);
  // Behind the surface, nothing.
  EXPECT_EQ(LambertianElectrons(albedo, point, tilted(1.7), u, r, response), 0);
}

TEST(ReturnedSignal, AnEmitterLightsOnlyWithinItsCone) {
  // The axis need not be of unit length.
  const Emitter emitter{Eigen::Vector3d(0.1, 0, 0), 1.0, Eigen::Vector3d(0, 0, 2), 15 * pi / 180};
  const Material grey = FindMaterialPreset("matte-grey")->material;
  const auto at = [&](double angle_deg) {
    const double angle = angle_deg * pi / 180;
    const Eigen::Vector3d point = emitter.position + Eigen::Vector3d(std::sin(angle), 0, std::cos(angle));
    return DirectRadiance(grey, point, -Eigen::Vector3d::UnitZ(), emitter, Eigen::Vector3d::Zero());
  };
  EXPECT_GT(at(14.9), 0);
  EXPECT_GT(at(-14.9), 0);
  EXPECT_EQ(at(15.1), 0);
  EXPECT_EQ(at(-30), 0);
  // Inside the cone it is the emitter without one.
  Emitter everywhere = emitter;
  everywhere.cone_half_angle_rad = pi;
  const Eigen::Vector3d point = emitter.position + Eigen::Vector3d(0.1, 0, 1);
  EXPECT_EQ(DirectRadiance(grey, point, -Eigen::Vector3d::UnitZ(), emitter, Eigen::Vector3d::Zero()),
            DirectRadiance(grey, point, -Eigen::Vector3d::UnitZ(), everywhere, Eigen::Vector3d::Zero()));
}

// Pearson's chi-square of 20 000 draws of a pixel at `signal` electrons, standardised by
// `assumed_sigma`, in 14 bins (12 of width 0.5 within 3 sigma and the two tails) against the
// standard normal's probabilities.
double NoiseChiSquare(double signal, double assumed_sigma, const PixelResponse& response) {
  const int n = 20000, bins = 14;
  std::vector<int> counts(bins, 0);
  for (int k = 0; k < n; ++k) {
    const double z = (RespondToRadiance(signal, response, 17, static_cast<uint64_t>(k)).measured_e - signal) /
                     assumed_sigma;
    ++counts[static_cast<size_t>(z < -3 ? 0 : z >= 3 ? bins - 1 : 1 + static_cast<int>((z + 3) / 0.5))];
  }
  const auto cdf = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  double chi2 = 0;
  for (int bin = 0; bin < bins; ++bin) {
    const double lo = bin == 0 ? -INFINITY : -3 + 0.5 * (bin - 1);
    const double hi = bin == bins - 1 ? INFINITY : -3 + 0.5 * bin;
    const double expected = n * (cdf(hi) - cdf(lo));
    chi2 += std::pow(counts[static_cast<size_t>(bin)] - expected, 2) / expected;
  }
  return chi2;
}

TEST(ReturnedSignal, TheNoiseIsGaussianOfVarianceSignalPlusReadNoiseSquared) {
  PixelResponse response;
  response.gain_e = 1;
  response.full_well_e = 1e9;
  response.read_noise_e = 20;
  // 13 degrees of freedom: the 99.9th percentile is 34.5.
  for (const double signal : {400.0, 5000.0}) {
    const double sigma = std::sqrt(signal + 400);
    EXPECT_LT(NoiseChiSquare(signal, sigma, response), 34.5) << signal;
    // The test tells a sigma 5% off.
    EXPECT_GT(NoiseChiSquare(signal, 1.05 * sigma, response), 34.5) << signal;
    EXPECT_GT(NoiseChiSquare(signal, sigma / 1.05, response), 34.5) << signal;
  }
  // Shot noise alone (the read noise forgotten) fails where the floor matters.
  EXPECT_GT(NoiseChiSquare(400, std::sqrt(400.0), response), 34.5);
}

TEST(ReturnedSignal, TheChecksNameTheEmittersAndThePixelsField) {
  EXPECT_TRUE(ValidateEmitter(Emitter{}, "emitter").ok());
  Emitter emitter;
  emitter.radiant_intensity_w_per_sr = -1;
  EXPECT_EQ(ValidateEmitter(emitter, "projector").field(), "projector.radiant_intensity_w_per_sr");
  emitter = Emitter{};
  emitter.axis = Eigen::Vector3d::Zero();
  EXPECT_EQ(ValidateEmitter(emitter, "projector").field(), "projector.axis");
  emitter = Emitter{};
  emitter.position.x() = std::nan("");
  EXPECT_EQ(ValidateEmitter(emitter, "projector").field(), "projector.position");
  for (const double bad : {0.0, -0.1, 4.0, std::nan("")}) {
    emitter = Emitter{};
    emitter.cone_half_angle_rad = bad;
    const Status status = ValidateEmitter(emitter, "projector");
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_EQ(status.field(), "projector.cone_half_angle_rad") << bad;
  }

  EXPECT_TRUE(ValidatePinholePixel(PinholePixel{}, "pixel").ok());
  PinholePixel pixel;
  pixel.quantum_efficiency = 1.2;
  EXPECT_EQ(ValidatePinholePixel(pixel, "pixel").field(), "pixel.quantum_efficiency");
  pixel = PinholePixel{};
  pixel.exposure_s = 0;
  EXPECT_EQ(ValidatePinholePixel(pixel, "pixel").field(), "pixel.exposure_s");
  pixel = PinholePixel{};
  pixel.aperture_area_m2 = INFINITY;
  EXPECT_EQ(ValidatePinholePixel(pixel, "pixel").field(), "pixel.aperture_area_m2");
}

}  // namespace
}  // namespace vscan::sensor
