// Alignment without a pose on scans of procedural machined parts (large flat faces: a bracket with
// a riser, a stepped block, an irregular seven-sided prism; tests/unit/registration/machined_parts),
// against Open3D's FPFH + RANSAC + point-to-plane ICP on the same scans in the same run.
// Each pair: two 640 x 480 ray-cast scans (45 degrees across, sensor frame, 0.3 mm Gaussian noise
// per coordinate) from random views at 0.35 m from above (elevations 10-80 degrees: the part rests
// on a table, and its plain underside alone fits many poses) that overlap by at least half (each
// way), the source moved by a random rotation (uniform) and shift (up to 0.2 m). A pair succeeds
// within 0.1 degrees and 0.5 mm at the part (the centroid of the source's points).
// Usage: machined_alignment_bench [pairs per part, default 20]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "feature_alignment_open3d.h"
#include "machined_parts.h"
#include "registration/feature_alignment.h"
#include "spatial/kd_tree.h"

namespace vscan::bench {
namespace {

using registration::testing::MachinedPart;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kNoise = 0.0003;
constexpr double kDistance = 0.35;
constexpr double kVoxel = 0.002;
constexpr double kMinOverlap = 0.5;
constexpr double kOverlapReach = 0.002;
constexpr double kMaxDeg = 0.1;
constexpr double kMaxMm = 0.5;

std::vector<Eigen::Vector3f> Moved(const std::vector<Eigen::Vector3f>& points, const Pose3& pose) {
  std::vector<Eigen::Vector3f> moved;
  moved.reserve(points.size());
  for (const auto& p : points) moved.push_back((pose * p.cast<double>()).cast<float>());
  return moved;
}

// The share of `from` within kOverlapReach of `to` (both world frame).
double Overlap(const std::vector<Eigen::Vector3f>& from, const std::vector<Eigen::Vector3f>& to) {
  const spatial::KdTree tree(to);
  size_t near = 0;
  const auto reach_sq = static_cast<float>(kOverlapReach * kOverlapReach);
  for (const auto& p : from) near += tree.NearestTwo(p, reach_sq)[0].slot != spatial::KdTree::kNoSlot ? 1 : 0;
  return from.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(from.size());
}

struct Pair {
  std::vector<Eigen::Vector3f> source, target;  // source moved; target in its sensor frame
  Pose3 truth = Pose3::Identity();              // target_from_source
  Pose3 source_from_sensor = Pose3::Identity(); // the random motion
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double overlap = 0;
};

Pair DrawPair(const MachinedPart& part, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  for (;;) {
    const double azimuth = 360.0 * unit(rng), elevation = 15.0 + 55.0 * unit(rng);
    const Pose3 world_from_a = registration::testing::ViewOfPart(azimuth, elevation, kDistance);
    const Pose3 world_from_b = registration::testing::ViewOfPart(azimuth + 90.0 * (unit(rng) - 0.5),
                                                                 std::clamp(elevation + 40.0 * (unit(rng) - 0.5), 10.0, 80.0),
                                                                 kDistance);
    const auto seed = static_cast<uint32_t>(rng());
    const std::vector<Eigen::Vector3f> a = registration::testing::ScanPart(part, world_from_a, kNoise, seed);
    const std::vector<Eigen::Vector3f> b = registration::testing::ScanPart(part, world_from_b, kNoise, seed + 1);
    const std::vector<Eigen::Vector3f> a_world = Moved(a, world_from_a), b_world = Moved(b, world_from_b);
    const double overlap = std::min(Overlap(a_world, b_world), Overlap(b_world, a_world));
    if (a.size() < 2000 || b.size() < 2000 || overlap < kMinOverlap) continue;
    Pair pair;
    const Eigen::Quaterniond q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
    pair.source_from_sensor.linear() = q.toRotationMatrix();
    pair.source_from_sensor.translation() = 0.2 * unit(rng) * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    pair.source = Moved(a, pair.source_from_sensor);
    pair.target = b;
    pair.truth = world_from_b.inverse() * world_from_a * pair.source_from_sensor.inverse();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& p : pair.source) sum += p.cast<double>();
    pair.centre = sum / static_cast<double>(pair.source.size());
    pair.overlap = overlap;
    return pair;
  }
}

struct Tally {
  std::string name;
  int tried = 0, succeeded = 0, found = 0;
  std::vector<double> deg, mm, seconds;

