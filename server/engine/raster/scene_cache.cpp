#include "raster/scene_cache.h"

#include <chrono>
#include <utility>

namespace vscan::raster {

bool SceneCache::Matches(const Entry& entry, std::span<const raycast::SceneInstance> instances) {
  if (entry.stamps.size() != instances.size()) return false;
  for (size_t i = 0; i < instances.size(); ++i) {
    const InstanceStamp& s = entry.stamps[i];
    const raycast::SceneInstance& instance = instances[i];
    if (instance.mesh.get() != s.address || s.mesh.expired() || instance.scale != s.scale ||
        instance.instance_id != s.instance_id || instance.world_from_object.matrix() != s.world_from_object) {
      return false;
    }
  }
  return true;
}

StatusOr<SceneLookup> SceneCache::Acquire(const std::string& key, std::span<const raycast::SceneInstance> instances) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if (it->key != key) continue;
    if (Matches(*it, instances)) {
      entries_.splice(entries_.begin(), entries_, it);
      return SceneLookup{entries_.front().gpu.get(), entries_.front().faces, false, 0.0};
    }
    entries_.erase(it);
    break;
  }

  const auto start = std::chrono::steady_clock::now();
  ASSIGN_OR_RETURN(SceneGeometry geometry, BuildSceneGeometry(instances));
  ASSIGN_OR_RETURN(std::unique_ptr<GpuScene> gpu, GpuScene::Upload(geometry, max_faces_));
  Entry entry;
  entry.key = key;
  for (const raycast::SceneInstance& instance : instances) {
    entry.stamps.push_back({instance.mesh, instance.mesh.get(), instance.world_from_object.matrix(), instance.scale,
                            instance.instance_id});
  }
  const SceneFaces& faces = *geometry.faces;
  entry.bytes = gpu->bytes() + faces.size() * (sizeof(Eigen::Vector3f) + sizeof(uint32_t));
  entry.gpu = std::move(gpu);
  entry.faces = std::move(geometry.faces);
  entries_.push_front(std::move(entry));
  Trim();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return SceneLookup{entries_.front().gpu.get(), entries_.front().faces, true, ms};
}

void SceneCache::Evict(const std::string& key) {
  entries_.remove_if([&](const Entry& e) { return e.key == key; });
}

// Keeps the newest entry even when it alone is over the byte budget: the scan needs it.
void SceneCache::Trim() {
  uint64_t bytes = 0;
  for (const Entry& e : entries_) bytes += e.bytes;
  while (entries_.size() > 1 && (entries_.size() > max_entries_ || bytes > max_bytes_)) {
    bytes -= entries_.back().bytes;
    entries_.pop_back();
  }
}

}  // namespace vscan::raster
