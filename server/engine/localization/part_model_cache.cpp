#include "localization/part_model_cache.h"

#include <algorithm>
#include <cstdio>

namespace vscan::localization {

StatusOr<std::shared_ptr<const PartModel>> PartModelCache::Get(const std::string& key,
                                                               const std::function<StatusOr<PartModel>()>& build) {
  {
    const std::lock_guard lock(mutex_);
    const auto found = std::find_if(kept_.begin(), kept_.end(), [&](const auto& entry) { return entry.first == key; });
    if (found != kept_.end()) {
      kept_.splice(kept_.begin(), kept_, found);
      return kept_.front().second;
    }
  }
  ASSIGN_OR_RETURN(PartModel built, build());
  auto model = std::make_shared<const PartModel>(std::move(built));
  const std::lock_guard lock(mutex_);
  kept_.remove_if([&](const auto& entry) { return entry.first == key; });
  kept_.emplace_front(key, model);
  const auto total = [&] {
    size_t bytes = 0;
    for (const auto& entry : kept_) bytes += entry.second->MemoryBytes();
    return bytes;
  };
  while (kept_.size() > 1 && (kept_.size() > capacity_ || total() > max_bytes_)) kept_.pop_back();
  return model;
}

size_t PartModelCache::size() const {
  const std::lock_guard lock(mutex_);
  return kept_.size();
}

size_t PartModelCache::bytes() const {
  const std::lock_guard lock(mutex_);
  size_t bytes = 0;
  for (const auto& entry : kept_) bytes += entry.second->MemoryBytes();
  return bytes;
}

std::string PartModelKey(const std::string& mesh_name, double scale, const PartModelSettings& settings) {
  char figures[160];
  std::snprintf(figures, sizeof(figures), "|%.17g|%.17g|%zu|%.17g|%.17g|%u", scale, settings.voxel_size,
                settings.samples, settings.ppf_step_voxels, settings.angle_step_rad, settings.scene_reference_stride);
  return mesh_name + figures;
}

}  // namespace vscan::localization
