#pragma once
// The materials of one lit scan as a buffer texture (RGBA32F per material slot: albedo, metallic,
// roughness, specular_reflectance), rewritten per scan; created on the first lit scan. Render thread only.

#include <vector>

#include "raster/direct_light.h"
#include "vscan/common/status.h"
#include "vscan/gl/gl_api.h"

namespace vscan::raster {

class MaterialTable {
 public:
  MaterialTable() = default;
  MaterialTable(const MaterialTable&) = delete;
  MaterialTable& operator=(const MaterialTable&) = delete;
  ~MaterialTable();

  // Slot s gets MaterialOf(light, slot_instance_ids[s]); at least one slot is written.
  Status Upload(const DirectLight& light, const std::vector<uint32_t>& slot_instance_ids);
  GLuint texture() const { return texture_; }

 private:
  GLuint buffer_ = 0, texture_ = 0;
};

}  // namespace vscan::raster
