// Ray-cast scanner against plain Embree loops over the same rays and triangles.
#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "bench_meshes.h"
#include "packet_loop.h"
#include "ratio_reporter.h"
#include "raycast/embree_scene.h"
#include "raycast/scanner.h"

namespace vscan::bench {
namespace {

constexpr uint32_t kWidth = 1280, kHeight = 1024;
static_assert(kWidth % 4 == 0);
constexpr int kCopies = 10;

// The plain loops trace the scanner's own Embree scene, so both walk the same BVH and the
// difference is the scanner's work around rtcIntersect16.
struct Fixture {
  BunnyGrid grid;
  std::shared_ptr<const raycast::RaycastScene> scene;
  RTCScene embree = nullptr;
  uint64_t triangles = 0;
  Eigen::Matrix3f rotation;
  std::vector<float> column_x, row_y;
  std::unique_ptr<PacketLoop> packets;

  Fixture() {
    const TriangleMesh bunny = ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
    grid = MakeBunnyGrid(bunny, kCopies, kWidth, kHeight);
    auto built = raycast::RaycastScene::Build(grid.instances);
    if (!built.ok()) {
      std::fprintf(stderr, "bench: %s\n", built.status().ToString().c_str());
      std::exit(1);
    }
    scene = *built;
    embree = vscan::raycast::EmbreeOf(*scene).scene;
    triangles = scene->triangle_count();
    rotation = grid.world_from_sensor.linear().cast<float>();
    for (uint32_t u = 0; u < kWidth; ++u) column_x.push_back(grid.camera.RayThroughPixel(u, 0).x());
    for (uint32_t v = 0; v < kHeight; ++v) row_y.push_back(grid.camera.RayThroughPixel(0, v).y());
    packets = std::make_unique<PacketLoop>(embree, grid.camera, grid.world_from_sensor);
  }
};

const Fixture& Shared() {
  static const Fixture fixture;
  return fixture;
}

// World direction of pixel (u, v)'s z = 1 sensor ray; pixels past the border repeat the last one.
void WorldRay(const Fixture& f, uint32_t u, uint32_t v, float& dx, float& dy, float& dz) {
  const float x = f.column_x[std::min<uint32_t>(u, kWidth - 1)], y = f.row_y[std::min<uint32_t>(v, kHeight - 1)];
  const Eigen::Matrix3f& r = f.rotation;
  dx = r(0, 0) * x + r(0, 1) * y + r(0, 2);
  dy = r(1, 0) * x + r(1, 1) * y + r(1, 2);
  dz = r(2, 0) * x + r(2, 1) * y + r(2, 2);
}

uint64_t PlainPacketFrame(const Fixture& f) { return f.packets->Frame(); }

uint64_t PlainSingleFrame(const Fixture& f) {
  const auto& cam = f.grid.camera;
  const Eigen::Vector3f o = f.grid.world_from_sensor.translation().cast<float>();
  return tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, cam.height), uint64_t{0},
      [&](const tbb::blocked_range<uint32_t>& range, uint64_t hits) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit ray;
        for (uint32_t v = range.begin(); v != range.end(); ++v) {
          for (uint32_t u = 0; u < cam.width; ++u) {
            ray.ray.org_x = o.x();
            ray.ray.org_y = o.y();
            ray.ray.org_z = o.z();
            WorldRay(f, u, v, ray.ray.dir_x, ray.ray.dir_y, ray.ray.dir_z);
            ray.ray.tnear = static_cast<float>(cam.near);
            ray.ray.tfar = static_cast<float>(cam.far);
            ray.ray.time = 0;
            ray.ray.mask = 0xFFFFFFFFu;
            ray.ray.id = 0;
            ray.ray.flags = 0;
            ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(f.embree, &context, &ray);
            hits += ray.hit.geomID != RTC_INVALID_GEOMETRY_ID;
          }
        }
        return hits;
      },
      std::plus<>());
}

// CPU time of every thread of the process; steadier than wall time when the machine is shared.
double ProcessCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

void SetCounters(benchmark::State& state, const Fixture& f, uint64_t hits, double cpu_ms) {
  const double rays = static_cast<double>(f.grid.camera.pixel_count());
  state.counters["cpu_ms/frame"] = cpu_ms / static_cast<double>(state.iterations());
  state.counters["Mrays/s"] =
      benchmark::Counter(rays * static_cast<double>(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
  state.counters["hit_ratio"] = static_cast<double>(hits) / rays;
  state.counters["triangles"] = static_cast<double>(f.triangles);
}

void BM_PlainEmbreePackets16(benchmark::State& state) {
  const Fixture& f = Shared();
  uint64_t hits = 0;
  const double cpu = ProcessCpuMs();
  for (auto _ : state) benchmark::DoNotOptimize(hits = PlainPacketFrame(f));
  SetCounters(state, f, hits, ProcessCpuMs() - cpu);
}

void BM_PlainEmbreeSingleRays(benchmark::State& state) {
  const Fixture& f = Shared();
  uint64_t hits = 0;
  const double cpu = ProcessCpuMs();
  for (auto _ : state) benchmark::DoNotOptimize(hits = PlainSingleFrame(f));
  SetCounters(state, f, hits, ProcessCpuMs() - cpu);
}

void ScanBench(benchmark::State& state, uint32_t fields) {
  const Fixture& f = Shared();
  raycast::ScanOptions options;
  options.fields = fields;
  uint64_t hits = 0;
  const double cpu = ProcessCpuMs();
  for (auto _ : state) {
    auto cloud = raycast::Scan(*f.scene, f.grid.camera, f.grid.world_from_sensor, options);
    if (!cloud.ok()) {
      state.SkipWithError(cloud.status().ToString().c_str());
      return;
    }
    hits = cloud->size();
    benchmark::DoNotOptimize(cloud->positions.data());
  }
  SetCounters(state, f, hits, ProcessCpuMs() - cpu);
}

void BM_ScanAllFields(benchmark::State& state) { ScanBench(state, kFieldsAll); }
void BM_ScanPositionOnly(benchmark::State& state) { ScanBench(state, kFieldPosition); }

BENCHMARK(BM_PlainEmbreePackets16)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlainEmbreeSingleRays)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScanAllFields)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScanPositionOnly)->UseRealTime()->Unit(benchmark::kMillisecond);

// Scan returns a fresh cloud each call. glibc hands big blocks back to the kernel when they are
// freed, so every scan would fault its ~50 MB in again; a server keeps its heap instead (vscand
// should set the same). --vscan_default_malloc measures glibc's defaults.
void KeepFreedMemory(int& argc, char** argv) {
  bool keep = true;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::string_view(argv[i]) == "--vscan_default_malloc") {
      keep = false;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  if (keep) {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  }
  std::printf("malloc: %s\n", keep ? "freed memory kept (M_MMAP_THRESHOLD 32 MiB, M_TRIM_THRESHOLD 1 GiB)"
                                    : "glibc defaults");
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  vscan::bench::KeepFreedMemory(argc, argv);
  vscan::bench::RatioReporter reporter("BM_PlainEmbreePackets16", {"BM_Scan", "BM_PlainEmbreeSingleRays"});
  return vscan::bench::RunWithRatios(argc, argv, reporter);
}
