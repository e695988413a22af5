#pragma once
// Procedural machined parts with large flat faces (a bracket with a riser, bosses and a pocket; a
// stepped block; an irregular many-sided prism) and depth scans of them by the project's ray caster,
// for the alignment tests and benchmark.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "raycast/raycast_scene.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::registration::testing {

struct MachinedPart {
  std::string name;
  TriangleMesh mesh;  // metres, centred near the origin, about 0.1 to 0.2 m across
  std::shared_ptr<const raycast::RaycastScene> scene;
};

// 0: bracket, 1: stepped block, 2: seven-sided prism.
MachinedPart MakeMachinedPart(int which);
constexpr int kMachinedParts = 3;

// The sensor `distance` from the origin, in the direction of (azimuth about +z, elevation above
// the xy plane) in degrees, looking at the origin.
Pose3 ViewOfPart(double azimuth_deg, double elevation_deg, double distance);

// A width x height depth scan (fov_deg across) in the sensor frame, with Gaussian noise of
// noise_sigma (metres) on each coordinate.
struct PartCamera {
  uint32_t width = 640, height = 480;
  double fov_deg = 45.0;
};
std::vector<Eigen::Vector3f> ScanPart(const MachinedPart& part, const Pose3& world_from_sensor, double noise_sigma,
                                      uint32_t seed, const PartCamera& camera = {});

}  // namespace vscan::registration::testing
