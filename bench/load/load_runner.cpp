#include "load_runner.h"

#include <atomic>
#include <mutex>
#include <random>
#include <thread>

namespace vscan::cli {
namespace {

using Clock = std::chrono::steady_clock;

// After a refusal (no free scan slot) a client waits this long before its next call.
constexpr auto kRefusalPause = std::chrono::milliseconds(10);

v1::ScanRequest ScanRequestFrom(const LoadWork& work, const v1::Viewpoint& viewpoint, uint64_t seed) {
  v1::ScanRequest request;
  request.set_scene_id(work.scene_id);
  auto* camera = request.mutable_sensor()->mutable_pinhole();
  camera->set_width(work.width);
  camera->set_height(work.height);
  camera->set_horizontal_fov_deg(60);
  auto* look = request.mutable_pose()->mutable_look_at();
  *look->mutable_eye() = viewpoint.position();
  *look->mutable_target() = viewpoint.target();
  look->mutable_up()->set_z(1);
  *request.mutable_noise() = work.noise;
  request.set_seed(seed);
  return request;
}

class LoadClient {
 public:
  LoadClient(const LoadWork& work, client::Client client, uint64_t seed, const std::array<double, kLoadKinds>& weights)
      : work_(work), client_(std::move(client)), random_(seed), pick_(weights.begin(), weights.end()) {}

  // One call of a kind drawn from the mix; its latency or error goes into the tally.
  void CallOnce() {
    const auto kind = static_cast<LoadKind>(pick_(random_));
    const v1::Viewpoint& viewpoint = work_.viewpoints[calls_ % work_.viewpoints.size()];
    const auto start = Clock::now();
    const Status status = Call(kind, viewpoint);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    const auto k = static_cast<size_t>(kind);
    ++calls_;
    if (status.ok()) {
      tally_.ok_ms[k].push_back(ms);
      return;
    }
    ++tally_.errors[k][StatusCodeName(status.code())];
    if (status.code() == StatusCode::kResourceExhausted) std::this_thread::sleep_for(kRefusalPause);
  }

  const LoadTally& tally() const { return tally_; }

 private:
  Status Call(LoadKind kind, const v1::Viewpoint& viewpoint) {
    switch (kind) {
      case LoadKind::kScan:
        return Scan(viewpoint);
      case LoadKind::kIk:
        return Solve(viewpoint);
      case LoadKind::kCatalogue:
        return ReadCatalogue();
    }
    return Internal("unknown call kind");
  }

  // Points are counted as they arrive and not kept: the clients should not weigh on the machine.
  Status Scan(const v1::Viewpoint& viewpoint) {
    client::ScanCallbacks callbacks;
    uint64_t points = 0;
    callbacks.on_chunk = [&points](const v1::PointChunk& chunk) {
      points += chunk.count();
      return Status::Ok();
    };
    const auto scanned = client_.Scan(ScanRequestFrom(work_, viewpoint, random_()), callbacks);
    if (scanned.ok()) tally_.scan_points += points;
    return scanned.status();
  }

  Status Solve(const v1::Viewpoint& viewpoint) {
    v1::InverseKinematicsRequest request;
    request.set_mount_id(work_.mount_id);
    *request.mutable_look_from()->mutable_position() = viewpoint.position();
    *request.mutable_look_from()->mutable_target() = viewpoint.target();
    return client_.InverseKinematics(request).status();
  }

  // Reads that every client of a catalogue makes: a scene, its mount, the list of meshes.
  Status ReadCatalogue() {
    switch (catalogue_calls_++ % 3) {
      case 0:
        return client_.GetScene(work_.scene_id).status();
      case 1:
        return client_.GetMount(work_.mount_id).status();
      default:
        return client_.ListMeshes().status();
    }
  }

  const LoadWork& work_;
  client::Client client_;
  std::mt19937_64 random_;
  std::discrete_distribution<int> pick_;
  uint64_t calls_ = 0;
  uint64_t catalogue_calls_ = 0;
  LoadTally tally_;
};

}  // namespace

LoadRun RunLoad(const LoadWork& work, const LoadLimits& limits, const ClientFactory& make_client) {
  std::vector<LoadClient> clients;
  clients.reserve(static_cast<size_t>(limits.clients));
  for (int i = 0; i < limits.clients; ++i) {
    clients.emplace_back(work, make_client(), limits.seed + static_cast<uint64_t>(i), limits.weights);
  }
  std::atomic<uint64_t> claimed{0};
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(limits.duration);
  const auto more = [&] {
    if (Clock::now() >= deadline) return false;
    return !limits.requests || claimed.fetch_add(1) < *limits.requests;
  };
  std::vector<std::thread> threads;
  threads.reserve(clients.size());
  for (LoadClient& client : clients) {
    threads.emplace_back([&client, &more] {
      while (more()) client.CallOnce();
    });
  }
  for (std::thread& thread : threads) thread.join();
  LoadRun run;
  run.elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();
  for (const LoadClient& client : clients) run.tally.Merge(client.tally());
  return run;
}

}  // namespace vscan::cli
