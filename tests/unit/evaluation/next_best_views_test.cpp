#include "evaluation/next_best_views.h"

#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "evaluation/surface_sampling.h"
#include "vscan_test/meshes.h"

namespace vscan::evaluation {
namespace {

// A box 0.2 x 0.1 x 0.3 m: faces of 0.03 m^2 across x, 0.06 across y and 0.02 across z.
const Eigen::Vector3d kLo(-0.1, -0.05, -0.15), kHi(0.1, 0.05, 0.15);
constexpr double kViewsTau = 0.006;
constexpr float kOnFace = 1e-5f;

enum Side : size_t { kPlusX, kMinusX, kPlusY, kMinusY, kPlusZ, kMinusZ };

// At 200 x 200 pixels and 40 degrees, a pixel spans 3.3 mm at 0.9 m: a face seen head-on has a hit
// within tau of every point, corners included.
sensor::PinholeCamera Camera() { return sensor::CameraFromFov(200, 200, 40, 0.05, 10); }

CandidateView LookAtFrom(const Eigen::Vector3d& eye, const Eigen::Vector3d& target = Eigen::Vector3d::Zero()) {
  const Eigen::Vector3d up = std::abs(eye.normalized().z()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  auto pose = PoseFromLookAt(eye, target, up, "eye");
  EXPECT_TRUE(pose.ok()) << pose.status().ToString();
  return {*pose, 0};
}

// The six views along the axes, 1 m from the centre, in Side order.
std::vector<CandidateView> AxisViews() {
  std::vector<CandidateView> views;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      views.push_back(LookAtFrom(sign * Eigen::Vector3d::Unit(axis)));
      views.back().tag = static_cast<uint32_t>(views.size() - 1);
    }
  }
  return views;
}

NextBestViewOptions Options() {
  NextBestViewOptions options;
  options.tau = kViewsTau;
  options.max_views = 6;
  return options;
}

struct BoxCase {
  TriangleMesh mesh = test::MakeBox(kLo, kHi);
  std::vector<Eigen::Vector3f> samples = SampleSurface(mesh, 44'000, 11);
  std::vector<uint8_t> covered;

  size_t Count(const std::function<bool(const Eigen::Vector3f&)>& keep) const {
    size_t n = 0;
    for (size_t i = 0; i < samples.size(); ++i) n += covered[i] == 0 && keep(samples[i]) ? 1 : 0;
    return n;
  }
};

// Covered: both faces across y, and the -x face with a band of 2 tau around it, so that the -x view
// sees only covered samples. Missed: the +x face and most of the two faces across z.
BoxCase ScannedFromTheSides() {
  BoxCase box;
  for (const Eigen::Vector3f& p : box.samples) {
    const bool side = std::abs(p.y()) >= 0.05f - kOnFace;
    const bool back = p.x() < -0.1f + 2 * kViewsTau;
    box.covered.push_back(side || back ? 1 : 0);
  }
  return box;
}

StatusOr<std::vector<ViewPick>> Pick(const BoxCase& box, std::span<const CandidateView> views,
                                     const NextBestViewOptions& options = Options()) {
  return PickNextBestViews(box.mesh, box.samples, box.covered, Camera(), views, options);
}

TEST(NextBestViews, PicksTheFaceWithMostMissedAreaThenTheRest) {
  const BoxCase box = ScannedFromTheSides();
  const auto picks = Pick(box, AxisViews());
  ASSERT_TRUE(picks.ok()) << picks.status().ToString();
  ASSERT_EQ(picks->size(), 3u);

  // +x first: its face, plus the missed samples on the faces across z within tau of its edge.
  const size_t face = box.Count([](const Eigen::Vector3f& p) { return p.x() >= 0.1f - kOnFace; });
  const size_t band =
      box.Count([](const Eigen::Vector3f& p) { return p.x() > 0.1f - kViewsTau && p.x() < 0.1f - kOnFace; });
  EXPECT_EQ((*picks)[0].candidate, kPlusX);
  EXPECT_GE((*picks)[0].gained_samples, face);
  EXPECT_LE((*picks)[0].gained_samples, face + band);
  EXPECT_GT((*picks)[0].gained_samples, face + band / 3);

  // Then the two faces across z, in either order; together the three see every missed sample.
  EXPECT_EQ((*picks)[1].candidate + (*picks)[2].candidate, size_t{kPlusZ + kMinusZ});
  EXPECT_NE((*picks)[1].candidate, (*picks)[2].candidate);
  const size_t missed = box.Count([](const Eigen::Vector3f&) { return true; });
  const size_t already = box.samples.size() - missed;
  size_t gained = 0;
  double previous = static_cast<double>(already) / box.samples.size();
  for (const ViewPick& pick : *picks) {
    gained += pick.gained_samples;
    EXPECT_GT(pick.coverage_after, previous);
    EXPECT_DOUBLE_EQ(pick.coverage_after, static_cast<double>(already + gained) / box.samples.size());
    previous = pick.coverage_after;
  }
  EXPECT_EQ(gained, missed);
  EXPECT_DOUBLE_EQ(picks->back().coverage_after, 1.0);
  // Each a face across z, less the few samples near its edge that +x saw.
  for (size_t k = 1; k < 3; ++k) {
    const float sign = (*picks)[k].candidate == kPlusZ ? 1.0f : -1.0f;
    const size_t on_face = box.Count([sign](const Eigen::Vector3f& p) { return sign * p.z() >= 0.15f - kOnFace; });
    EXPECT_LE((*picks)[k].gained_samples, on_face);
    EXPECT_GT((*picks)[k].gained_samples, on_face * 9 / 10);
  }
}

TEST(NextBestViews, AViewOfCoveredSamplesOnlyGainsNothing) {
  const BoxCase box = ScannedFromTheSides();
  const std::vector<CandidateView> back = {AxisViews()[kMinusX]};
  const auto picks = Pick(box, back);
  ASSERT_TRUE(picks.ok()) << picks.status().ToString();
  EXPECT_TRUE(picks->empty());
}

TEST(NextBestViews, KeepsToMaxViewsAndMinGain) {
  const BoxCase box = ScannedFromTheSides();
  const auto all = Pick(box, AxisViews());
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  ASSERT_EQ(all->size(), 3u);

  NextBestViewOptions options = Options();
  options.max_views = 2;
  const auto two = Pick(box, AxisViews(), options);
  ASSERT_TRUE(two.ok());
  ASSERT_EQ(two->size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ((*two)[i].candidate, (*all)[i].candidate);
    EXPECT_EQ((*two)[i].gained_samples, (*all)[i].gained_samples);
  }

  options = Options();
  options.min_gain_samples = (*all)[2].gained_samples + 1;
  const auto above_third = Pick(box, AxisViews(), options);
  ASSERT_TRUE(above_third.ok());
  EXPECT_EQ(above_third->size(), 2u);
  options.min_gain_samples = (*all)[0].gained_samples + 1;
  const auto none = Pick(box, AxisViews(), options);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->empty());
}

TEST(NextBestViews, NothingToPickWhenAllIsCovered) {
  BoxCase box = ScannedFromTheSides();
  box.covered.assign(box.samples.size(), 1);
  const auto picks = Pick(box, AxisViews());
  ASSERT_TRUE(picks.ok());
  EXPECT_TRUE(picks->empty());
}

TEST(NextBestViews, AThinnedImageSeesOnlyWhatItsRaysReach) {
  // A 20 x 20 grid puts hits 33 mm apart on the +x face: only the samples within tau of one count.
  const BoxCase box = ScannedFromTheSides();
  NextBestViewOptions options = Options();
  options.max_rays_per_view = 400;
  const std::vector<CandidateView> front = {AxisViews()[kPlusX]};
  const auto picks = Pick(box, front, options);
  ASSERT_TRUE(picks.ok());
  ASSERT_EQ(picks->size(), 1u);
  const size_t face = box.Count([](const Eigen::Vector3f& p) { return p.x() >= 0.1f - kOnFace; });
  EXPECT_GT((*picks)[0].gained_samples, face / 20);
  EXPECT_LT((*picks)[0].gained_samples, face / 4);
}

TEST(NextBestViews, AnOccludedObjectIsNotSeen) {
  // A small cube 0.3 m behind a big one, as seen from +x.
  TriangleMesh mesh = test::MakeBox(Eigen::Vector3d::Constant(-0.1), Eigen::Vector3d::Constant(0.1));
  const TriangleMesh small = test::MakeBox(Eigen::Vector3d(-0.33, -0.03, -0.03), Eigen::Vector3d(-0.27, 0.03, 0.03));
  const auto offset = static_cast<uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), small.vertices.begin(), small.vertices.end());
  for (const auto& t : small.triangles) mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const std::vector<Eigen::Vector3f> samples = SampleSurface(small, 6'000, 3);
  const std::vector<uint8_t> covered(samples.size(), 0);

  const std::vector<CandidateView> views = {LookAtFrom({1, 0, 0}), LookAtFrom({-1, 0, 0})};
  const auto front_only = PickNextBestViews(mesh, samples, covered, Camera(), std::span(views).first(1), Options());
  ASSERT_TRUE(front_only.ok()) << front_only.status().ToString();
  EXPECT_TRUE(front_only->empty());

  const auto picks = PickNextBestViews(mesh, samples, covered, Camera(), views, Options());
  ASSERT_TRUE(picks.ok());
  ASSERT_EQ(picks->size(), 1u);
  EXPECT_EQ((*picks)[0].candidate, 1u);
  // Its -x face, a sixth of the small cube, and bands of the faces next to it.
  size_t face = 0;
  for (const Eigen::Vector3f& p : samples) face += p.x() <= -0.33f + kOnFace ? 1 : 0;
  EXPECT_GE((*picks)[0].gained_samples, face);
  EXPECT_LT((*picks)[0].gained_samples, 2 * face);
}

