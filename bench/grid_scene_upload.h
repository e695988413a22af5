#pragma once
// The bunny-grid scene made on a vscand through the client: one mesh upload, an object per bunny,
// and the scan request that frames them.

#include <string>

#include "bench_meshes.h"
#include "vscan/client/client.h"

namespace vscan::bench {

// Uploads the bunny PLY at bunny_path, places it as grid.instances in a new scene named
// scene_name, and returns a request for grid.camera at grid.world_from_sensor (no fields set).
StatusOr<v1::ScanRequest> UploadBunnyGrid(client::Client& client, const BunnyGrid& grid, const std::string& bunny_path,
                                          const std::string& scene_name);

}  // namespace vscan::bench
