#pragma once
// Meshes and the bunny-grid scene the ray-cast benchmark runs on.

#include <string>
#include <vector>

#include "raycast/raycast_scene.h"
#include "sensor/camera.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::bench {

// Reads the vertices and triangular faces of an ASCII PLY file; exits with a message on failure.
TriangleMesh ReadAsciiPly(const std::string& path);

struct BunnyGrid {
  std::vector<raycast::SceneInstance> instances;
  sensor::PinholeCamera camera;
  Pose3 world_from_sensor;
};

// copies bunnies in staggered rows, framed by a width x height camera that looks at them.
BunnyGrid MakeBunnyGrid(const TriangleMesh& bunny, int copies, uint32_t width, uint32_t height);

}  // namespace vscan::bench
