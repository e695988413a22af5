// Cost of the one-bounce indirect light (capture/indirect_light.h) on a phoxi-m-class frame at full
// resolution (2064 x 1544): an open bin of cardboard holding nine bunnies of three materials at the
// preset's optimal distance, scanned clean, with the direct returned light, and with the indirect
// light at a few sample counts and grid strides. Medians and spread (min, max) of repeated runs, and
// the median CPU time over all threads (on a shared machine the wall time also counts others' load).
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench_meshes.h"
#include "measured_scan.h"
#include "capture/measure_scan.h"
#include "raycast/scanner.h"
#include "sensor/presets.h"

namespace vscan::bench {
namespace {

constexpr int kRuns = 7;

// A quad as two triangles.
void AddQuad(TriangleMesh& mesh, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
             const Eigen::Vector3d& d) {
  const auto first = static_cast<uint32_t>(mesh.vertices.size());
  for (const Eigen::Vector3d& v : {a, b, c, d}) mesh.vertices.push_back(v.cast<float>());
  mesh.triangles.push_back({first, first + 1, first + 2});
  mesh.triangles.push_back({first, first + 2, first + 3});
}

// An open box, its floor at depth `floor_z` in front of the sensor (looking along +z), its walls
// rising `wall` metres towards the sensor.
TriangleMesh OpenBin(double half_x, double half_y, double floor_z, double wall) {
  TriangleMesh mesh;
  const double top = floor_z - wall;
  AddQuad(mesh, {-half_x, -half_y, floor_z}, {half_x, -half_y, floor_z}, {half_x, half_y, floor_z},
          {-half_x, half_y, floor_z});
  for (const double x : {-half_x, half_x}) {
    AddQuad(mesh, {x, -half_y, floor_z}, {x, half_y, floor_z}, {x, half_y, top}, {x, -half_y, top});
  }
  for (const double y : {-half_y, half_y}) {
    AddQuad(mesh, {-half_x, y, floor_z}, {half_x, y, floor_z}, {half_x, y, top}, {-half_x, y, top});
  }
  return mesh;
}

struct Timing {
  double median = 0, min = 0, max = 0;
  double cpu_median = 0;  // the process's CPU time over all threads: what a shared machine's load does not inflate
  size_t points = 0;
};

double CpuMs() { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

Timing Time(const std::function<size_t()>& run) {
  std::vector<double> ms, cpu;
  Timing t;
  for (int i = 0; i < kRuns; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = CpuMs();
    t.points = run();
    cpu.push_back(CpuMs() - cpu_start);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  std::sort(cpu.begin(), cpu.end());
  t.median = ms[kRuns / 2];
  t.min = ms.front();
  t.max = ms.back();
  t.cpu_median = cpu[kRuns / 2];
  return t;
}

int Main(const char* only) {
  const sensor::SensorPreset& preset = *sensor::FindSensorPreset("phoxi-m-class");
  const sensor::PinholeCamera& camera = preset.camera;
  const double floor_z = 0.75;  // the bin's floor; its rim at the preset's optimal 0.65 m
  const TriangleMesh bunny = ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
  Eigen::Vector3f lo, hi;
  bunny.Bounds(lo, hi);
  const auto bunny_mesh = std::make_shared<const TriangleMesh>(bunny);
  std::vector<raycast::SceneInstance> instances;
  raycast::SceneInstance bin;
  bin.mesh = std::make_shared<const TriangleMesh>(OpenBin(0.26, 0.2, floor_z, 0.2));
  bin.instance_id = 1;
  bin.material = sensor::FindMaterialPreset("cardboard")->material;
  instances.push_back(bin);
  const char* materials[] = {"white-abs", "black-abs", "machined-aluminium"};
  for (int k = 0; k < 9; ++k) {
    raycast::SceneInstance b;
    b.mesh = bunny_mesh;
    b.instance_id = static_cast<uint32_t>(k + 2);
    b.material = sensor::FindMaterialPreset(materials[k % 3])->material;
    // Standing on the floor (the bunny's y up turned to -z, towards the sensor), in a 3 x 3 grid.
    const Eigen::Vector3d at((k % 3 - 1) * 0.15, (k / 3 - 1) * 0.12, floor_z);
    b.world_from_object = Eigen::Translation3d(at) *
                          Eigen::AngleAxisd(-0.5 * std::numbers::pi, Eigen::Vector3d::UnitX()) *
                          Eigen::AngleAxisd(0.7 * k, Eigen::Vector3d::UnitY()) *
                          Eigen::Translation3d(-0.5 * (lo.x() + hi.x()), -lo.y(), -0.5 * (lo.z() + hi.z()));
    instances.push_back(b);
  }
  auto built = raycast::RaycastScene::Build(instances);
  if (!built.ok()) {
    std::fprintf(stderr, "bench: %s\n", built.status().ToString().c_str());
    return 1;
  }
  const raycast::RaycastScene& scene = **built;
  const Pose3 world_from_sensor = Pose3::Identity();

  const auto clean = [&] {
    raycast::ScanOptions options;
    options.fields = kFieldsDefault;
    return raycast::Scan(scene, camera, world_from_sensor, options)->size();
  };
  const auto measured = [&](capture::MeasurementSpec spec) {
    return MeasuredScan(scene, camera, world_from_sensor, std::move(spec));
  };

  // The preset's noise and projector, and the returned light from the projector off each material.
  capture::MeasurementSpec direct;
  direct.fields = kFieldsDefault;
  direct.seed = 1;
  direct.noise = preset.noise;
  direct.structured_light = preset.structured_light;
  capture::ReturnedLightSpec light;
  const Pose3 sensor_from_projector = sensor::SensorFromProjector(*preset.structured_light);
  light.emitter.position = sensor_from_projector.translation();
  light.emitter.axis = sensor_from_projector.linear().col(2);
  light.emitter.radiant_intensity_w_per_sr = 0.2;
  light.pixel.gain_e = capture::CameraPixelGain(camera, sensor::PinholePixel{});
  light.reference_e = 5000;
  for (const raycast::SceneInstance& instance : instances) {
    if (light.materials.size() <= instance.instance_id) light.materials.resize(instance.instance_id + 1);
    light.materials[instance.instance_id] = instance.material;
  }
  capture::MeasurementSpec without_light = direct;
  direct.returned_light = light;
  const auto indirect = [&](uint32_t samples, uint32_t stride) {
    capture::MeasurementSpec spec = direct;
    spec.returned_light->indirect_samples = samples;
    spec.returned_light->indirect_stride_px = stride;
    return spec;
  };

  struct Case {
    std::string name;
    std::function<size_t()> run;
  };
  const std::vector<Case> cases = {
      {"clean scan", clean},
      {"noise + projector", measured(without_light)},
      {"noise + projector + direct light", measured(direct)},
      {"+ indirect 16 samples, stride 8", measured(indirect(16, 8))},
      {"+ indirect 64 samples, stride 8", measured(indirect(64, 8))},
      {"+ indirect 16 samples, stride 4", measured(indirect(16, 4))},
      {"+ indirect 64 samples, stride 4", measured(indirect(64, 4))},
  };
  std::printf("indirect light, phoxi-m-class %ux%u, open cardboard bin + 9 bunnies (%llu triangles), %d runs\n",
              camera.width, camera.height, static_cast<unsigned long long>(scene.triangle_count()), kRuns);
  std::printf("%-36s %9s %9s %9s %9s %8s %10s\n", "case", "points", "median ms", "min ms", "max ms", "x clean",
              "cpu ms");
  double base = 0;
  for (const Case& c : cases) {
    if (only != nullptr && base != 0 && c.name.find(only) == std::string::npos) continue;
    const Timing t = Time(c.run);
    if (base == 0) base = t.median;
    std::printf("%-36s %9zu %9.0f %9.0f %9.0f %8.2f %10.0f\n", c.name.c_str(), t.points, t.median, t.min, t.max,
                t.median / base, t.cpu_median);
  }
  return 0;
}

}  // namespace
}  // namespace vscan::bench

// An optional argument runs only the clean scan and the cases whose name contains it.
int main(int argc, char** argv) {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  return vscan::bench::Main(argc > 1 ? argv[1] : nullptr);
}
