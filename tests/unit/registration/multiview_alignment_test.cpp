#include "registration/multiview_alignment.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "icp_test_util.h"
#include "multiview_views.h"

namespace vscan::registration {
namespace {

using testing::BunnyView;
using testing::CentreErrorMm;
using testing::RandomError;
using testing::RotationErrorDeg;
using testing::ScanBunny;
using testing::ViewAround;

constexpr double kDistance = 0.35;

// Views of the bunny at equal steps of azimuth all around, and initial poses off by a rotation of
// error_deg about a random axis through the bunny and a shift of error_m, except view 0 (the anchor).
struct Ring {
  std::vector<BunnyView> views;
  std::vector<Pose3> initial;
};

Ring MakeRing(int count, double elevation_deg, double fov_deg, double noise, double error_deg, double error_m) {
  Ring ring;
  for (int k = 0; k < count; ++k) {
    ring.views.push_back(ScanBunny(ViewAround(360.0 * k / count, elevation_deg, kDistance), fov_deg, noise, 100 + k));
    const Pose3& truth = ring.views.back().model_from_sensor;
    ring.initial.push_back(k == 0 ? truth : RandomError(error_deg, error_m, 7 + k) * truth);
  }
  return ring;
}

ViewScan ScanOf(const Ring& ring, size_t k) {
  ViewScan scan;
  scan.points = ring.views[k].points;
  scan.initial_model_from_sensor = ring.initial[k];
  return scan;
}

std::vector<ViewAlignment> AlignRing(const Ring& ring, const MultiviewOptions& options) {
  auto aligner = MultiviewAligner::Create(options);
  EXPECT_TRUE(aligner.ok()) << aligner.status().ToString();
  for (size_t k = 0; k < ring.views.size(); ++k) {
    const auto added = aligner->Add(ScanOf(ring, k));
    EXPECT_TRUE(added.ok()) << added.status().ToString();
  }
  auto result = aligner->Finish();
  EXPECT_TRUE(result.ok()) << result.status().ToString();
  return result.ok() ? *result : std::vector<ViewAlignment>{};
}

struct Errors {
  std::vector<double> rotation_deg;
  std::vector<double> centre_mm;
  double max_rotation_deg() const { return *std::max_element(rotation_deg.begin(), rotation_deg.end()); }
  double max_centre_mm() const { return *std::max_element(centre_mm.begin(), centre_mm.end()); }
};

Errors ErrorsOf(const Ring& ring, const std::vector<Pose3>& poses) {
  Errors e;
  for (size_t k = 0; k < ring.views.size(); ++k) {
    e.rotation_deg.push_back(RotationErrorDeg(poses[k], ring.views[k].model_from_sensor));
    e.centre_mm.push_back(CentreErrorMm(poses[k], ring.views[k].model_from_sensor));
  }
  return e;
}

std::vector<Pose3> PosesOf(const std::vector<ViewAlignment>& alignments) {
  std::vector<Pose3> poses;
  for (const auto& a : alignments) poses.push_back(a.model_from_sensor);
  return poses;
}

void ExpectAllAligned(const std::vector<ViewAlignment>& alignments) {
  for (size_t k = 0; k < alignments.size(); ++k) {
    EXPECT_TRUE(alignments[k].aligned) << "view " << k << ": " << alignments[k].reason;
    EXPECT_TRUE(alignments[k].reason.empty()) << k;
  }
}

TEST(MultiviewAlignmentTest, NoiseFreeViewsLandOnTheirTruePoses) {
  const Ring ring = MakeRing(8, 15.0, 40.0, 0.0, 2.0, 0.008);
  const Errors initial = ErrorsOf(ring, ring.initial);
  const std::vector<ViewAlignment> result = AlignRing(ring, MultiviewOptions{});
  ASSERT_EQ(result.size(), 8u);
  ExpectAllAligned(result);
  EXPECT_EQ(result[0].model_from_sensor.matrix(), ring.initial[0].matrix()) << "the anchor keeps its pose";
  const Errors final = ErrorsOf(ring, PosesOf(result));
  EXPECT_LT(final.max_rotation_deg(), 0.05);
  EXPECT_LT(final.max_centre_mm(), 0.2);
  // Every perturbed view started at least 2 degrees and several millimetres off.
  for (size_t k = 1; k < 8; ++k) {
    EXPECT_LT(final.rotation_deg[k], initial.rotation_deg[k] / 40.0) << k;
    EXPECT_LT(final.centre_mm[k], initial.centre_mm[k] / 40.0) << k;
  }
}

// Gaussian noise of sigma = 0.5 mm on each coordinate: the views must land within sigma / 2 at the
// object, and turn by less than half the angle sigma subtends over the bunny's half width (75 mm),
// far better than the noise of any single point.
TEST(MultiviewAlignmentTest, NoisyViewsLandWithinBoundsSetByTheNoise) {
  constexpr double kSigma = 0.0005;
  const Ring ring = MakeRing(8, 15.0, 40.0, kSigma, 2.0, 0.008);
  const std::vector<ViewAlignment> result = AlignRing(ring, MultiviewOptions{});
  ASSERT_EQ(result.size(), 8u);
  ExpectAllAligned(result);
  const Errors final = ErrorsOf(ring, PosesOf(result));
  EXPECT_LT(final.max_centre_mm(), 0.5 * kSigma * 1000.0);
  EXPECT_LT(final.max_rotation_deg(), 0.5 * std::atan(kSigma / 0.075) * 180.0 / std::numbers::pi);
  for (const auto& a : result) {
    EXPECT_GT(a.fitness, 0.7);
    EXPECT_LT(a.inlier_rmse, 2.0 * kSigma);
  }
}

// Narrow views (18 degrees, about 11 cm across at 35 cm) with noise all around the bunny: each view
// rests mostly on the one before it, so errors grow away from the anchor until the ring closes. The
// pose graph spreads them round the loop.
TEST(MultiviewAlignmentTest, ThePoseGraphReducesDriftAroundAFullRevolution) {
  const Ring ring = MakeRing(12, 10.0, 18.0, 0.0005, 1.0, 0.005);
  MultiviewOptions options;
  options.pose_graph = false;
  const std::vector<ViewAlignment> sequential = AlignRing(ring, options);
  options.pose_graph = true;
  const std::vector<ViewAlignment> graph = AlignRing(ring, options);
  ASSERT_EQ(sequential.size(), 12u);
  ASSERT_EQ(graph.size(), 12u);
  ExpectAllAligned(sequential);
  ExpectAllAligned(graph);
  const Errors before = ErrorsOf(ring, PosesOf(sequential));
  const Errors after = ErrorsOf(ring, PosesOf(graph));
  // The sequential errors do accumulate: the view opposite the anchor is worse than both of the
  // anchor's neighbours.
  EXPECT_GT(before.centre_mm[6], 2.0 * std::max(before.centre_mm[1], before.centre_mm[11]));
  EXPECT_LT(after.max_centre_mm(), 0.75 * before.max_centre_mm());
  EXPECT_LT(after.max_rotation_deg(), before.max_rotation_deg());
  EXPECT_EQ(graph[0].model_from_sensor.matrix(), ring.initial[0].matrix());
}

// Poses known to a micrometre and 0.00006 degrees (a robot without encoder noise) stay where they
// are although narrow noisy views, aligned on their own, drift from them.
TEST(MultiviewAlignmentTest, FirmlyKnownInitialPosesHoldAgainstNoisyScans) {
  const Ring ring = MakeRing(12, 10.0, 18.0, 0.0005, 0.0, 0.0);
  auto aligned = [&](bool prior) {
    auto aligner = MultiviewAligner::Create(MultiviewOptions{});
    EXPECT_TRUE(aligner.ok());
    for (size_t k = 0; k < ring.views.size(); ++k) {
      ViewScan scan = ScanOf(ring, k);
      if (prior) scan.initial_information = Matrix6d::Identity() / (1e-6 * 1e-6);
      EXPECT_TRUE(aligner->Add(std::move(scan)).ok());
    }
    auto result = aligner->Finish();
    EXPECT_TRUE(result.ok()) << result.status().ToString();
    return result.ok() ? ErrorsOf(ring, PosesOf(*result)) : Errors{{1e9}, {1e9}};
  };
  const Errors alone = aligned(false);
  const Errors held = aligned(true);
  EXPECT_GT(alone.max_centre_mm(), 0.05);
  EXPECT_LT(held.max_centre_mm(), 0.01);
  EXPECT_LT(held.max_rotation_deg(), 0.001);
}

// Priors as wide as the true errors of the initial poses (0.3 degrees, 2 mm, every view but the
// first): with no scan held fixed, the set sits where the priors agree best, a fraction of their
// error off, and the scans keep it together.
TEST(MultiviewAlignmentTest, PriorsAsWideAsThePoseErrorsPlaceTheSetBetweenThem) {
  const Ring ring = MakeRing(12, 10.0, 18.0, 0.0005, 0.3, 0.002);
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  Matrix6d information = Matrix6d::Zero();
  information.diagonal() << Eigen::Vector3d::Constant(1 / std::pow(0.3 * std::numbers::pi / 180, 2)),
      Eigen::Vector3d::Constant(1 / (0.002 * 0.002));
  for (size_t k = 0; k < ring.views.size(); ++k) {
    ViewScan scan = ScanOf(ring, k);
    scan.initial_information = information;
    ASSERT_TRUE(aligner->Add(std::move(scan)).ok());
  }
  const auto result = aligner->Finish();
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  ExpectAllAligned(*result);
  const Errors initial = ErrorsOf(ring, ring.initial);
  const Errors final = ErrorsOf(ring, PosesOf(*result));
  EXPECT_LT(final.max_centre_mm(), 0.5 * initial.max_centre_mm());
  EXPECT_LT(final.max_rotation_deg(), initial.max_rotation_deg());
  // No scan was held: the first moved off its (exact) initial pose with the rest.
  EXPECT_NE((*result)[0].model_from_sensor.matrix(), ring.initial[0].matrix());
}

TEST(MultiviewAlignmentTest, BadInitialInformationIsRefused) {
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  const Ring ring = MakeRing(1, 10.0, 40.0, 0.0, 0.0, 0.0);
  ViewScan scan = ScanOf(ring, 0);
  scan.initial_information = Matrix6d::Identity();
  (*scan.initial_information)(0, 0) = std::numeric_limits<double>::quiet_NaN();
  const auto added = aligner->Add(std::move(scan));
  ASSERT_FALSE(added.ok());
  EXPECT_EQ(added.status().field(), "scan.initial_information");
}

TEST(MultiviewAlignmentTest, AScanThatCannotBeAlignedIsReportedAndNotMerged) {
  const Ring ring = MakeRing(4, 15.0, 40.0, 0.0, 0.0, 0.0);
  MultiviewOptions options;
  options.pose_graph = false;
  auto aligner = MultiviewAligner::Create(options);
  ASSERT_TRUE(aligner.ok());
  for (size_t k = 0; k < 3; ++k) ASSERT_TRUE(aligner->Add(ScanOf(ring, k))->aligned);
  const size_t union_size = aligner->UnionPoints().size();

  // A view of the bunny whose initial pose is off by 90 degrees lands at a wrong pose with a
  // fitness above min_fitness; the size of the correction gives it away.
  ViewScan turned = ScanOf(ring, 3);
  turned.initial_model_from_sensor = RandomError(90.0, 0.0, 5) * ring.views[3].model_from_sensor;
  const auto wrong = aligner->Add(turned);
  ASSERT_TRUE(wrong.ok());
  EXPECT_FALSE(wrong->aligned);
  EXPECT_NE(wrong->reason.find("max_correction"), std::string::npos) << wrong->reason;
  EXPECT_GE(wrong->fitness, options.min_fitness);
  EXPECT_EQ(aligner->UnionPoints().size(), union_size);

  // An unrelated shape a metre away: nothing within reach.
  ViewScan elsewhere;
  for (int i = 0; i < 5000; ++i) {
    const double a = 0.001 * i, b = 0.37 * i;
    elsewhere.points.emplace_back(Eigen::Vector3f(static_cast<float>(0.05 * std::sin(a) * std::cos(b)),
                                                  static_cast<float>(0.05 * std::sin(a) * std::sin(b)),
                                                  static_cast<float>(1.0 + 0.05 * std::cos(a))));
  }
  const auto lost = aligner->Add(elsewhere);
  ASSERT_TRUE(lost.ok());
  EXPECT_FALSE(lost->aligned);
  EXPECT_NE(lost->reason.find("too_few_correspondences"), std::string::npos) << lost->reason;
  EXPECT_EQ(aligner->UnionPoints().size(), union_size);

  const auto result = aligner->Finish();
  ASSERT_TRUE(result.ok());
  ASSERT_EQ(result->size(), 5u);
  EXPECT_FALSE((*result)[3].aligned);
  EXPECT_FALSE((*result)[4].aligned);
  EXPECT_EQ((*result)[3].model_from_sensor.matrix(), turned.initial_model_from_sensor.matrix());
  EXPECT_EQ(aligner->UnionPoints().size(), union_size);
}

// Without the correction bound the same 90 degree start is accepted at a wrong pose: fitness alone
// does not tell.
TEST(MultiviewAlignmentTest, FitnessAloneWouldAcceptAWrongPose) {
  const Ring ring = MakeRing(4, 15.0, 40.0, 0.0, 0.0, 0.0);
  MultiviewOptions options;
  options.max_correction = 10.0;
  auto aligner = MultiviewAligner::Create(options);
  ASSERT_TRUE(aligner.ok());
  for (size_t k = 0; k < 3; ++k) ASSERT_TRUE(aligner->Add(ScanOf(ring, k))->aligned);
  ViewScan turned = ScanOf(ring, 3);
  turned.initial_model_from_sensor = RandomError(90.0, 0.0, 5) * ring.views[3].model_from_sensor;
  const auto wrong = aligner->Add(turned);
  ASSERT_TRUE(wrong.ok());
  EXPECT_TRUE(wrong->aligned);
  EXPECT_GT(RotationErrorDeg(wrong->model_from_sensor, ring.views[3].model_from_sensor), 10.0);
}

TEST(MultiviewAlignmentTest, TheFirstScanWithEnoughPointsIsTheAnchor) {
  const Ring ring = MakeRing(8, 15.0, 40.0, 0.0, 2.0, 0.008);
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  ViewScan few;
  few.points.assign(ring.views[0].points.begin(), ring.views[0].points.begin() + 50);
  const auto first = aligner->Add(few);
  ASSERT_TRUE(first.ok());
  EXPECT_FALSE(first->aligned);
  EXPECT_NE(first->reason.find("too few points"), std::string::npos) << first->reason;
  EXPECT_TRUE(aligner->UnionPoints().empty());

  // View 1 comes first, off by its perturbation: it keeps that pose, and view 0 is placed relative
  // to it, off by the same motion.
  ViewScan anchor = ScanOf(ring, 1);
  const auto second = aligner->Add(anchor);
  ASSERT_TRUE(second.ok());
  EXPECT_TRUE(second->aligned);
  EXPECT_EQ(second->model_from_sensor.matrix(), anchor.initial_model_from_sensor.matrix());
  EXPECT_FALSE(aligner->UnionPoints().empty());
  const Pose3 offset = ring.initial[1] * ring.views[1].model_from_sensor.inverse();
  ViewScan other = ScanOf(ring, 0);
  other.initial_model_from_sensor = RandomError(1.0, 0.003, 3) * offset * ring.views[0].model_from_sensor;
  const auto third = aligner->Add(other);
  ASSERT_TRUE(third.ok());
  ASSERT_TRUE(third->aligned) << third->reason;
  EXPECT_LT(RotationErrorDeg(third->model_from_sensor, offset * ring.views[0].model_from_sensor), 0.05);
  EXPECT_EQ(aligner->size(), 3u);
}

// The view opposite the anchor comes second, when the union holds only the anchor's side of the
// bunny; once the views between them are in, Finish's second try aligns it.
TEST(MultiviewAlignmentTest, FinishAlignsAScanThatCameTooEarly) {
  const Ring ring = MakeRing(8, 15.0, 40.0, 0.0, 2.0, 0.008);
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  const std::vector<size_t> order = {0, 4, 1, 2, 3, 5, 6, 7};
  for (size_t k : order) {
    const auto added = aligner->Add(ScanOf(ring, k));
    ASSERT_TRUE(added.ok());
    EXPECT_EQ(added->aligned, k != 4) << k << ": " << added->reason;
  }
  const auto result = aligner->Finish();
  ASSERT_TRUE(result.ok());
  const ViewAlignment& late = (*result)[1];
  ASSERT_TRUE(late.aligned) << late.reason;
  EXPECT_LT(RotationErrorDeg(late.model_from_sensor, ring.views[4].model_from_sensor), 0.05);
  EXPECT_LT(CentreErrorMm(late.model_from_sensor, ring.views[4].model_from_sensor), 0.2);
}

// The same view again and again, with fresh noise and small pose errors: the union fills the
// voxels the surface passes through (up to sqrt(3) times as many as one thinned view, plus a
// shell for the noise) and then stops growing, however many scans come.
TEST(MultiviewAlignmentTest, TheUnionStaysBoundedWhenViewsRepeat) {
  const Ring ring = MakeRing(1, 15.0, 40.0, 0.0005, 0.0, 0.0);
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  ASSERT_TRUE(aligner->Add(ScanOf(ring, 0))->aligned);
  const size_t once = aligner->UnionPoints().size();
  EXPECT_LT(once, ring.views[0].points.size() / 2) << "thinning should keep far fewer points";
  size_t last_growth = 0;
  for (uint32_t seed = 1; seed <= 12; ++seed) {
    ViewScan again;
    again.points = ScanBunny(ring.views[0].model_from_sensor, 40.0, 0.0005, 500 + seed).points;
    again.initial_model_from_sensor = RandomError(1.0, 0.003, seed) * ring.views[0].model_from_sensor;
    const size_t before = aligner->UnionPoints().size();
    ASSERT_TRUE(aligner->Add(again)->aligned);
    last_growth = aligner->UnionPoints().size() - before;
  }
  EXPECT_LT(aligner->UnionPoints().size(), 2 * once);
  EXPECT_LT(last_growth, once / 25);
}

TEST(MultiviewAlignmentTest, SameResultWhateverTheThreadCount) {
  const Ring ring = MakeRing(5, 15.0, 40.0, 0.0005, 2.0, 0.008);
  const auto run = [&](int threads) {
    tbb::task_arena arena(threads);
    return arena.execute([&] { return AlignRing(ring, MultiviewOptions{}); });
  };
  const std::vector<ViewAlignment> one = run(1);
  const std::vector<ViewAlignment> two = run(2);
  ASSERT_EQ(one.size(), two.size());
  for (size_t k = 0; k < one.size(); ++k) {
    EXPECT_EQ(one[k].model_from_sensor.matrix(), two[k].model_from_sensor.matrix()) << k;
    EXPECT_EQ(one[k].fitness, two[k].fitness) << k;
  }
}

TEST(MultiviewAlignmentTest, RejectsBadOptionsNamingTheField) {
  const auto field_of = [](const MultiviewOptions& options) {
    const auto aligner = MultiviewAligner::Create(options);
    EXPECT_FALSE(aligner.ok());
    if (aligner.ok()) return std::string();
    EXPECT_EQ(aligner.status().code(), StatusCode::kInvalidArgument);
    return aligner.status().field();
  };
  for (double voxel : {0.0, -0.002, std::nan("")}) {
    MultiviewOptions options;
    options.voxel_size = voxel;
    EXPECT_EQ(field_of(options), "alignment.voxel_size") << voxel;
  }
  MultiviewOptions options;
  options.min_fitness = 1.5;
  EXPECT_EQ(field_of(options), "alignment.min_fitness");
  options = {};
  options.min_pair_overlap = -0.1;
  EXPECT_EQ(field_of(options), "alignment.min_pair_overlap");
  options = {};
  options.max_correction = std::nan("");
  EXPECT_EQ(field_of(options), "alignment.max_correction");
  options = {};
  options.icp.max_iterations = 0;
  EXPECT_EQ(field_of(options), "icp.max_iterations");
  options = {};
  options.icp.max_correspondence_distance = std::nan("");
  EXPECT_EQ(field_of(options), "icp.max_correspondence_distance");
}

TEST(MultiviewAlignmentTest, CancelReturnsCancelledAndKeepsTheScansAdded) {
  const Ring ring = MakeRing(2, 15.0, 40.0, 0.0, 2.0, 0.008);
  auto aligner = MultiviewAligner::Create(MultiviewOptions{});
  ASSERT_TRUE(aligner.ok());
  const std::atomic<bool> cancel{true};
  ASSERT_TRUE(aligner->Add(ScanOf(ring, 0)).ok());
  const auto added = aligner->Add(ScanOf(ring, 1), &cancel);
  ASSERT_FALSE(added.ok());
  EXPECT_EQ(added.status().code(), StatusCode::kCancelled);
  EXPECT_EQ(aligner->size(), 1u);
  ASSERT_TRUE(aligner->Add(ScanOf(ring, 1)).ok());
  const auto finished = aligner->Finish(&cancel);
  ASSERT_FALSE(finished.ok());
  EXPECT_EQ(finished.status().code(), StatusCode::kCancelled);
  const auto again = aligner->Finish();
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->size(), 2u);
}

}  // namespace
}  // namespace vscan::registration
