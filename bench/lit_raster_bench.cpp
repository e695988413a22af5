// The returned light on a raster scan at full resolution (2064x1544, ten bunnies): its direct term
// from the shaders (an extra R32F target) against the same term evaluated per point on the CPU
// (what the raster backends did before), and against the raster scan without returned light.
// The lit variants run the whole measured scan (MeasureScan: verdicts, the signal, noise).
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

#include <benchmark/benchmark.h>

#include "bench_meshes.h"
#include "capture/measure_scan.h"
#include "raster/raster_scanner.h"

namespace vscan::bench {
namespace {

constexpr uint32_t kWidth = 2064, kHeight = 1544;
constexpr int kCopies = 10;

struct Setup {
  BunnyGrid grid;
  std::shared_ptr<const raycast::RaycastScene> scene;
  capture::MeasurementSpec spec;
  std::unique_ptr<raster::RasterRenderer> renderer;
};

Setup& Shared() {
  static Setup* setup = [] {
    auto* s = new Setup;
    s->grid = MakeBunnyGrid(ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"),
                            kCopies, kWidth, kHeight);
    auto scene = raycast::RaycastScene::Build(s->grid.instances);
    auto renderer = raster::RasterRenderer::Create();
    if (!scene.ok() || !renderer.ok()) {
      std::fprintf(stderr, "bench: %s %s\n", scene.status().ToString().c_str(), renderer.status().ToString().c_str());
      std::exit(1);
    }
    s->scene = *scene;
    s->renderer = std::move(*renderer);
    std::fprintf(stderr, "raster: %s, %s\n", s->renderer->gl_renderer().c_str(), s->renderer->gl_version().c_str());
    capture::ReturnedLightSpec light;
    light.pixel.gain_e = 2e4;
    // Every other bunny polished metal, the rest plastic and grey: three materials in the frame.
    light.materials.assign(kCopies + 2, sensor::Material{0.5, 0.0, 0.5, 0.04});
    for (size_t id = 0; id < light.materials.size(); id += 2) light.materials[id] = {0.9, 1.0, 0.15, 0.04};
    light.materials[1] = {0.3, 0.0, 0.7, 0.04};
    s->spec.returned_light = light;
    return s;
  }();
  return *setup;
}

raster::RasterOptions CleanOptions(const Setup& s) {
  raster::RasterOptions options;
  options.fields = capture::CleanFieldsFor(s.spec);
  options.frame = raycast::ScanFrame::kSensor;
  return options;
}

void Count(benchmark::State& state, const raster::RasterStats& stats, double& render_ms, double& decode_ms) {
  render_ms += stats.render_ms;
  decode_ms += stats.decode_ms;
  state.counters["points"] = static_cast<double>(stats.points);
}

void Finish(benchmark::State& state, double render_ms, double decode_ms) {
  state.counters["render_ms"] = render_ms / static_cast<double>(state.iterations());
  state.counters["decode_ms"] = decode_ms / static_cast<double>(state.iterations());
}

raster::RasterMethod MethodOf(const benchmark::State& state) {
  return state.range(0) == 0 ? raster::RasterMethod::kDepthBuffer : raster::RasterMethod::kColourBuffer;
}

// The clean raster scan a measured scan starts from, its render and decode times counted.
StatusOr<PointCloud> PlainScan(benchmark::State& state, const Setup& s, double& render_ms, double& decode_ms) {
  raster::RasterStats stats;
  auto cloud = raster::RasterScan(*s.renderer, "bunnies", s.grid.instances, s.grid.camera, s.grid.world_from_sensor,
                                  MethodOf(state), CleanOptions(s), &stats);
  if (cloud.ok()) Count(state, stats, render_ms, decode_ms);
  return cloud;
}

// The clean raster scan alone, without returned light.
void BM_NoReturnedLight(benchmark::State& state) {
  Setup& s = Shared();
  double render_ms = 0, decode_ms = 0;
  for (auto _ : state) {
    auto cloud = PlainScan(state, s, render_ms, decode_ms);
    if (!cloud.ok()) return state.SkipWithError(cloud.status().ToString().c_str());
    benchmark::DoNotOptimize(cloud->positions.data());
  }
  Finish(state, render_ms, decode_ms);
}

// The plain raster scan, then MeasureScan evaluating the direct term per point on the CPU.
void BM_CpuDirectTerm(benchmark::State& state) {
  Setup& s = Shared();
  double render_ms = 0, decode_ms = 0;
  for (auto _ : state) {
    auto cloud = PlainScan(state, s, render_ms, decode_ms);
    if (!cloud.ok()) return state.SkipWithError(cloud.status().ToString().c_str());
    auto measured = capture::MeasureScan(*s.scene, s.grid.camera, s.grid.world_from_sensor, std::move(*cloud), s.spec,
                                         nullptr, nullptr);
    if (!measured.ok()) return state.SkipWithError(measured.status().ToString().c_str());
    benchmark::DoNotOptimize(measured->positions.data());
  }
  Finish(state, render_ms, decode_ms);
}

// The lit raster scan, then MeasureScan taking the shaders' direct radiance.
void BM_ShaderDirectTerm(benchmark::State& state) {
  Setup& s = Shared();
  const capture::ReturnedLightSpec& light = *s.spec.returned_light;
  const raster::DirectLight direct{light.emitter, light.materials, light.default_material};
  double render_ms = 0, decode_ms = 0;
  for (auto _ : state) {
    raster::RasterStats stats;
    auto lit = raster::RasterScanLit(*s.renderer, "bunnies", s.grid.instances, s.grid.camera, s.grid.world_from_sensor,
                                     MethodOf(state), direct, CleanOptions(s), &stats);
    if (!lit.ok()) return state.SkipWithError(lit.status().ToString().c_str());
    Count(state, stats, render_ms, decode_ms);
    auto measured = capture::MeasureScan(*s.scene, s.grid.camera, s.grid.world_from_sensor, std::move(lit->cloud),
                                         s.spec, nullptr, nullptr, lit->direct_radiance);
    if (!measured.ok()) return state.SkipWithError(measured.status().ToString().c_str());
    benchmark::DoNotOptimize(measured->positions.data());
  }
  Finish(state, render_ms, decode_ms);
}

// Arg 0: depth-buffer method, 1: colour-buffer method. Run with repetitions and
// --benchmark_enable_random_interleaving so that a shared machine's load falls on all alike.
#define VSCAN_LIT_ARGS ->Arg(0)->Arg(1)->Iterations(4)->UseRealTime()->Unit(benchmark::kMillisecond)
BENCHMARK(BM_NoReturnedLight) VSCAN_LIT_ARGS;
BENCHMARK(BM_CpuDirectTerm) VSCAN_LIT_ARGS;
BENCHMARK(BM_ShaderDirectTerm) VSCAN_LIT_ARGS;

}  // namespace
}  // namespace vscan::bench

BENCHMARK_MAIN();
