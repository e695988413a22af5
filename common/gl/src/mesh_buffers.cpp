#include "vscan/gl/mesh_buffers.h"

#include <type_traits>

#include "vscan/gl/gl_api.h"

namespace vscan::gl {

static_assert(std::is_same_v<GLuint, uint32_t>, "GL object names are kept as uint32_t in the header");
static_assert(sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t), "triangles upload as packed indices");

namespace {

// Fills a new buffer bound to `target` within the bound vertex array.
GLuint NewBuffer(GLenum target, size_t bytes, const void* data) {
  GLuint buffer = 0;
  glGenBuffers(1, &buffer);
  glBindBuffer(target, buffer);
  glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
  return buffer;
}

}  // namespace

MeshBuffers::MeshBuffers() { glGenVertexArrays(1, &vertex_array_); }

MeshBuffers::~MeshBuffers() {
  if (!attribute_buffers_.empty()) {
    glDeleteBuffers(static_cast<GLsizei>(attribute_buffers_.size()), attribute_buffers_.data());
  }
  if (index_buffer_ != 0) glDeleteBuffers(1, &index_buffer_);
  if (vertex_array_ != 0) glDeleteVertexArrays(1, &vertex_array_);
}

void MeshBuffers::AddAttribute(uint32_t location, std::span<const Eigen::Vector3f> values) {
  if (attribute_buffers_.empty()) vertices_ = values.size();
  glBindVertexArray(vertex_array_);
  attribute_buffers_.push_back(NewBuffer(GL_ARRAY_BUFFER, values.size_bytes(), values.data()));
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, 3, GL_FLOAT, GL_FALSE, sizeof(Eigen::Vector3f), nullptr);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  bytes_ += values.size_bytes();
}

void MeshBuffers::SetTriangles(std::span<const std::array<uint32_t, 3>> triangles) {
  glBindVertexArray(vertex_array_);
  if (index_buffer_ != 0) {
    glDeleteBuffers(1, &index_buffer_);
    bytes_ -= triangles_ * sizeof(triangles[0]);
  }
  // The element buffer binding is part of the vertex array, so it is bound while that is.
  index_buffer_ = NewBuffer(GL_ELEMENT_ARRAY_BUFFER, triangles.size_bytes(), triangles.data());
  glBindVertexArray(0);
  triangles_ = triangles.size();
  bytes_ += triangles.size_bytes();
}

void MeshBuffers::DrawTriangles() const {
  if (triangles_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * triangles_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

void MeshBuffers::DrawPoints() const {
  if (vertices_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(vertices_));
  glBindVertexArray(0);
}

}  // namespace vscan::gl
