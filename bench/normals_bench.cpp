// Normal estimation (k = 16) on one scan-like cloud: vscan's EstimateNormals against PCL's
// NormalEstimationOMP on 2 threads, index build included for both, with their agreement.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include "normals/normal_estimation.h"

namespace vscan::bench {
namespace {

constexpr int kK = 16;
constexpr int kPclThreads = 2;

// A 640x480 range image of a bumpy surface about 1 m in front of a pinhole camera at the origin,
// with 0.3 mm range noise: 307,200 points laid out as a scanner delivers them.
const std::vector<Eigen::Vector3f>& ScanCloud() {
  static const std::vector<Eigen::Vector3f> cloud = [] {
    constexpr int kWidth = 640, kHeight = 480;
    constexpr double kFocal = 600.0;
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(0.0, 0.0003);
    std::vector<Eigen::Vector3f> points;
    points.reserve(kWidth * kHeight);
    for (int v = 0; v < kHeight; ++v) {
      for (int u = 0; u < kWidth; ++u) {
        const Eigen::Vector3d ray((u - kWidth / 2 + 0.5) / kFocal, (v - kHeight / 2 + 0.5) / kFocal, 1.0);
        const double depth = 1.0 + 0.04 * std::sin(9.0 * ray.x()) * std::cos(7.0 * ray.y()) +
                             0.01 * std::sin(31.0 * ray.x() + 17.0 * ray.y()) + 0.3 * ray.x() + noise(rng);
        points.push_back((depth * ray).cast<float>());
      }
    }
    return points;
  }();
  return cloud;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr PclCloud() {
  static const auto cloud = [] {
    auto c = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (const auto& p : ScanCloud()) c->push_back({p.x(), p.y(), p.z()});
    return c;
  }();
  return cloud;
}

std::vector<Eigen::Vector3f> Ours() {
  auto normals = normals::EstimateNormals(ScanCloud(), {.k = kK});
  if (!normals.ok()) {
    std::fprintf(stderr, "bench: %s\n", normals.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(normals).value();
}

pcl::PointCloud<pcl::Normal> Pcl() {
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimator(kPclThreads);
  estimator.setInputCloud(PclCloud());
  estimator.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  estimator.setKSearch(kK);
  pcl::PointCloud<pcl::Normal> normals;
  estimator.compute(normals);  // builds the kd-tree over the input first
  return normals;
}

void BM_Normals_Vscan(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Ours());
  state.counters["points"] = static_cast<double>(ScanCloud().size());
}

void BM_Normals_PclOmp2(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Pcl());
  state.counters["points"] = static_cast<double>(ScanCloud().size());
}

BENCHMARK(BM_Normals_Vscan)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Normals_PclOmp2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Mean and largest angle between the two results, ignoring sign (both orient to the origin).
void ReportAgreement() {
  const auto ours = Ours();
  const auto pcl = Pcl();
  double sum = 0.0, worst = 0.0;
  size_t compared = 0;
  for (size_t i = 0; i < ours.size(); ++i) {
    const Eigen::Vector3f theirs = pcl[i].getNormalVector3fMap();
    if (!ours[i].allFinite() || !theirs.allFinite()) continue;
    // In double and via atan2: acos of a float dot product cannot resolve angles below ~0.03 deg.
    const Eigen::Vector3d a = ours[i].cast<double>(), b = theirs.cast<double>();
    const double deg = std::atan2(a.cross(b).norm(), std::abs(a.dot(b))) * 180.0 / std::numbers::pi;
    sum += deg;
    worst = std::max(worst, deg);
    ++compared;
  }
  std::printf("agreement: %zu of %zu points compared, mean %.2e deg, max %.2e deg\n", compared, ours.size(),
              compared ? sum / static_cast<double>(compared) : 0.0, worst);
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  vscan::bench::ReportAgreement();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