TEST(NextBestViews, GrazingAndOutOfRangeHitsSeeNothing) {
  // A square seen from 5 degrees above its plane: every ray meets it at 84.5 to 85.5 degrees.
  const TriangleMesh square = test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.1);
  const std::vector<Eigen::Vector3f> samples = SampleSurface(square, 5'000, 5);
  const std::vector<uint8_t> covered(samples.size(), 0);
  const double elevation = 5 * std::numbers::pi / 180;
  const std::vector<CandidateView> views = {LookAtFrom({std::cos(elevation), 0, std::sin(elevation)})};
  NextBestViewOptions options = Options();
  options.max_incidence_deg = 80;
  const auto grazing = PickNextBestViews(square, samples, covered, Camera(), views, options);
  ASSERT_TRUE(grazing.ok());
  EXPECT_TRUE(grazing->empty());
  options.max_incidence_deg = 87;
  const auto allowed = PickNextBestViews(square, samples, covered, Camera(), views, options);
  ASSERT_TRUE(allowed.ok());
  ASSERT_EQ(allowed->size(), 1u);
  EXPECT_GT((*allowed)[0].gained_samples, 0u);

  // The square lies 0.9 to 1.1 m away: a camera that sees no farther than 0.8 m sees none of it.
  sensor::PinholeCamera short_sighted = Camera();
  short_sighted.far = 0.8;
  const auto beyond = PickNextBestViews(square, samples, covered, short_sighted, views, options);
  ASSERT_TRUE(beyond.ok());
  EXPECT_TRUE(beyond->empty());
}

