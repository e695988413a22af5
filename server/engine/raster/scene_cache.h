#pragma once
// Uploaded scenes by the caller's key, least recently used evicted first. A key's entry is reused
// only while the instances match it exactly (same mesh objects, poses, scales and ids), so a
// stale key re-uploads rather than render an old scene. Render thread only.

#include <cstdint>
#include <list>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "raster/gpu_scene.h"
#include "raster/scene_geometry.h"
#include "raycast/raycast_scene.h"
#include "vscan/common/status.h"

namespace vscan::raster {

struct SceneLookup {
  const GpuScene* gpu = nullptr;              // valid until the next call on the cache
  std::shared_ptr<const SceneFaces> faces;  // safe to keep on any thread
  bool uploaded = false;
  double upload_ms = 0;
};

class SceneCache {
 public:
  SceneCache(size_t max_entries, uint64_t max_bytes, int64_t max_faces)
      : max_entries_(max_entries), max_bytes_(max_bytes), max_faces_(max_faces) {}

  StatusOr<SceneLookup> Acquire(const std::string& key, std::span<const raycast::SceneInstance> instances);
  void Evict(const std::string& key);
  size_t size() const { return entries_.size(); }

 private:
  // What an entry was built from; weak_ptr tells a freed mesh from a new one at the same address.
  struct InstanceStamp {
    std::weak_ptr<const TriangleMesh> mesh;
    const TriangleMesh* address = nullptr;
    Eigen::Matrix4d world_from_object;
    double scale = 0;
    uint32_t instance_id = 0;
  };
  struct Entry {
    std::string key;
    std::vector<InstanceStamp> stamps;
    std::unique_ptr<GpuScene> gpu;
    std::shared_ptr<const SceneFaces> faces;
    uint64_t bytes = 0;
  };

  static bool Matches(const Entry& entry, std::span<const raycast::SceneInstance> instances);
  void Trim();

  size_t max_entries_;
  uint64_t max_bytes_;
  int64_t max_faces_;
  std::list<Entry> entries_;  // most recently used first
};

}  // namespace vscan::raster
