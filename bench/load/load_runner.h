#pragma once
// The clients of vscan-load: each on its own thread and channel, drawing scans, inverse
// kinematics and catalogue reads from a weighted mix until a request count or a deadline.

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "load_stats.h"
#include "vscan/client/client.h"

namespace vscan::cli {

// What the calls work on: a scene with a mount, viewpoints to scan from and to solve for.
struct LoadWork {
  std::string scene_id;
  std::string mount_id;
  std::vector<v1::Viewpoint> viewpoints;
  uint32_t width = 1280;
  uint32_t height = 1024;
  v1::NoiseSpec noise;
};

struct LoadLimits {
  int clients = 1;
  // No call starts after this; calls under way finish.
  std::chrono::duration<double> duration{30.0};
  // When set, the clients also stop after this many calls in all.
  std::optional<uint64_t> requests;
  // Relative weights of scan, IK and catalogue calls (LoadKind order).
  std::array<double, kLoadKinds> weights{1, 1, 1};
  uint64_t seed = 1;
};

struct LoadRun {
  LoadTally tally;
  // From the first call's start to the last call's end.
  double elapsed_s = 0;
};

// Makes one client with a channel of its own.
using ClientFactory = std::function<client::Client()>;

LoadRun RunLoad(const LoadWork& work, const LoadLimits& limits, const ClientFactory& make_client);

}  // namespace vscan::cli
