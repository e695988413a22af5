// One-bounce indirect light: the time-of-flight multipath bias in a right-angled corner against a
// quadrature over the other wall written here, none on a single plane, structured light refusing
// the pixels near a corner's fold, determinism and thread-count independence, and the refusals.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <complex>
#include <functional>
#include <string>
#include <numbers>
#include <vector>

#include <tbb/global_control.h>

#include <atomic>

#include "capture/indirect_light.h"
#include "capture_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::capture::indirect_test {
namespace {

using test::Build;
using test::Code;
using test::Measure;

constexpr uint32_t kWallA = 1, kWallB = 2;
constexpr double kSpeedOfLight = 299792458.0;

sensor::Material Lambertian(double albedo) { return {albedo, 0.0, 1.0, 0.0}; }

// A wall from the fold line (through `fold`, along y, |y| <= half_height) out along the unit
// vector `along` for `length` metres.
raycast::SceneInstance Wall(const Eigen::Vector3d& fold, const Eigen::Vector3d& along, double length,
                            double half_height, uint32_t id) {
  TriangleMesh mesh;
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY() * half_height;
  const Eigen::Vector3d end = fold + along * length;
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(fold - y), Eigen::Vector3d(fold + y), Eigen::Vector3d(end + y),
                                   Eigen::Vector3d(end - y)}) {
    mesh.vertices.push_back(v.cast<float>());
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  raycast::SceneInstance instance;
  instance.mesh = vscan::test::Share(std::move(mesh));
  instance.instance_id = id;
  return instance;
}

// A concave right-angled corner: its fold along y through (0, 0, depth); wall A runs out along
// `a` and wall B along `b`, a perpendicular to b, each wall's normal the other's direction.
struct Corner {
  Eigen::Vector3d fold, a, b;
  double length, half_height;
};

MeasurementSpec LitSpec(double albedo, uint32_t samples) {
  MeasurementSpec spec = test::TruthSpec();
  ReturnedLightSpec light;
  light.emitter.radiant_intensity_w_per_sr = 1.0;
  light.pixel.gain_e = 1e4;
  light.pixel.full_well_e = 1e12;
  light.pixel.min_snr = 0;
  light.materials.assign(kWallB + 1, Lambertian(albedo));
  light.indirect_samples = samples;
  spec.returned_light = light;
  spec.include_rejected = true;
  spec.seed = 7;
  return spec;
}

// The one-bounce light x1 (on wall A, normal nA) returns to a camera and emitter at the origin,
// integrated over wall B by a midpoint rule, graded towards the fold (s = L t^2) and towards x1's
// height (y = y1 +- H' t^2): the radiance, its phasor relative to the direct path at wavenumber k,
// and for the Monte Carlo's spread the second moments of one cosine-weighted sample's estimate X
// (pi f L_in): of |X| and of Im(X w), the part of its phasor across the unit direction conj(w).
struct Quadrature {
  double radiance = 0;
  std::complex<double> phasor{0, 0};
  double second_moment = 0;
  double across_second_moment = 0;
};

