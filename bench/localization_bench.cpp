// The baseline localizer against PCL's FPFH + SampleConsensusPrerejective + ICP pipeline on the
// same generated scans of angle blocks lying on a floor, clean and with the phoxi-m-class noise:
// time per scan (median and range over the runs) and the BOP recalls of what each finds.
// Usage: localization_bench [runs=3]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "capture/measure_scan.h"
#include "localization/baseline_localizer.h"
#include "localization/bop_scoring.h"
#include "localization/model_samples.h"
#include "localization_pcl.h"
#include "parts_scene.h"
#include "raycast/raycast_scene.h"
#include "sensor/presets.h"

namespace vscan::bench {
namespace {

using localization::testing::FixturePart;

constexpr double kFloorSide = 0.4;
constexpr uint32_t kWidth = 1032, kHeight = 772;  // the PhoXi family's half-resolution mode
constexpr size_t kPartsPerScene = 6;
constexpr uint64_t kScenes = 4;  // seeds 1 to 4
constexpr size_t kModelSamples = 20000;

struct Scene {
  std::vector<localization::TrueInstance> truth;
  std::vector<Eigen::Vector3f> points;  // world frame, no normals
};

struct Outcome {
  std::vector<double> seconds_per_scan;  // one per run
  size_t valid = 0, correct = 0;
  double mssd_ar_sum = 0;
  size_t scans = 0;
};

template <typename T>
T OrDie(StatusOr<T> value) {
  if (!value.ok()) {
    std::fprintf(stderr, "localization_bench: %s\n", value.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(*value);
}

Scene MakeScene(uint64_t seed, const capture::MeasurementSpec* noise) {
  const auto placed = localization::testing::LyingParts({{FixturePart::kAngleBlock, kPartsPerScene}}, kFloorSide, seed);
  Scene scene;
  for (const auto& p : placed) scene.truth.push_back({1, p.world_from_part, 1.0});
  const auto cast = OrDie(raycast::RaycastScene::Build(localization::testing::FloorInstances(placed, kFloorSide)));
  const auto camera = sensor::CameraFromFov(kWidth, kHeight, 50, 0.05, 4 * kFloorSide);
  const Pose3 sensor = localization::testing::FloorSensorPose(kFloorSide);
  PointCloud cloud;
  if (noise == nullptr) {
    raycast::ScanOptions options;
    options.fields = kFieldPosition;
    cloud = OrDie(raycast::Scan(*cast, camera, sensor, options));
  } else {
    cloud = OrDie(capture::ScanMeasured(*cast, camera, sensor, *noise, raycast::ScanFrame::kWorld, nullptr, nullptr,
                                        nullptr));
  }
  scene.points = std::move(cloud.positions);
  return scene;
}

using Localize = std::function<std::vector<localization::EstimatedInstance>(const Scene&)>;

Outcome Measure(const std::vector<Scene>& scenes, const Localize& localize, int runs) {
  const std::vector<localization::PartDefinition> parts{
      {1, localization::testing::LoadPart(FixturePart::kAngleBlock)->vertices, {}}};
  Outcome outcome;
  for (int run = 0; run < runs; ++run) {
    double seconds = 0;
    for (const Scene& scene : scenes) {
      const auto start = std::chrono::steady_clock::now();
      const auto estimates = localize(scene);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (run > 0) continue;  // the recalls do not change between runs
      const auto score = OrDie(localization::ScoreScan(parts, scene.truth, estimates));
      outcome.valid += score.valid_instances;
      outcome.correct += score.parts[0].add_correct;
      outcome.mssd_ar_sum += score.mssd_average_recall.value_or(0);
      ++outcome.scans;
    }
    outcome.seconds_per_scan.push_back(seconds / static_cast<double>(scenes.size()));
  }
  return outcome;
}

void Print(const char* condition, const char* method, Outcome o) {
  std::sort(o.seconds_per_scan.begin(), o.seconds_per_scan.end());
  std::printf("| %s | %s | %.2f | %.2f-%.2f | %zu/%zu = %.2f | %.2f |\n", condition, method,
              o.seconds_per_scan[o.seconds_per_scan.size() / 2], o.seconds_per_scan.front(), o.seconds_per_scan.back(),
              o.correct, o.valid, static_cast<double>(o.correct) / static_cast<double>(o.valid),
              o.mssd_ar_sum / static_cast<double>(o.scans));
}

int Main(int runs) {
  const sensor::SensorPreset* preset = sensor::FindSensorPreset("phoxi-m-class");
  if (preset == nullptr) {
    std::fprintf(stderr, "localization_bench: no phoxi-m-class preset\n");
    return 1;
  }
  capture::MeasurementSpec noisy;
  noisy.noise = preset->noise;
  noisy.fields = kFieldPosition;
  noisy.seed = 7;

  const TriangleMesh& part = *localization::testing::LoadPart(FixturePart::kAngleBlock);
  const localization::ModelSamples samples = localization::SampleModel(part, kModelSamples, 1);
  const Eigen::Vector3f viewpoint = localization::testing::FloorSensorPose(kFloorSide).translation().cast<float>();
  localization::LocalizerOptions options;
  options.viewpoint = viewpoint.cast<double>();
  options.max_instances = kPartsPerScene + 2;
  Eigen::Vector3f lo, hi;
  part.Bounds(lo, hi);
  const double voxel = static_cast<double>((hi - lo).norm()) / 50;

  const Localize baseline = [&](const Scene& scene) {
    const auto found = OrDie(localization::LocalizeInstances(part, scene.points, {}, options));
    std::vector<localization::EstimatedInstance> estimates;
    for (const auto& i : found.instances) estimates.push_back({1, i.world_from_part, i.score});
    return estimates;
  };
  const Localize pcl_peer = [&](const Scene& scene) {
    std::vector<localization::EstimatedInstance> estimates;
    for (const auto& i : PclLocalize(samples.points, samples.normals, scene.points, viewpoint, voxel,
                                     options.max_instances)) {
      estimates.push_back({1, i.world_from_part, i.score});
    }
    return estimates;
  };

  std::printf("%llu scenes of %zu angle blocks on a %.2f m floor, %ux%u, %d runs; ADD at 10%% of the diameter\n",
              static_cast<unsigned long long>(kScenes), kPartsPerScene, kFloorSide, kWidth, kHeight, runs);
  std::printf("| scans | method | s/scan median | s/scan range | ADD recall | MSSD AR |\n|---|---|---|---|---|---|\n");
  for (const bool with_noise : {false, true}) {
    std::vector<Scene> scenes;
    for (uint64_t seed = 1; seed <= kScenes; ++seed) scenes.push_back(MakeScene(seed, with_noise ? &noisy : nullptr));
    const char* condition = with_noise ? "phoxi-m-class noise" : "clean";
    Print(condition, "vscan baseline (PPF + ICP)", Measure(scenes, baseline, runs));
    Print(condition, "PCL FPFH + SAC-IA prerejective + ICP", Measure(scenes, pcl_peer, runs));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) { return vscan::bench::Main(argc > 1 ? std::max(1, std::atoi(argv[1])) : 3); }
