// Alignment without a known pose on the registration reference pair (data/registration, 100k
// points each) at the default options: the pair as it is (5 degrees apart), the source turned by
// 150 degrees, and a sweep of seeded random turns. Prints the median wall and processor time of a
// few runs (processor time summed over threads, which a busy machine inflates less than the wall
// time), what the result found and its error against the known transform.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "random/seeded_draws.h"
#include "registration/feature_alignment.h"
#include "vscan/common/cloud_io.h"

namespace vscan::bench {
namespace {

constexpr int kRuns = 5;
constexpr int kSweepTurns = 12;
constexpr double kDeg = std::numbers::pi / 180.0;
const std::string kDir = std::string(VSCAN_DATA_DIR) + "/registration/";

struct Pair {
  std::vector<Eigen::Vector3f> source, target;
  Pose3 target_from_source = Pose3::Identity();
};

bool Load(Pair& pair) {
  StatusOr<PointCloud> source = ReadPcd(kDir + "src_100k.pcd");
  StatusOr<PointCloud> target = ReadPcd(kDir + "tgt_100k.pcd");
  std::ifstream in(kDir + "T_gt_src_from_tgt.txt");
  Eigen::Matrix4d source_from_target;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) in >> source_from_target(r, c);
  }
  if (!source.ok() || !target.ok() || !in) {
    std::printf("feature_alignment_bench: cannot read the pair in %s\n", kDir.c_str());
    return false;
  }
  pair.source = std::move(source->positions);
  pair.target = std::move(target->positions);
  pair.target_from_source = Pose3(source_from_target).inverse();
  return true;
}

Pose3 Turn(double angle_deg, const Eigen::Vector3d& axis, const Eigen::Vector3d& shift) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(angle_deg * kDeg, axis.normalized()).toRotationMatrix();
  pose.translation() = shift;
  return pose;
}

std::vector<Eigen::Vector3f> Moved(const std::vector<Eigen::Vector3f>& points, const Pose3& pose) {
  std::vector<Eigen::Vector3f> moved;
  moved.reserve(points.size());
  for (const auto& p : points) moved.push_back((pose * p.cast<double>()).cast<float>());
  return moved;
}

double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

double TranslationErrorMm(const Pose3& a, const Pose3& b) {
  return (a.translation() - b.translation()).norm() * 1000.0;
}

struct Timed {
  registration::FeatureAlignmentResult result;
  double seconds = 0;
  double cpu_seconds = 0;
};

bool AlignOnce(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target, Timed& out) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  auto result = registration::AlignByFeatures(source, target, registration::FeatureAlignmentOptions{});
  out.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!result.ok()) {
    std::printf("feature_alignment_bench: %s\n", result.status().ToString().c_str());
    return false;
  }
  out.result = std::move(*result);
  return true;
}

void PrintOutcome(const char* label, const Timed& run, const Pose3& truth) {
  const auto& r = run.result;
  std::printf(
      "%-16s found %-3s keypoints %zu/%zu matches %zu inliers %zu fitness %.3f  "
      "error %.4f deg %.3f mm%s%s\n",
      label, r.found ? "yes" : "no", r.keypoints_source, r.keypoints_target, r.matches, r.inliers, r.fitness,
      RotationErrorDeg(r.target_from_source, truth), TranslationErrorMm(r.target_from_source, truth),
      r.found ? "" : "  reason: ", r.reason.c_str());
}

void TimeCase(const char* label, const Pair& pair, const Pose3& motion) {
  const std::vector<Eigen::Vector3f> source = Moved(pair.source, motion);
  const Pose3 truth = pair.target_from_source * motion.inverse();
  std::vector<double> seconds, cpu_seconds;
  Timed run;
  for (int i = 0; i < kRuns; ++i) {
    if (!AlignOnce(source, pair.target, run)) return;
    seconds.push_back(run.seconds);
    cpu_seconds.push_back(run.cpu_seconds);
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(cpu_seconds.begin(), cpu_seconds.end());
  std::printf("%-16s median %.3f s wall (min %.3f, max %.3f), %.3f s processor, %d runs\n", label,
              seconds[seconds.size() / 2], seconds.front(), seconds.back(), cpu_seconds[cpu_seconds.size() / 2], kRuns);
  PrintOutcome(label, run, truth);
}

// Uniformly drawn axes, angles in [0, 180) degrees, shifts up to 10 cm: how many are found and the
// worst error of those found.
void Sweep(const Pair& pair) {
  random::SplitMix64Stream draws(2024);
  int found = 0;
  double worst_deg = 0, worst_mm = 0, total_seconds = 0;
  for (int turn = 0; turn < kSweepTurns; ++turn) {
    Eigen::Vector3d axis;
    do {
      axis = Eigen::Vector3d(draws.Uniform(), draws.Uniform(), draws.Uniform()) * 2.0 - Eigen::Vector3d::Ones();
    } while (axis.norm() > 1.0 || axis.norm() < 0.1);
    const Eigen::Vector3d shift =
        (Eigen::Vector3d(draws.Uniform(), draws.Uniform(), draws.Uniform()) * 2.0 - Eigen::Vector3d::Ones()) * 0.1;
    const Pose3 motion = Turn(180.0 * draws.Uniform(), axis, shift);
    Timed run;
    if (!AlignOnce(Moved(pair.source, motion), pair.target, run)) return;
    total_seconds += run.seconds;
    const Pose3 truth = pair.target_from_source * motion.inverse();
    if (!run.result.found) {
      PrintOutcome(("turn " + std::to_string(turn)).c_str(), run, truth);
      continue;
    }
    ++found;
    worst_deg = std::max(worst_deg, RotationErrorDeg(run.result.target_from_source, truth));
    worst_mm = std::max(worst_mm, TranslationErrorMm(run.result.target_from_source, truth));
  }
  std::printf("sweep            found %d of %d random turns, worst error %.4f deg %.3f mm, mean %.3f s\n", found,
              kSweepTurns, worst_deg, worst_mm, total_seconds / kSweepTurns);
}

}  // namespace
}  // namespace vscan::bench

int main() {
  using namespace vscan::bench;
  Pair pair;
  if (!Load(pair)) return 0;
  TimeCase("as given", pair, vscan::Pose3::Identity());
  TimeCase("turned 150 deg", pair, Turn(150.0, {0.4, -0.3, 0.85}, {0.05, 0.0, 0.0}));
  Sweep(pair);
  return 0;
}
