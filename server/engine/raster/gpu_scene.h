#pragma once
// A scene's triangles in GPU buffers (the shared vscan_gl mesh upload, drawn in a single call),
// and the face normals with each face's material slot as a buffer texture for the shaders. Lives on the render
// thread.

#include <cstdint>
#include <memory>
#include <vector>

#include "raster/scene_geometry.h"
#include "vscan/common/status.h"
#include "vscan/gl/gl_api.h"
#include "vscan/gl/mesh_buffers.h"

namespace vscan::raster {

class GpuScene {
 public:
  // max_faces: GL_MAX_TEXTURE_BUFFER_SIZE; more faces are ResourceExhausted.
  static StatusOr<std::unique_ptr<GpuScene>> Upload(const SceneGeometry& geometry, int64_t max_faces);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  // Draws every triangle with the bound program; face i is gl_PrimitiveID i.
  void Draw() const { mesh_.DrawTriangles(); }
  GLuint face_normal_texture() const { return normal_texture_; }
  uint64_t triangle_count() const { return mesh_.triangle_count(); }
  uint64_t bytes() const { return bytes_; }
  // Instance id of each material slot; a face's slot is the w of its face_normal_texture texel.
  const std::vector<uint32_t>& slot_instance_ids() const { return slot_ids_; }

 private:
  GpuScene() = default;
  gl::MeshBuffers mesh_;
  GLuint normal_buffer_ = 0, normal_texture_ = 0;
  std::vector<uint32_t> slot_ids_;
  uint64_t bytes_ = 0;
};

}  // namespace vscan::raster