TEST(NextBestViews, RejectsBadOptionsAndInputs) {
  const BoxCase box = ScannedFromTheSides();
  const std::vector<CandidateView> views = AxisViews();
  const auto field_of = [&](const NextBestViewOptions& options) {
    const auto result = Pick(box, views, options);
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
    return result.status().field();
  };
  NextBestViewOptions o = Options();
  o.max_views = 0;
  EXPECT_EQ(field_of(o), "next_best_views.max_views");
  o = Options();
  o.tau = 0;
  EXPECT_EQ(field_of(o), "next_best_views.tau");
  o.tau = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field_of(o), "next_best_views.tau");
  o = Options();
  o.max_incidence_deg = 91;
  EXPECT_EQ(field_of(o), "next_best_views.max_incidence_deg");
  o = Options();
  o.max_rays_per_view = 0;
  EXPECT_EQ(field_of(o), "next_best_views.max_rays_per_view");
  o = Options();
  o.min_gain_samples = 0;
  EXPECT_EQ(field_of(o), "next_best_views.min_gain_samples");

  const std::vector<uint8_t> short_covered(box.samples.size() - 1, 0);
  EXPECT_EQ(PickNextBestViews(box.mesh, box.samples, short_covered, Camera(), views, Options()).status().field(),
            "covered");
  std::vector<Eigen::Vector3f> bad_samples = box.samples;
  bad_samples[7].x() = std::numeric_limits<float>::infinity();
  EXPECT_EQ(PickNextBestViews(box.mesh, bad_samples, box.covered, Camera(), views, Options()).status().field(),
            "samples[7]");
  sensor::PinholeCamera no_range = Camera();
  no_range.far = no_range.near;
  EXPECT_EQ(PickNextBestViews(box.mesh, box.samples, box.covered, no_range, views, Options()).status().code(),
            StatusCode::kInvalidArgument);
  std::vector<CandidateView> bad_views = views;
  bad_views[2].frame_from_sensor.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(PickNextBestViews(box.mesh, box.samples, box.covered, Camera(), bad_views, Options()).status().field(),
            "next_best_views.candidates[2].frame_from_sensor");
}