Quadrature IntegrateOverWallB(const Corner& c, const Eigen::Vector3d& x1, double albedo, double intensity,
                              double k, std::complex<double> w = 1.0) {
  const Eigen::Vector3d n1 = c.b, n2 = c.a;  // each wall's normal is the other's direction
  const double f = albedo / std::numbers::pi;
  const Eigen::Vector3d to_camera = -x1.normalized();
  if (n1.dot(to_camera) <= 0) return {};
  const double direct_legs = x1.norm();
  constexpr int kS = 500, kY = 250;
  Quadrature q;
  const double y1 = x1.y();
  for (int is = 0; is < kS; ++is) {
    const double t = (is + 0.5) / kS;
    const double s = c.length * t * t, ds = c.length * 2 * t / kS;
    for (int side = 0; side < 2; ++side) {
      const double span = side == 0 ? c.half_height - y1 : c.half_height + y1;  // y1 to the edge
      for (int iy = 0; iy < kY; ++iy) {
        const double u = (iy + 0.5) / kY;
        const double dy = span * u * u, dyy = span * 2 * u / kY;
        const Eigen::Vector3d x2 = c.fold + s * c.b + Eigen::Vector3d::UnitY() * (side == 0 ? y1 + dy : y1 - dy);
        const Eigen::Vector3d d = x2 - x1;
        const double r = d.norm();
        const double cos1 = n1.dot(d) / r, cos2 = -n2.dot(d) / r;
        if (cos1 <= 0 || cos2 <= 0) continue;
        const double e = x2.norm(), cos_e = n2.dot(-x2) / e;
        if (cos_e <= 0) continue;
        const double l_in = f * intensity * cos_e / (e * e);  // x2 lit from the origin, seen from x1
        const double geometry = cos1 * cos2 / (r * r) * ds * dyy;
        q.radiance += f * l_in * geometry;
        const std::complex<double> turn = std::polar(1.0, k * (e + r - direct_legs));
        q.phasor += f * l_in * geometry * turn;
        q.second_moment += std::numbers::pi * f * f * l_in * l_in * geometry;
        q.across_second_moment += std::numbers::pi * f * f * l_in * l_in * geometry * std::pow(std::imag(turn * w), 2);
      }
    }
  }
  return q;
}

// The multipath bias of a time-of-flight camera (width x 9 pixels, 40 degrees) in a right-angled
// corner of two Lambertian walls, each pixel of the middle row on wall A at least min_from_fold from
// the fold against the quadrature: the measured range is half the path of the phase of direct +
// indirect. allowance_m: what the grid's interpolation may add to the Monte Carlo's spread.
void CheckCornerAgainstQuadrature(uint32_t width, uint32_t stride, uint32_t samples, double min_from_fold,
                                  double allowance_m) {
  const double s2 = std::sqrt(0.5);
  const Corner c{{0, 0, 1.0}, {s2, 0, -s2}, {-s2, 0, -s2}, 0.6, 0.6};
  const auto scene = Build({Wall(c.fold, c.a, c.length, c.half_height, kWallA),
                            Wall(c.fold, c.b, c.length, c.half_height, kWallB)});
  const auto camera = test::Camera(width, 9, 40);
  const double albedo = 0.8, frequency = 20e6, k = 2 * std::numbers::pi * frequency / kSpeedOfLight;
  MeasurementSpec spec = LitSpec(albedo, samples);
  spec.returned_light->indirect_stride_px = stride;
  spec.returned_light->modulation_frequency_hz = frequency;
  const PointCloud cloud = Measure(*scene, camera, spec);
  ASSERT_EQ(cloud.size(), width * 9u);
  const uint32_t middle_row = 4;
  int compared = 0;
  double largest_bias = 0, error_sum = 0, sigma_sum = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.pixels[i] / camera.width != middle_row || cloud.instance_ids[i] != kWallA) continue;
    ASSERT_EQ(cloud.statuses[i], Code(PointStatus::kMeasured));
    const Eigen::Vector3d x1 = cloud.clean_positions[i].cast<double>();
    if ((x1 - c.fold).dot(c.a) < min_from_fold) continue;
    const Quadrature q = IntegrateOverWallB(c, x1, albedo, 1.0, k);
    const double r = x1.norm(), cos_e = c.b.dot(-x1) / r;
    const double direct = albedo / std::numbers::pi * cos_e / (r * r);
    const std::complex<double> total = direct + q.phasor;
    const double expected_bias = std::arg(total) / k / 2;  // co-located emitter: range = path / 2
    const double measured_bias = cloud.positions[i].cast<double>().norm() - r;
    // The Monte Carlo's mean of N samples turns the phase by its part across the total, whose
    // sigma is sqrt(Var(Im(X w)) / N) over |total| (w = conj(total) / |total|): 5 sigma, plus 1e-5 m
    // for the quadrature and the float positions. An interpolated pixel averages grid pixels of
    // about the same sigma, which does not widen it.
    const std::complex<double> w = std::conj(total) / std::abs(total);
    const Quadrature across = IntegrateOverWallB(c, x1, albedo, 1.0, k, w);
    const double across_variance = across.across_second_moment - std::pow(std::imag(q.phasor * w), 2);
    const double tolerance =
        5 * std::sqrt(across_variance / samples) / std::abs(total) / k / 2 + 1e-5 + allowance_m;
    const double sigma = std::sqrt(q.second_moment / samples);  // bounds the radiance's spread
    EXPECT_NEAR(measured_bias, expected_bias, tolerance) << "pixel " << cloud.pixels[i] << " x1 " << x1.transpose();
    EXPECT_GT(expected_bias, 0.0);  // behind the surface: indirect paths are longer
    // The electrons: direct + indirect radiance times the gain and cos^4, within 5 sigma of the
    // Monte Carlo's spread and the pixel's own shot and read noise together (and with a grid, 2% of
    // the indirect light for its interpolation).
    const double falloff = std::pow(cloud.clean_positions[i].z() / r, 4);
    const double gain = spec.returned_light->pixel.gain_e * falloff;
    const double expected_e = gain * (direct + q.radiance);
    const double read_noise = spec.returned_light->pixel.read_noise_e;
    EXPECT_NEAR(cloud.intensities[i], expected_e,
                5 * std::sqrt(std::pow(gain * sigma, 2) + expected_e + read_noise * read_noise) +
                    (stride > 1 ? 0.02 * gain * q.radiance : 0.0));
    if (std::getenv("VSCAN_TEST_VERBOSE")) {
      std::printf("s %.3f bias %.5f (expected %.5f, tolerance %.5f) indirect/direct %.3f\n",
                  (x1 - c.fold).dot(c.a), measured_bias, expected_bias, tolerance, q.radiance / direct);
    }
    largest_bias = std::max(largest_bias, expected_bias);
    error_sum += measured_bias - expected_bias;
    sigma_sum += (tolerance - 1e-5 - allowance_m) / 5;
    ++compared;
  }
  EXPECT_GE(compared, 12);
  // No drift of the whole row: the mean error within 5 sigma of a mean over the grid pixels among
  // them (independent draws; an interpolated pixel shares its grid pixels' errors), plus the allowance.
  const double grid_pixels = std::ceil(static_cast<double>(compared) / stride);
  EXPECT_NEAR(error_sum / compared, 0.0, 5 * sigma_sum / compared / std::sqrt(grid_pixels) + 1e-5 + allowance_m);
  EXPECT_GT(largest_bias, 0.02);  // the test means something: centimetres of bias, not noise
}

