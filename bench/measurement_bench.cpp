// Cost of the measurement model against the clean ray-cast scan it starts from, on the bunny grid
// at 1280x1024: medians of repeated runs, printed in ms and as a percentage of the clean scan.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "bench_meshes.h"
#include "measured_scan.h"
#include "capture/measure_scan.h"
#include "raycast/scanner.h"

namespace vscan::bench {
namespace {

constexpr uint32_t kWidth = 1280, kHeight = 1024;
constexpr int kCopies = 10;
constexpr int kRuns = 15;

double MedianMs(const std::function<size_t()>& run, size_t* points) {
  std::vector<double> ms;
  for (int i = 0; i < kRuns; ++i) {
    const auto start = std::chrono::steady_clock::now();
    *points = run();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(ms.begin(), ms.begin() + kRuns / 2, ms.end());
  return ms[kRuns / 2];
}

int Main(const char* only) {
  const TriangleMesh bunny = ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
  const BunnyGrid grid = MakeBunnyGrid(bunny, kCopies, kWidth, kHeight);
  auto built = raycast::RaycastScene::Build(grid.instances);
  if (!built.ok()) {
    std::fprintf(stderr, "bench: %s\n", built.status().ToString().c_str());
    return 1;
  }
  const raycast::RaycastScene& scene = **built;

  const auto clean = [&] {
    raycast::ScanOptions options;
    options.fields = kFieldsDefault;
    return raycast::Scan(scene, grid.camera, grid.world_from_sensor, options)->size();
  };
  const auto measured = [&](capture::MeasurementSpec spec) {
    return MeasuredScan(scene, grid.camera, grid.world_from_sensor, std::move(spec));
  };

  capture::MeasurementSpec spec;
  spec.fields = kFieldsDefault;
  spec.seed = 1;
  spec.noise.sigma_a = 0.0005;
  spec.noise.sigma_c = 0.002;
  spec.noise.along_ray = true;
  const capture::MeasurementSpec noise = spec;
  spec.distortion.k1 = 0.05;
  spec.distortion.p1 = 0.001;
  const capture::MeasurementSpec distortion = spec;
  spec.outliers = {0.01, 5, 0.002};
  const capture::MeasurementSpec outliers = spec;
  spec.grazing_limit_deg = 75;
  spec.flying_pixels.enabled = true;
  const capture::MeasurementSpec grazing_flying = spec;
  spec.fields |= kFieldsGroundTruth;
  const capture::MeasurementSpec ground_truth = spec;
  spec.fields |= kFieldEstimatedNormal;
  const capture::MeasurementSpec estimated = spec;
  // A projector 20 cm beside the camera with the camera's field: one shadow ray per hit.
  capture::MeasurementSpec structured = noise;
  sensor::StructuredLight projector;
  projector.camera = grid.camera;
  projector.projector_offset = Eigen::Vector3d(0.2, 0, 0);
  structured.structured_light = projector;

  // The same noise with the returned light (docs/SENSORS.md): a ToF-like emitter at the camera,
  // the copies alternately machined aluminium and black ABS, and the noise following the signal.
  capture::MeasurementSpec lit = noise;
  capture::ReturnedLightSpec light;
  light.emitter.radiant_intensity_w_per_sr = 0.05;
  light.pixel.gain_e = capture::CameraPixelGain(grid.camera, sensor::PinholePixel{});
  light.reference_e = 5000;
  for (const raycast::SceneInstance& instance : grid.instances) {
    if (light.materials.size() <= instance.instance_id) light.materials.resize(instance.instance_id + 1);
    light.materials[instance.instance_id] =
        sensor::FindMaterialPreset(instance.instance_id % 2 ? "machined-aluminium" : "black-abs")->material;
  }
  lit.returned_light = light;

  // The same noise on a cloud of positions only: the clean scan under it needs fewer fields.
  capture::MeasurementSpec positions_only = noise;
  positions_only.fields = kFieldPosition;

  struct Case {
    const char* name;
    std::function<size_t()> run;
  };
  const std::vector<Case> cases = {
      {"clean scan", clean},
      {"+ noise (along ray)", measured(noise)},
      {"noise, positions only", measured(positions_only)},
      {"+ distortion", measured(distortion)},
      {"+ outliers 1%", measured(outliers)},
      {"+ grazing + flying pixels", measured(grazing_flying)},
      {"+ ground-truth fields", measured(ground_truth)},
      {"+ estimated normals (k=16)", measured(estimated)},
      {"noise + structured-light projector", measured(structured)},
      {"noise + returned light", measured(lit)},
  };
  std::printf("measurement model, bunny grid (%d copies, %llu triangles), %ux%u, median of %d runs\n", kCopies,
              static_cast<unsigned long long>(scene.triangle_count()), kWidth, kHeight, kRuns);
  std::printf("%-30s %10s %10s %10s\n", "case", "points", "ms", "% clean");
  double base = 0;
  for (const Case& c : cases) {
    if (only != nullptr && base != 0 && std::string(c.name).find(only) == std::string::npos) continue;
    size_t points = 0;
    const double ms = MedianMs(c.run, &points);
    if (base == 0) base = ms;
    std::printf("%-30s %10zu %10.1f %9.0f%%\n", c.name, points, ms, 100.0 * ms / base);
  }
  return 0;
}

}  // namespace
}  // namespace vscan::bench

// An optional argument runs only the clean scan and the cases whose name contains it.
int main(int argc, char** argv) {
  // As in vscand: keep freed cloud memory mapped instead of page-faulting it in again each scan.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  return vscan::bench::Main(argc > 1 ? argv[1] : nullptr);
}
