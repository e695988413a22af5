#pragma once
// The Embree side of RaycastScene, for the scene builder and the raycast queries only.

#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>

#include "raycast/raycast_scene.h"

namespace vscan::raycast {

struct RaycastScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<uint32_t> instance_of_geometry;
  uint64_t triangles = 0;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

inline const RaycastScene::Impl& EmbreeOf(const RaycastScene& scene) { return *scene.impl_; }

}  // namespace vscan::raycast