// (a) Every pixel traced: the bias by the fold (from 1 cm) to the far side of the view.
TEST(IndirectLight, TimeOfFlightBiasInACornerMatchesAQuadratureOfTheOneBounceLight) {
  CheckCornerAgainstQuadrature(40, 1, 4096, 0.01, 0.0);
}

// The grid: every 4th pixel traced and the others interpolated, 5 cm from the fold on (where the
// bias bends little within a stride: 2 cm along the wall), within the same sigma and 0.3 mm for the
// interpolation.
TEST(IndirectLight, TheInterpolatedGridMatchesTheQuadratureAwayFromTheFold) {
  CheckCornerAgainstQuadrature(160, 4, 4096, 0.05, 3e-4);
}

// (b) A single plane is convex: no direction from it reaches another surface, so the indirect
// light is zero everywhere and the scan equals the direct-only one bit for bit.
TEST(IndirectLight, ASinglePlaneGetsNoIndirectLight) {
  const auto scene = Build({test::Plane(1.0, 2.0)});
  const auto camera = test::Camera(64, 48, 60);
  MeasurementSpec spec = LitSpec(0.9, 64);
  spec.returned_light->materials.assign(test::kPlaneId + 1, Lambertian(0.9));
  spec.returned_light->indirect_stride_px = 1;
  spec.returned_light->modulation_frequency_hz = 20e6;
  PointCloud clean;
  for (size_t i = 0; i < 64u * 48u; ++i) {
    clean.positions.push_back(camera.RayThroughPixel(i % 64, i / 64));
    clean.normals.push_back({0, 0, -1});
    clean.instance_ids.push_back(test::kPlaneId);
    clean.pixels.push_back(static_cast<uint32_t>(i));
  }
  clean.fields = kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldPixel;
  const auto returns = IndirectReturns(*scene, Pose3::Identity(), camera, clean, *spec.returned_light, 3);
  ASSERT_TRUE(returns.ok());
  for (const IndirectReturn& r : *returns) {
    ASSERT_EQ(r.radiance, 0.0);
    ASSERT_EQ(std::abs(r.phasor), 0.0);
  }
  const PointCloud with = Measure(*scene, camera, spec);
  spec.returned_light->indirect_samples = 0;
  const PointCloud without = Measure(*scene, camera, spec);
  ASSERT_EQ(with.size(), without.size());
  for (size_t i = 0; i < with.size(); ++i) {
    ASSERT_EQ(with.positions[i], without.positions[i]);
    ASSERT_EQ(with.intensities[i], without.intensities[i]);
  }
}

