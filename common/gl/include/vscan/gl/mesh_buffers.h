#pragma once
// Vertices and triangles in GPU buffers under one vertex array, drawn with a single call: the one
// upload path for scan scenes and previews. Threading: create, fill, draw and destroy it on the
// thread whose context is current, and destroy it before that context. No GL header here.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::gl {

// The most vertices or triangle indices one draw call takes (GLsizei is 32-bit signed).
inline constexpr uint64_t kMaxDrawCount = 0x7fffffff;

class MeshBuffers {
 public:
  // Creates an empty vertex array; needs a current context. Check GL errors after filling it.
  MeshBuffers();
  ~MeshBuffers();
  MeshBuffers(const MeshBuffers&) = delete;
  MeshBuffers& operator=(const MeshBuffers&) = delete;

  // The vertex shader's vec3 input at `location`, one value per vertex. Every attribute should
  // have as many values as the first; that count is what DrawPoints draws.
  void AddAttribute(uint32_t location, std::span<const Eigen::Vector3f> values);
  // Vertex indices, three per triangle; DrawTriangles draws them.
  void SetTriangles(std::span<const std::array<uint32_t, 3>> triangles);

  // Every triangle with the bound program; triangle i is gl_PrimitiveID i.
  void DrawTriangles() const;
  // Every vertex as a point with the bound program.
  void DrawPoints() const;

  uint64_t vertex_count() const { return vertices_; }
  uint64_t triangle_count() const { return triangles_; }
  // GPU memory the buffers hold.
  uint64_t bytes() const { return bytes_; }

 private:
  uint32_t vertex_array_ = 0;  // GL object names (GLuint)
  uint32_t index_buffer_ = 0;
  std::vector<uint32_t> attribute_buffers_;
  uint64_t vertices_ = 0, triangles_ = 0, bytes_ = 0;
};

}  // namespace vscan::gl