TEST(NextBestViews, StopsWhenCancelled) {
  const BoxCase box = ScannedFromTheSides();
  const std::atomic<bool> cancel{true};
  const auto picks = PickNextBestViews(box.mesh, box.samples, box.covered, Camera(), AxisViews(), Options(), &cancel);
  EXPECT_EQ(picks.status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::evaluation

namespace vscan::evaluation {
namespace {

TEST(NextBestViews, UnderTheSensorsOwnLightABlackPartGivesNoPicksAndAWhiteOneTheSame) {
  const BoxCase box = ScannedFromTheSides();
  const std::vector<CandidateView> views = AxisViews();
  const auto unlit = Pick(box, views);
  ASSERT_TRUE(unlit.ok());
  ASSERT_FALSE(unlit->empty());
  NextBestViewOptions options = Options();
  options.light.emplace();
  options.light->emitter.radiant_intensity_w_per_sr = 0.001;
  options.light->pixel.gain_e = 1e7;
  // White at 1 m: about 2900 e; black 300 times less, an SNR under 2.
  options.light->material = {0.9, 0.0, 1.0, 0.0};
  const auto white = Pick(box, views, options);
  ASSERT_TRUE(white.ok());
  ASSERT_EQ(white->size(), unlit->size());
  for (size_t i = 0; i < unlit->size(); ++i) {
    EXPECT_EQ((*white)[i].candidate, (*unlit)[i].candidate);
    EXPECT_EQ((*white)[i].gained_samples, (*unlit)[i].gained_samples);
  }
  options.light->material = {0.003, 0.0, 1.0, 0.0};
  const auto black = Pick(box, views, options);
  ASSERT_TRUE(black.ok());
  EXPECT_TRUE(black->empty());
  options.light->material.roughness = 2;
  const auto refused = Pick(box, views, options);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().field(), "next_best_views.light.material.roughness");
}

}  // namespace
}  // namespace vscan::evaluation