// A corner seen by a structured-light scanner: wall A faces the camera and the projector (15
// degrees off), wall B is lit at grazing (75 degrees); near the fold B gets more light from A than
// from the projector.
struct SlCorner {
  Corner c;
  std::shared_ptr<const raycast::RaycastScene> scene;
  sensor::PinholeCamera camera = test::Camera(160, 120, 80);
};

SlCorner MakeSlCorner() {
  const double alpha = 15 * test::kDeg;
  const Eigen::Vector3d a(std::cos(alpha), 0, -std::sin(alpha)), b(-std::sin(alpha), 0, -std::cos(alpha));
  SlCorner sl{{{0, 0, 1.0}, a, b, 0.6, 0.8}, nullptr};
  sl.scene = Build({Wall(sl.c.fold, a, 0.6, 0.8, kWallA), Wall(sl.c.fold, b, 0.6, 0.8, kWallB)});
  return sl;
}

MeasurementSpec SlSpec(const sensor::PinholeCamera& camera, uint32_t samples) {
  MeasurementSpec spec = LitSpec(0.9, samples);
  sensor::StructuredLight projector;
  projector.camera = camera;
  projector.projector_offset = Eigen::Vector3d(-0.1, 0, 0);
  spec.structured_light = projector;
  spec.returned_light->emitter.position = projector.projector_offset;
  return spec;
}

// (c) Pixels of the grazing wall within 5 cm of the fold are refused as interreflection, those past
// 45 cm and the whole of the facing wall decode; without indirect light every pixel decodes.
TEST(IndirectLight, StructuredLightRejectsInterreflectionNearACornersFold) {
  const SlCorner sl = MakeSlCorner();
  MeasureStats stats;
  const PointCloud cloud = Measure(*sl.scene, sl.camera, SlSpec(sl.camera, 256), &stats);
  size_t near = 0, near_rejected = 0, far = 0, far_measured = 0, facing = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint8_t status = cloud.statuses[i];
    if (status == Code(PointStatus::kRejectedShadowed) || status == Code(PointStatus::kRejectedUnlit)) continue;
    const Eigen::Vector3d p = cloud.clean_positions[i].cast<double>();
    if (cloud.instance_ids[i] == kWallA) {
      EXPECT_EQ(status, Code(PointStatus::kMeasured)) << p.transpose();
      ++facing;
      continue;
    }
    const double from_fold = (p - sl.c.fold).dot(sl.c.b);
    if (from_fold < 0.05) {
      ++near;
      near_rejected += status == Code(PointStatus::kRejectedInterreflection);
    } else if (from_fold > 0.45) {
      ++far;
      far_measured += status == Code(PointStatus::kMeasured);
    }
  }
  EXPECT_GT(facing, 3000u);
  EXPECT_GT(near, 100u);
  EXPECT_GT(far, 100u);
  EXPECT_GE(near_rejected, near * 98 / 100);
  EXPECT_EQ(far_measured, far);
  EXPECT_GE(stats.rejected_interreflection, near_rejected);

  MeasureStats direct_stats;
  Measure(*sl.scene, sl.camera, SlSpec(sl.camera, 0), &direct_stats);
  EXPECT_EQ(direct_stats.rejected_interreflection, 0u);
}

