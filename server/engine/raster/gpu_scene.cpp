#include "raster/gpu_scene.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {
namespace {

void FillBuffer(GLenum target, GLuint buffer, size_t bytes, const void* data) {
  glBindBuffer(target, buffer);
  glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
}

}  // namespace

StatusOr<std::unique_ptr<GpuScene>> GpuScene::Upload(const SceneGeometry& geometry, int64_t max_faces) {
  const SceneFaces& faces = *geometry.faces;
  max_faces = std::min<int64_t>(max_faces, std::numeric_limits<GLsizei>::max() / 3);
  if (static_cast<int64_t>(faces.size()) > max_faces) {
    return ResourceExhausted("instances: " + std::to_string(faces.size()) + " triangles exceed the renderer's limit of " +
                             std::to_string(max_faces));
  }
  std::unique_ptr<GpuScene> scene(new GpuScene);
  scene->triangles_ = faces.size();
  if (faces.size() == 0) return scene;

  glGenVertexArrays(1, &scene->vertex_array_);
  glGenBuffers(1, &scene->vertex_buffer_);
  glGenBuffers(1, &scene->index_buffer_);
  glBindVertexArray(scene->vertex_array_);
  FillBuffer(GL_ARRAY_BUFFER, scene->vertex_buffer_, geometry.vertices.size() * sizeof(Eigen::Vector3f),
             geometry.vertices.data());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Eigen::Vector3f), nullptr);
  FillBuffer(GL_ELEMENT_ARRAY_BUFFER, scene->index_buffer_, geometry.indices.size() * sizeof(uint32_t),
             geometry.indices.data());
  glBindVertexArray(0);

  // RGBA32F rather than RGB32F: buffer textures take three-component formats only from GL 4.0.
  std::vector<float> normals(4 * faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) normals[4 * f + k] = faces.normals[f][k];
    normals[4 * f + 3] = 0.0f;
  }
  glGenBuffers(1, &scene->normal_buffer_);
  FillBuffer(GL_TEXTURE_BUFFER, scene->normal_buffer_, normals.size() * sizeof(float), normals.data());
  glGenTextures(1, &scene->normal_texture_);
  glBindTexture(GL_TEXTURE_BUFFER, scene->normal_texture_);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, scene->normal_buffer_);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);

  scene->bytes_ = geometry.vertices.size() * sizeof(Eigen::Vector3f) + geometry.indices.size() * sizeof(uint32_t) +
                  normals.size() * sizeof(float);
  RETURN_IF_ERROR(gl::CheckGl("raster: uploading the scene"));
  return scene;
}

GpuScene::~GpuScene() {
  if (normal_texture_ != 0) glDeleteTextures(1, &normal_texture_);
  const GLuint buffers[] = {vertex_buffer_, index_buffer_, normal_buffer_};
  glDeleteBuffers(3, buffers);
  if (vertex_array_ != 0) glDeleteVertexArrays(1, &vertex_array_);
}

void GpuScene::Draw() const {
  if (triangles_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * triangles_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace vscan::raster
