#include "raster/material_table.h"

#include <algorithm>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {

MaterialTable::~MaterialTable() {
  if (texture_ != 0) glDeleteTextures(1, &texture_);
  if (buffer_ != 0) glDeleteBuffers(1, &buffer_);
}

Status MaterialTable::Upload(const DirectLight& light, const std::vector<uint32_t>& slot_instance_ids) {
  const size_t slots = std::max<size_t>(1, slot_instance_ids.size());
  std::vector<float> texels(4 * slots);
  for (size_t s = 0; s < slots; ++s) {
    const sensor::Material& m = MaterialOf(light, s < slot_instance_ids.size() ? slot_instance_ids[s] : 0);
    texels[4 * s + 0] = static_cast<float>(m.albedo);
    texels[4 * s + 1] = static_cast<float>(m.metallic);
    texels[4 * s + 2] = static_cast<float>(m.roughness);
    texels[4 * s + 3] = static_cast<float>(m.specular_reflectance);
  }
  if (buffer_ == 0) glGenBuffers(1, &buffer_);
  glBindBuffer(GL_TEXTURE_BUFFER, buffer_);
  glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(texels.size() * sizeof(float)), texels.data(),
               GL_STREAM_DRAW);
  if (texture_ == 0) glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_BUFFER, texture_);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, buffer_);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  return gl::CheckGl("raster: uploading the materials");
}

}  // namespace vscan::raster