// (d) The same seed gives the same scan bit for bit, on one thread or many; another seed differs.
TEST(IndirectLight, DeterministicForASeedWhateverTheThreads) {
  const SlCorner sl = MakeSlCorner();
  MeasurementSpec spec = LitSpec(0.9, 16);
  spec.returned_light->modulation_frequency_hz = 20e6;
  const PointCloud many = Measure(*sl.scene, sl.camera, spec);
  PointCloud one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = Measure(*sl.scene, sl.camera, spec);
  }
  ASSERT_EQ(many.size(), one.size());
  for (size_t i = 0; i < many.size(); ++i) {
    ASSERT_EQ(many.positions[i], one.positions[i]) << i;
    ASSERT_EQ(many.intensities[i], one.intensities[i]) << i;
  }
  spec.seed = 8;
  const PointCloud other = Measure(*sl.scene, sl.camera, spec);
  size_t differ = 0;
  for (size_t i = 0; i < many.size(); ++i) differ += many.positions[i] != other.positions[i];
  EXPECT_GT(differ, many.size() / 2);
}

// A scan cancelled before its bounces stops with CANCELLED instead of tracing them.
TEST(IndirectLight, ACancelledScanStopsWithCancelled) {
  const SlCorner sl = MakeSlCorner();
  MeasurementSpec spec = LitSpec(0.9, 64);
  spec.fields &= ~kFieldEstimatedNormal;
  auto clean = raycast::Scan(*sl.scene, ExtendedRangeCamera(sl.camera), Pose3::Identity(),
                             {.fields = CleanFieldsFor(spec), .frame = raycast::ScanFrame::kSensor});
  ASSERT_TRUE(clean.ok());
  const std::atomic<bool> cancel{true};
  const auto cloud = MeasureScan(*sl.scene, sl.camera, Pose3::Identity(), *clean, spec, &cancel, nullptr);
  EXPECT_EQ(cloud.status().code(), StatusCode::kCancelled);
  const std::atomic<bool> go_on{false};
  EXPECT_TRUE(MeasureScan(*sl.scene, sl.camera, Pose3::Identity(), *clean, spec, &go_on, nullptr).ok());
  // The flag stops the bounces, not an earlier stage: without them the same scan completes.
  MeasurementSpec direct = spec;
  direct.returned_light->indirect_samples = 0;
  EXPECT_TRUE(MeasureScan(*sl.scene, sl.camera, Pose3::Identity(), *clean, direct, &cancel, nullptr).ok());
}

// A scene broken into fragments (every pixel its own object, so no pixel shares a surface with a
// grid pixel) would make every pixel trace its own bounces; past the budget the first edge pixels
// in pixel order are traced and the rest interpolate their grid pixels on any surface.
TEST(IndirectLight, EdgePixelsPastTheBudgetInterpolateInsteadOfTracing) {
  const SlCorner sl = MakeSlCorner();
  MeasurementSpec spec = LitSpec(0.9, 16);
  ReturnedLightSpec light = *spec.returned_light;
  light.indirect_stride_px = 4;
  auto scanned = raycast::Scan(*sl.scene, sl.camera, Pose3::Identity(),
                               {.fields = kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldPixel,
                                .frame = raycast::ScanFrame::kSensor});
  ASSERT_TRUE(scanned.ok());
  PointCloud fragments = *scanned;
  for (size_t i = 0; i < fragments.size(); ++i) fragments.instance_ids[i] = static_cast<uint32_t>(i + 1);
  light.materials.assign(fragments.size() + 1, Lambertian(0.9));
  const uint64_t grid = IndirectGridSamples(sl.camera, light);
  constexpr uint64_t kTraced = 10;
  const auto unbounded = IndirectReturns(*sl.scene, Pose3::Identity(), sl.camera, fragments, light, 5);
  const auto bounded = IndirectReturns(*sl.scene, Pose3::Identity(), sl.camera, fragments, light, 5, {}, nullptr,
                                       grid + kTraced * light.indirect_samples);
  ASSERT_TRUE(unbounded.ok() && bounded.ok());
  size_t alone = 0, differ = 0, lit = 0;
  for (size_t i = 0; i < fragments.size(); ++i) {
    const uint32_t p = fragments.pixels[i];
    const bool on_grid = (p % sl.camera.width) % 4 == 0 && (p / sl.camera.width) % 4 == 0;
    const IndirectReturn& a = (*unbounded)[i];
    const IndirectReturn& b = (*bounded)[i];
    lit += a.radiance > 0;
    if (on_grid || alone++ < kTraced) {
      ASSERT_EQ(a.radiance, b.radiance) << i;  // traced in both
      continue;
    }
    ASSERT_TRUE(std::isfinite(b.radiance) && b.radiance >= 0) << i;
    differ += a.radiance != b.radiance;
  }
  EXPECT_GT(lit, fragments.size() / 4);
  EXPECT_GT(differ, alone / 2);  // interpolated rather than traced
}

