#include "raster/gpu_scene.h"

#include <algorithm>
#include <string>
#include <unordered_map>
#include <vector>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {

StatusOr<std::unique_ptr<GpuScene>> GpuScene::Upload(const SceneGeometry& geometry, int64_t max_faces) {
  const SceneFaces& faces = *geometry.faces;
  max_faces = std::min<int64_t>(max_faces, gl::kMaxDrawCount / 3);
  if (static_cast<int64_t>(faces.size()) > max_faces) {
    return ResourceExhausted("instances: " + std::to_string(faces.size()) + " triangles exceed the renderer's limit of " +
                             std::to_string(max_faces));
  }
  std::unique_ptr<GpuScene> scene(new GpuScene);
  if (faces.size() == 0) return scene;
  scene->mesh_.AddAttribute(0, geometry.vertices);
  scene->mesh_.SetTriangles(geometry.triangles);

  // RGBA32F rather than RGB32F: buffer textures take three-component formats only from GL 4.0.
  // The fourth component is the face's material slot, exact in a float below 2^24 slots.
  std::vector<float> normals(4 * faces.size());
  std::unordered_map<uint32_t, uint32_t> slot_of;
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) normals[4 * f + k] = faces.normals[f][k];
    const auto [it, added] = slot_of.try_emplace(faces.instance_ids[f], static_cast<uint32_t>(slot_of.size()));
    if (added) scene->slot_ids_.push_back(faces.instance_ids[f]);
    normals[4 * f + 3] = static_cast<float>(it->second);
  }
  glGenBuffers(1, &scene->normal_buffer_);
  glBindBuffer(GL_TEXTURE_BUFFER, scene->normal_buffer_);
  glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(normals.size() * sizeof(float)), normals.data(),
               GL_STATIC_DRAW);
  glGenTextures(1, &scene->normal_texture_);
  glBindTexture(GL_TEXTURE_BUFFER, scene->normal_texture_);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, scene->normal_buffer_);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);

  scene->bytes_ = scene->mesh_.bytes() + normals.size() * sizeof(float);
  RETURN_IF_ERROR(gl::CheckGl("raster: uploading the scene"));
  return scene;
}

GpuScene::~GpuScene() {
  if (normal_texture_ != 0) glDeleteTextures(1, &normal_texture_);
  if (normal_buffer_ != 0) glDeleteBuffers(1, &normal_buffer_);
}

}  // namespace vscan::raster
