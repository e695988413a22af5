#include "measured_scan.h"

#include <cstdio>
#include <cstdlib>

namespace vscan::bench {

std::function<size_t()> MeasuredScan(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                     const Pose3& world_from_sensor, capture::MeasurementSpec spec) {
  return [&scene, &camera, world_from_sensor, spec = std::move(spec)] {
    auto cloud = capture::ScanMeasured(scene, camera, world_from_sensor, spec, raycast::ScanFrame::kWorld, nullptr,
                                       nullptr, nullptr);
    if (!cloud.ok()) {
      std::fprintf(stderr, "bench: %s\n", cloud.status().ToString().c_str());
      std::exit(1);
    }
    return cloud->size();
  };
}

}  // namespace vscan::bench
