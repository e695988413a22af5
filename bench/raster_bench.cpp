// Both raster methods against the ray caster on the same scene (ten bunnies, 164k triangles) and
// the same cameras, with every per-point field on.
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <benchmark/benchmark.h>

#include "bench_meshes.h"
#include "raster/raster_scanner.h"
#include "raycast/scanner.h"

namespace vscan::bench {
namespace {

constexpr int kCopies = 10;

struct Frame {
  std::string key;
  BunnyGrid grid;
  std::shared_ptr<const raycast::RaycastScene> scene;
};

const TriangleMesh& Bunny() {
  static const TriangleMesh bunny = ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
  return bunny;
}

const Frame& FrameFor(uint32_t width, uint32_t height) {
  static std::map<std::pair<uint32_t, uint32_t>, Frame> frames;
  auto [it, added] = frames.try_emplace({width, height});
  if (added) {
    it->second.key = "bunnies-" + std::to_string(width) + "x" + std::to_string(height);
    it->second.grid = MakeBunnyGrid(Bunny(), kCopies, width, height);
    auto scene = raycast::RaycastScene::Build(it->second.grid.instances);
    if (!scene.ok()) {
      std::fprintf(stderr, "bench: %s\n", scene.status().ToString().c_str());
      std::exit(1);
    }
    it->second.scene = *scene;
  }
  return it->second;
}

raster::RasterRenderer& Renderer() {
  static const auto renderer = [] {
    auto created = raster::RasterRenderer::Create();
    if (!created.ok()) {
      std::fprintf(stderr, "bench: %s\n", created.status().ToString().c_str());
      std::exit(1);
    }
    std::fprintf(stderr, "raster: %s, %s, %s\n", (*created)->gl_renderer().c_str(), (*created)->gl_version().c_str(),
                 (*created)->platform().c_str());
    return std::move(*created);
  }();
  return *renderer;
}

// CPU time of every thread of the process, llvmpipe's and TBB's workers included.
double ProcessCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

void SetCounters(benchmark::State& state, uint64_t points, double cpu_ms) {
  const auto frames = static_cast<double>(state.iterations());
  state.counters["Mpoints/s"] = benchmark::Counter(static_cast<double>(points) * frames / 1e6, benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(points);
  state.counters["cpu_ms/frame"] = cpu_ms / frames;
}

void BM_Raycast(benchmark::State& state) {
  const Frame& f = FrameFor(static_cast<uint32_t>(state.range(0)), static_cast<uint32_t>(state.range(1)));
  raycast::ScanOptions options;
  options.fields = kFieldsAll;
  uint64_t points = 0;
  const double cpu = ProcessCpuMs();
  for (auto _ : state) {
    auto cloud = raycast::Scan(*f.scene, f.grid.camera, f.grid.world_from_sensor, options);
    if (!cloud.ok()) {
      state.SkipWithError(cloud.status().ToString().c_str());
      return;
    }
    points = cloud->size();
    benchmark::DoNotOptimize(cloud->positions.data());
  }
  SetCounters(state, points, ProcessCpuMs() - cpu);
}

void RasterBench(benchmark::State& state, raster::RasterMethod method, raster::DepthFormat format) {
  const Frame& f = FrameFor(static_cast<uint32_t>(state.range(0)), static_cast<uint32_t>(state.range(1)));
  raster::RasterRenderer& renderer = Renderer();
  raster::RasterOptions options;
  options.fields = kFieldsAll;
  options.depth_format = format;
  // The upload happens once per scene; frames after it reuse it.
  if (!raster::RasterScan(renderer, f.key, f.grid.instances, f.grid.camera, f.grid.world_from_sensor, method, options).ok()) {
    state.SkipWithError("first scan failed");
    return;
  }
  uint64_t points = 0;
  double render_ms = 0, decode_ms = 0;
  const double cpu = ProcessCpuMs();
  for (auto _ : state) {
    raster::RasterStats stats;
    auto cloud = raster::RasterScan(renderer, f.key, f.grid.instances, f.grid.camera, f.grid.world_from_sensor, method,
                                    options, &stats);
    if (!cloud.ok()) {
      state.SkipWithError(cloud.status().ToString().c_str());
      return;
    }
    points = cloud->size();
    render_ms += stats.render_ms;
    decode_ms += stats.decode_ms;
    benchmark::DoNotOptimize(cloud->positions.data());
  }
  SetCounters(state, points, ProcessCpuMs() - cpu);
  state.counters["render_ms"] = render_ms / static_cast<double>(state.iterations());
  state.counters["decode_ms"] = decode_ms / static_cast<double>(state.iterations());
}

void BM_RasterDepth(benchmark::State& state) {
  RasterBench(state, raster::RasterMethod::kDepthBuffer, raster::DepthFormat::kFloat32Reversed);
}
void BM_RasterDepth24(benchmark::State& state) {
  RasterBench(state, raster::RasterMethod::kDepthBuffer, raster::DepthFormat::kFixed24);
}
void BM_RasterColour(benchmark::State& state) {
  RasterBench(state, raster::RasterMethod::kColourBuffer, raster::DepthFormat::kFloat32Reversed);
}

// 640x360 is the frame of the paper's rendering anchor (PyBullet's CPU renderer, about 330 ms).
#define VSCAN_RESOLUTIONS ->Args({640, 480})->Args({1280, 1024})->Args({640, 360})->UseRealTime()->Unit(benchmark::kMillisecond)
BENCHMARK(BM_Raycast) VSCAN_RESOLUTIONS;
BENCHMARK(BM_RasterDepth) VSCAN_RESOLUTIONS;
BENCHMARK(BM_RasterDepth24) VSCAN_RESOLUTIONS;
BENCHMARK(BM_RasterColour) VSCAN_RESOLUTIONS;

}  // namespace
}  // namespace vscan::bench

BENCHMARK_MAIN();
