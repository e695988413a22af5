// Points per second delivered end to end into the client's arrays: a real vscand (in this
// process, over loopback TCP) streams a 1280x1024 scan of the ~160k-triangle bunny grid to the C++
// client, warm. Beside it in the same run: the plain Embree packet loop over the same frame (the
// limit) and vscand's whole-cloud path (--whole-cloud-scans, the way scans were sent before they
// streamed). first_chunk_share is the time to the first chunk as a share of the whole scan.

#include <malloc.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "api/server/server.h"
#include "bench_meshes.h"
#include "grid_scene_upload.h"
#include "packet_loop.h"
#include "ratio_reporter.h"
#include "raycast/embree_scene.h"
#include "raycast/raycast_scene.h"
#include "vscan/client/client.h"

namespace vscan::bench {
namespace {

const std::string kBunnyPath = std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply";

void Check(const Status& status) {
  if (!status.ok()) throw std::runtime_error(status.ToString());
}

struct ServedScene {
  std::filesystem::path data_dir;
  std::unique_ptr<api::Server> server;
  std::unique_ptr<client::Client> client;
  v1::ScanRequest request;
};

std::unique_ptr<ServedScene> Serve(const BunnyGrid& grid, bool whole_cloud) {
  auto s = std::make_unique<ServedScene>();
  s->data_dir = std::filesystem::temp_directory_path() /
                ("vscan-e2e-bench-" + std::to_string(getpid()) + (whole_cloud ? "-whole" : "-stream"));
  service::ServerOptions options;
  options.listen_address = "127.0.0.1:0";
  options.data_dir = s->data_dir.string();
  options.mesh_importer_path = VSCAN_MESH_IMPORTER;
  options.whole_cloud_scans = whole_cloud;
  auto server = api::Server::Start(options);
  Check(server.status());
  s->server = std::move(server).value();
  auto connected = client::Client::Connect("127.0.0.1:" + std::to_string(s->server->port()));
  Check(connected.status());
  s->client = std::make_unique<client::Client>(std::move(connected).value());

  auto request = UploadBunnyGrid(*s->client, grid, kBunnyPath, "e2e-bench");
  Check(request.status());
  s->request = std::move(request).value();
  Check(s->client->Scan(s->request).status());  // builds the server's scene: later scans are warm
  return s;
}

struct Fixture {
  BunnyGrid grid;
  std::shared_ptr<const raycast::RaycastScene> scene;
  std::unique_ptr<PacketLoop> packets;
  std::unique_ptr<ServedScene> streamed, whole;
};

Fixture& Setup() {
  static Fixture* fixture = [] {
    auto* f = new Fixture;
    f->grid = MakeBunnyGrid(ReadAsciiPly(kBunnyPath), 10, 1280, 1024);
    auto built = raycast::RaycastScene::Build(f->grid.instances);
    Check(built.status());
    f->scene = *built;
    f->packets = std::make_unique<PacketLoop>(raycast::EmbreeOf(*f->scene).scene, f->grid.camera,
                                              f->grid.world_from_sensor);
    f->streamed = Serve(f->grid, false);
    f->whole = Serve(f->grid, true);
    return f;
  }();
  return *fixture;
}

void BM_PlainEmbreePackets16(benchmark::State& state) {
  const Fixture& f = Setup();
  uint64_t hits = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hits = f.packets->Frame());
  state.counters["Mpoints/s"] = benchmark::Counter(static_cast<double>(hits) * static_cast<double>(state.iterations()) / 1e6,
                                                   benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(hits);
}

void ScanOverGrpc(benchmark::State& state, bool whole_cloud, bool all_fields) {
  Fixture& f = Setup();
  ServedScene& served = whole_cloud ? *f.whole : *f.streamed;
  v1::ScanRequest request = served.request;
  if (all_fields) {
    for (int field = v1::POINT_FIELD_POSITION; field <= v1::POINT_FIELD_PIXEL; ++field) {
      request.add_fields(static_cast<v1::PointField>(field));
    }
  } else {
    request.add_fields(v1::POINT_FIELD_POSITION);
  }
  using Clock = std::chrono::steady_clock;
  uint64_t points = 0;
  double server_ms = 0, first_share = 0, first_ms = 0;
  for (auto _ : state) {
    const auto start = Clock::now();
    Clock::time_point first{};
    client::ScanCallbacks callbacks;
    callbacks.on_progress = [&](uint64_t, uint64_t) {
      if (first == Clock::time_point{}) first = Clock::now();
    };
    auto result = served.client->Scan(request, callbacks);
    const auto end = Clock::now();
    if (!result.ok()) {
      state.SkipWithError(result.status().ToString().c_str());
      return;
    }
    points += result->cloud.size();
    server_ms += result->stats.scan_ms();
    first_ms += std::chrono::duration<double, std::milli>(first - start).count();
    first_share += std::chrono::duration<double>(first - start) / std::chrono::duration<double>(end - start);
    benchmark::DoNotOptimize(result->cloud.positions.data());
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["Mpoints/s"] = benchmark::Counter(static_cast<double>(points) / 1e6, benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(points) / n;
  state.counters["server_scan_ms"] = server_ms / n;
  state.counters["first_chunk_ms"] = first_ms / n;
  state.counters["first_chunk_share"] = first_share / n;
}

BENCHMARK(BM_PlainEmbreePackets16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ScanOverGrpc, streamed_positions, false, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ScanOverGrpc, streamed_all_fields, false, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ScanOverGrpc, whole_cloud_positions, true, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ScanOverGrpc, whole_cloud_all_fields, true, true)->Unit(benchmark::kMillisecond)->UseRealTime();


}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  // As vscand does: keep freed memory instead of faulting big clouds in again on every scan.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  vscan::bench::RatioReporter reporter("BM_PlainEmbreePackets16", {"ScanOverGrpc"});
  return vscan::bench::RunWithRatios(argc, argv, reporter);
}
