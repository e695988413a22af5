// Multiview alignment of ray-cast views of the bunny all around it (0.3 mm noise, initial poses
// 1 degree and 5 mm off): the time of each Add and of Finish (pose graph on), the union's size and
// the final errors against the true poses. Usage: multiview_bench [rows] [width height], where the
// views are rows rings of 24 at elevations 20, 45, 0, -20 degrees (default 1 ring of 720 x 540,
// about 100k points a view). A last Add of a 1280 x 960 view (about 300k points) is timed too.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bench_meshes.h"
#include "raycast/scanner.h"
#include "registration/multiview_alignment.h"

namespace vscan::bench {
namespace {

constexpr int kViewsPerRing = 24;
constexpr double kElevations[] = {20.0, 45.0, 0.0, -20.0};
constexpr double kDistance = 0.35;
constexpr double kFovDeg = 40.0;
constexpr double kNoise = 0.0003;
constexpr double kDeg = std::numbers::pi / 180.0;

struct Bunny {
  std::shared_ptr<const raycast::RaycastScene> scene;
  Eigen::Vector3d centre;
};

double Ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

Pose3 ViewAround(const Bunny& bunny, double azimuth_deg, double elevation_deg) {
  const double a = azimuth_deg * kDeg, e = elevation_deg * kDeg;
  const Eigen::Vector3d direction(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  return PoseFromLookAt(bunny.centre + kDistance * direction, bunny.centre, Eigen::Vector3d::UnitY(), "view").value();
}

std::vector<Eigen::Vector3f> Scan(const Bunny& bunny, const Pose3& pose, uint32_t width, uint32_t height,
                                  uint32_t seed) {
  raycast::ScanOptions options;
  options.fields = kFieldPosition;
  options.frame = raycast::ScanFrame::kSensor;
  const auto camera = sensor::CameraFromFov(width, height, kFovDeg, 0.05, 2.0);
  std::vector<Eigen::Vector3f> points = raycast::Scan(*bunny.scene, camera, pose, options).value().positions;
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(kNoise));
  for (auto& p : points) p += Eigen::Vector3f(noise(rng), noise(rng), noise(rng));
  return points;
}

Pose3 InitialError(const Bunny& bunny, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector3d axis(g(rng), g(rng), g(rng)), shift(g(rng), g(rng), g(rng));
  Pose3 error = RotationAboutLine(bunny.centre, axis, 1.0 * kDeg);
  error.translation() += 0.005 * shift.normalized();
  return error;
}

// The largest rotation error (radians) and error at the bunny's centre (metres) over the views.
std::pair<double, double> MaxErrors(const Bunny& bunny, const std::vector<Pose3>& poses,
                                    const std::vector<Pose3>& truth) {
  double rotation = 0.0, centre = 0.0;
  for (size_t k = 0; k < truth.size(); ++k) {
    rotation = std::max(rotation, Eigen::AngleAxisd(poses[k].linear().transpose() * truth[k].linear()).angle());
    centre = std::max(centre, (poses[k] * (truth[k].inverse() * bunny.centre) - bunny.centre).norm());
  }
  return {rotation, centre};
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

int Main(int rows, uint32_t width, uint32_t height) {
  const auto mesh = std::make_shared<const TriangleMesh>(
      ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"));
  Eigen::AlignedBox3d box;
  for (const auto& v : mesh->vertices) box.extend(v.cast<double>());
  raycast::SceneInstance instance;
  instance.mesh = mesh;
  auto scene = raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1));
  if (!scene.ok()) {
    std::fprintf(stderr, "multiview_bench: %s\n", scene.status().ToString().c_str());
    return 1;
  }
  const Bunny bunny{*scene, box.center()};

  std::vector<Pose3> truth;
  std::vector<std::vector<Eigen::Vector3f>> views;
  for (int row = 0; row < rows; ++row) {
    for (int k = 0; k < kViewsPerRing; ++k) {
      const double azimuth = 360.0 * (k + 0.5 * row) / kViewsPerRing;
      truth.push_back(ViewAround(bunny, azimuth, kElevations[row]));
      views.push_back(Scan(bunny, truth.back(), width, height, static_cast<uint32_t>(truth.size())));
    }
  }
  size_t total_points = 0;
  for (const auto& v : views) total_points += v.size();

  auto aligner = registration::MultiviewAligner::Create(registration::MultiviewOptions{}).value();
  std::vector<double> add_ms;
  std::vector<Pose3> added_poses;
  for (size_t k = 0; k < views.size(); ++k) {
    registration::ViewScan scan;
    scan.points = views[k];
    scan.initial_model_from_sensor = k == 0 ? truth[k] : InitialError(bunny, static_cast<uint32_t>(k)) * truth[k];
    const auto start = std::chrono::steady_clock::now();
    const auto added = aligner.Add(std::move(scan));
    add_ms.push_back(Ms(start));
    added_poses.push_back(added.ok() ? added->model_from_sensor : Pose3::Identity());
    if (!added.ok() || !added->aligned) {
      std::fprintf(stderr, "view %zu: %s\n", k, added.ok() ? added->reason.c_str() : added.status().ToString().c_str());
    }
  }
  const size_t union_before = aligner.UnionPoints().size();
  auto start = std::chrono::steady_clock::now();
  const auto finished = aligner.Finish();
  const double finish_ms = Ms(start);
  if (!finished.ok()) {
    std::fprintf(stderr, "finish: %s\n", finished.status().ToString().c_str());
    return 1;
  }
  std::vector<Pose3> final_poses;
  for (const auto& a : *finished) final_poses.push_back(a.model_from_sensor);
  const auto [add_rotation, add_centre] = MaxErrors(bunny, added_poses, truth);
  const auto [final_rotation, final_centre] = MaxErrors(bunny, final_poses, truth);

  const Pose3 big_pose = ViewAround(bunny, 7.0, 30.0);
  registration::ViewScan big;
  big.points = Scan(bunny, big_pose, 1280, 960, 999);
  const size_t big_points = big.points.size();
  big.initial_model_from_sensor = InitialError(bunny, 999) * big_pose;
  start = std::chrono::steady_clock::now();
  const auto big_added = aligner.Add(std::move(big));
  const double big_ms = Ms(start);

  std::printf("multiview: %zu views of %ux%u, %.0fk points a view on average\n", views.size(), width, height,
              static_cast<double>(total_points) / static_cast<double>(views.size()) / 1000.0);
  std::printf("  Add: median %.1f ms, max %.1f ms, total %.0f ms; union %zu points\n", Median(add_ms),
              *std::max_element(add_ms.begin(), add_ms.end()),
              std::accumulate(add_ms.begin(), add_ms.end(), 0.0), union_before);
  std::printf("  Finish (pose graph): %.0f ms\n", finish_ms);
  std::printf("  max errors after Add: rotation %.4f deg, at the bunny's centre %.4f mm\n", add_rotation / kDeg,
              add_centre * 1000.0);
  std::printf("  max errors after Finish: rotation %.4f deg, at the bunny's centre %.4f mm\n", final_rotation / kDeg,
              final_centre * 1000.0);
  std::printf("  Add of one %zuk-point view after them: %.1f ms (%s)\n", big_points / 1000, big_ms,
              big_added.ok() && big_added->aligned ? "aligned" : "not aligned");
  return 0;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  const int rows = argc > 1 ? std::clamp(std::atoi(argv[1]), 1, 4) : 1;
  const auto width = static_cast<uint32_t>(argc > 3 ? std::atoi(argv[2]) : 720);
  const auto height = static_cast<uint32_t>(argc > 3 ? std::atoi(argv[3]) : 540);
  return vscan::bench::Main(rows, width, height);
}