// (e) Each bound of the indirect light's members refused with INVALID_ARGUMENT naming the member.
TEST(IndirectLight, RefusalsNameTheField) {
  const auto refused = [](const std::function<void(ReturnedLightSpec&)>& change, const std::string& member) {
    ReturnedLightSpec spec;
    change(spec);
    const Status status = ValidateReturnedLight(spec, "returned_light");
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << member;
    EXPECT_NE(status.message().find("returned_light." + member), std::string::npos) << status.message();
  };
  refused([](ReturnedLightSpec& s) { s.indirect_samples = kMaxIndirectSamples + 1; }, "indirect_samples");
  refused([](ReturnedLightSpec& s) { s.indirect_samples = 1000000000; }, "indirect_samples");
  refused([](ReturnedLightSpec& s) { s.indirect_stride_px = 0; }, "indirect_stride_px");
  refused([](ReturnedLightSpec& s) { s.indirect_stride_px = kMaxIndirectStridePx + 1; }, "indirect_stride_px");
  refused([](ReturnedLightSpec& s) { s.modulation_frequency_hz = -1; }, "modulation_frequency_hz");
  refused([](ReturnedLightSpec& s) { s.modulation_frequency_hz = std::nan(""); }, "modulation_frequency_hz");
  refused([](ReturnedLightSpec& s) { s.modulation_frequency_hz = 1e11; }, "modulation_frequency_hz");
  refused([](ReturnedLightSpec& s) { s.interreflection_ratio = -0.5; }, "interreflection_ratio");
  refused([](ReturnedLightSpec& s) { s.interreflection_ratio = INFINITY; }, "interreflection_ratio");
  // The whole grid's bounces: 4096 samples on every pixel of a 2064 x 1544 frame is 1.3e10.
  ReturnedLightSpec heavy;
  heavy.indirect_samples = kMaxIndirectSamples;
  heavy.indirect_stride_px = 1;
  const sensor::PinholeCamera phoxi = sensor::CameraFromFov(2064, 1544, 48.8, 0.4, 1.2);
  EXPECT_GT(IndirectGridSamples(phoxi, heavy), kMaxIndirectGridSamples);
  heavy.indirect_samples = 16;
  heavy.indirect_stride_px = 8;
  EXPECT_EQ(IndirectGridSamples(phoxi, heavy), 16u * 258u * 193u);
  ReturnedLightSpec fine;
  fine.indirect_samples = kMaxIndirectSamples;
  fine.indirect_stride_px = kMaxIndirectStridePx;
  fine.modulation_frequency_hz = 20e6;
  EXPECT_TRUE(ValidateReturnedLight(fine, "returned_light").ok());
}

// The range of a path length: a co-located emitter halves it; an offset one solves the triangle.
TEST(IndirectLight, RangeOfPathLengthInvertsThePath) {
  const Eigen::Vector3d u = Eigen::Vector3d(0.2, -0.1, 1).normalized();
  EXPECT_NEAR(RangeOfPathLength(Eigen::Vector3d::Zero(), u, 3.0), 1.5, 1e-12);
  const Eigen::Vector3d e(0.1, 0.05, 0);
  const double r = 1.3, path = (e - r * u).norm() + r;
  EXPECT_NEAR(RangeOfPathLength(e, u, path), r, 1e-12);
}

}  // namespace
}  // namespace vscan::capture::indirect_test