  void Add(const Pair& pair, bool was_found, const Pose3& estimate, double s) {
    ++tried;
    found += was_found ? 1 : 0;
    const double d = Eigen::AngleAxisd(estimate.linear().transpose() * pair.truth.linear()).angle() / kDeg;
    const double m = (estimate * pair.centre - pair.truth * pair.centre).norm() * 1000.0;
    deg.push_back(d);
    mm.push_back(m);
    seconds.push_back(s);
    succeeded += was_found && d < kMaxDeg && m < kMaxMm ? 1 : 0;
  }
};

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

void Print(const std::string& part, const Tally& t) {
  std::printf("%-18s %-34s success %3d/%-3d (%5.1f%%)  found %3d  median %.4f deg %.3f mm (p90 %.4f deg %.3f mm)  "
              "time median %.3f s (p10 %.3f, p90 %.3f)\n",
              part.c_str(), t.name.c_str(), t.succeeded, t.tried, 100.0 * t.succeeded / std::max(t.tried, 1), t.found,
              Quantile(t.deg, 0.5), Quantile(t.mm, 0.5), Quantile(t.deg, 0.9), Quantile(t.mm, 0.9),
              Quantile(t.seconds, 0.5), Quantile(t.seconds, 0.1), Quantile(t.seconds, 0.9));
}

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan::bench;
  using namespace vscan;
  const int pairs_per_part = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  std::mt19937 rng(2026);
  std::vector<Tally> total = {{"vscan, no viewpoints (both signs)"}, {"vscan, sensor viewpoints"}, {"Open3D FPFH+RANSAC+ICP"}};
  for (int which = 0; which < registration::testing::kMachinedParts; ++which) {
    const registration::testing::MachinedPart part = registration::testing::MakeMachinedPart(which);
    std::vector<Tally> tallies = {{total[0].name}, {total[1].name}, {total[2].name}};
    for (int n = 0; n < pairs_per_part; ++n) {
      const Pair pair = DrawPair(part, rng);
      for (int mode = 0; mode < 2; ++mode) {
        registration::FeatureAlignmentOptions options;
        options.voxel_size = kVoxel;
        if (mode == 1) {
          options.source_viewpoint = pair.source_from_sensor.translation().cast<float>();
          options.target_viewpoint = Eigen::Vector3f::Zero();
        }
        const auto start = std::chrono::steady_clock::now();
        const auto result = registration::AlignByFeatures(pair.source, pair.target, options);
        const double seconds = Since(start);
        if (!result.ok()) {
          std::printf("machined_alignment_bench: %s\n", result.status().ToString().c_str());
          return 1;
        }
        tallies[static_cast<size_t>(mode)].Add(pair, result->found, result->target_from_source, seconds);
        if (!result->found) std::printf("  %s pair %d (overlap %.2f) %s: %s\n", part.name.c_str(), n, pair.overlap,
                                        mode == 0 ? "both signs" : "viewpoints", result->reason.c_str());
      }
      if (Open3dAvailable()) {
        const auto start = std::chrono::steady_clock::now();
        const Open3dAlignment peer = AlignWithOpen3d(pair.source, pair.target, kVoxel);
        tallies[2].Add(pair, peer.fitness > 0, peer.target_from_source, Since(start));
      }
    }
    for (size_t t = 0; t < tallies.size(); ++t) {
      if (tallies[t].tried == 0) continue;
      Print(part.name, tallies[t]);
      total[t].tried += tallies[t].tried;
      total[t].succeeded += tallies[t].succeeded;
      total[t].found += tallies[t].found;
      for (double v : tallies[t].deg) total[t].deg.push_back(v);
      for (double v : tallies[t].mm) total[t].mm.push_back(v);
      for (double v : tallies[t].seconds) total[t].seconds.push_back(v);
    }
  }
  for (const Tally& t : total) {
    if (t.tried > 0) Print("all parts", t);
  }
  return 0;
}
