// Points per second delivered end to end: a real vscand (in this process, over loopback TCP)
// streams a 1280x1024 scan of the ~160k-triangle bunny grid to the C++ client.

#include <filesystem>
#include <fstream>
#include <sstream>

#include <benchmark/benchmark.h>

#include "api/server.h"
#include "bench_meshes.h"
#include "vscan/client/client.h"
#include "vscan/common/proto_convert.h"

namespace vscan::bench {
namespace {

const std::string kBunnyPath = std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply";

struct Fixture {
  std::filesystem::path data_dir;
  std::unique_ptr<api::Server> server;
  std::unique_ptr<client::Client> client;
  v1::ScanRequest request;
};

Fixture& Setup() {
  static Fixture* fixture = [] {
    auto* f = new Fixture;
    f->data_dir = std::filesystem::temp_directory_path() / ("vscan-e2e-bench-" + std::to_string(getpid()));
    api::ServerOptions options;
    options.listen_address = "127.0.0.1:0";
    options.data_dir = f->data_dir.string();
    options.mesh_importer_path = VSCAN_MESH_IMPORTER;
    auto server = api::Server::Start(options);
    if (!server.ok()) throw std::runtime_error(server.status().ToString());
    f->server = std::move(server).value();
    auto connected = client::Client::Connect("127.0.0.1:" + std::to_string(f->server->port()));
    if (!connected.ok()) throw std::runtime_error(connected.status().ToString());
    f->client = std::make_unique<client::Client>(std::move(connected).value());

    client::MeshUploadOptions upload;
    upload.unit = v1::LENGTH_UNIT_METRE;
    auto mesh = f->client->UploadMeshFile(kBunnyPath, upload);
    if (!mesh.ok()) throw std::runtime_error(mesh.status().ToString());
    auto scene = f->client->CreateScene("e2e-bench");
    if (!scene.ok()) throw std::runtime_error(scene.status().ToString());

    const TriangleMesh bunny = ReadAsciiPly(kBunnyPath);
    const BunnyGrid grid = MakeBunnyGrid(bunny, 10, 1280, 1024);
    for (const auto& instance : grid.instances) {
      client::ObjectPlacement placement;
      placement.pose = PoseToProto(instance.world_from_object);
      placement.scale = instance.scale;
      auto added = f->client->AddObject(scene->scene_id(), mesh->mesh_id(), placement);
      if (!added.ok()) throw std::runtime_error(added.status().ToString());
    }
    f->request.set_scene_id(scene->scene_id());
    auto* pinhole = f->request.mutable_sensor()->mutable_pinhole();
    pinhole->set_width(grid.camera.width);
    pinhole->set_height(grid.camera.height);
    auto* k = pinhole->mutable_intrinsics();
    k->set_fx(grid.camera.fx);
    k->set_fy(grid.camera.fy);
    k->set_cx(grid.camera.cx);
    k->set_cy(grid.camera.cy);
    pinhole->set_near(grid.camera.near);
    pinhole->set_far(grid.camera.far);
    *f->request.mutable_pose() = PoseToProto(grid.world_from_sensor);
    return f;
  }();
  return *fixture;
}

void ScanOverGrpc(benchmark::State& state, bool all_fields) {
  Fixture& f = Setup();
  v1::ScanRequest request = f.request;
  if (all_fields) {
    for (int field = v1::POINT_FIELD_POSITION; field <= v1::POINT_FIELD_PIXEL; ++field) request.add_fields(static_cast<v1::PointField>(field));
  } else {
    request.add_fields(v1::POINT_FIELD_POSITION);
  }
  uint64_t points = 0;
  double server_ms = 0;
  for (auto _ : state) {
    auto result = f.client->Scan(request);
    if (!result.ok()) {
      state.SkipWithError(result.status().ToString().c_str());
      return;
    }
    points += result->cloud.size();
    server_ms += result->stats.scan_ms();
    benchmark::DoNotOptimize(result->cloud.positions.data());
  }
  state.counters["Mpoints/s"] = benchmark::Counter(static_cast<double>(points) / 1e6, benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(points) / static_cast<double>(state.iterations());
  state.counters["server_scan_ms"] = server_ms / static_cast<double>(state.iterations());
}

BENCHMARK_CAPTURE(ScanOverGrpc, all_fields, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ScanOverGrpc, positions_only, false)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace vscan::bench

BENCHMARK_MAIN();
