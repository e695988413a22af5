#include "vscan/render/renderer.h"

#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "offscreen_target.h"
#include "vscan/gl/egl_context.h"
#include "vscan/gl/gl_api.h"
#include "vscan/gl/gl_check.h"
#include "vscan/gl/gl_program.h"
#include "vscan/gl/mesh_buffers.h"

namespace vscan::render {
namespace {

constexpr const char* kPointVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform mat4 clip_from_world;
uniform float point_size;
out vec3 point_colour;
void main() {
  gl_Position = clip_from_world * vec4(position, 1.0);
  gl_PointSize = point_size;
  point_colour = colour;
}
)";

constexpr const char* kPointFragment = R"(#version 330 core
uniform bool round_splats;
in vec3 point_colour;
out vec4 fragment;
void main() {
  vec2 from_centre = gl_PointCoord - vec2(0.5);
  if (round_splats && dot(from_centre, from_centre) > 0.25) discard;
  fragment = vec4(point_colour, 1.0);
}
)";

constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 clip_from_world;
out vec3 world_position;
out vec3 world_normal;
void main() {
  gl_Position = clip_from_world * vec4(position, 1.0);
  world_position = position;
  world_normal = normal;
}
)";

// Two-sided: meshes with inconsistent winding are lit the same on both sides.
constexpr const char* kMeshFragment = R"(#version 330 core
uniform vec3 eye;
uniform float grey;
uniform float ambient;
in vec3 world_position;
in vec3 world_normal;
out vec4 fragment;
void main() {
  vec3 n = world_normal;
  if (dot(n, n) < 1e-20) n = cross(dFdx(world_position), dFdy(world_position));
  float lambert = abs(dot(normalize(n), normalize(eye - world_position)));
  fragment = vec4(vec3(grey * (ambient + (1.0 - ambient) * lambert)), 1.0);
}
)";

// Everything one render owns; the context is released last.
struct Frame {
  std::unique_ptr<gl::EglContext> context;
  std::unique_ptr<OffscreenTarget> target;
  std::unique_ptr<gl::MeshBuffers> buffers;
  GLuint program = 0;

  ~Frame() {
    if (!context) return;
    buffers.reset();
    target.reset();
    glDeleteProgram(program);
  }
};

Status Begin(Frame& frame, const RenderOptions& options, const char* vertex, const char* fragment,
             const char* name) {
  auto context = gl::EglContext::CreateCurrent();
  if (!context.ok()) return Status(context.status().code(), "render: " + context.status().message());
  frame.context = std::move(*context);
  ASSIGN_OR_RETURN(frame.target, OffscreenTarget::Create(options.width, options.height));
  ASSIGN_OR_RETURN(frame.program, gl::BuildProgram(vertex, fragment, name));
  frame.buffers = std::make_unique<gl::MeshBuffers>();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearColor(options.background[0] / 255.0f, options.background[1] / 255.0f, options.background[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(frame.program);
  return gl::CheckGl(std::string("render: ") + name);
}

void SetCamera(GLuint program, const View& view, const Bounds& bounds, const RenderOptions& options) {
  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
  const Eigen::Matrix4f clip_from_world = ClipFromWorld(view, bounds, aspect);
  glUniformMatrix4fv(glGetUniformLocation(program, "clip_from_world"), 1, GL_FALSE, clip_from_world.data());
}

// Area-weighted vertex normals: the sum of the unnormalised face normals around each vertex.
std::vector<Eigen::Vector3f> VertexNormals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3f> normals(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f& a = mesh.vertices[t[0]];
    const Eigen::Vector3f n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
    for (const uint32_t v : t) normals[v] += n;
  }
  for (Eigen::Vector3f& n : normals) {
    if (n.squaredNorm() > 0) n.normalize();
  }
  return normals;
}

}  // namespace

StatusOr<Image> RenderCloud(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& colours,
                            const Bounds& bounds, const View& view, const RenderOptions& options) {
  if (colours.size() != cloud.size()) {
    return InvalidArgument("colours: " + std::to_string(colours.size()) + " for " + std::to_string(cloud.size()) +
                           " points");
  }
  if (cloud.size() > gl::kMaxDrawCount) {
    return ResourceExhausted("render: " + std::to_string(cloud.size()) + " points exceed one draw call's limit of " +
                             std::to_string(gl::kMaxDrawCount));
  }
  Frame frame;
  RETURN_IF_ERROR(Begin(frame, options, kPointVertex, kPointFragment, "points"));
  GLfloat size_range[2] = {1, 1};
  glGetFloatv(GL_POINT_SIZE_RANGE, size_range);
  if (!(options.point_size >= size_range[0] && options.point_size <= size_range[1])) {
    return InvalidArgument("--point-size: " + std::to_string(options.point_size) + " is outside the context's " +
                           std::to_string(size_range[0]) + ".." + std::to_string(size_range[1]));
  }
  glEnable(GL_PROGRAM_POINT_SIZE);
  SetCamera(frame.program, view, bounds, options);
  glUniform1f(glGetUniformLocation(frame.program, "point_size"), options.point_size);
  glUniform1i(glGetUniformLocation(frame.program, "round_splats"), options.point_size >= 3.0f ? 1 : 0);
  frame.buffers->AddAttribute(0, cloud.positions);
  frame.buffers->AddAttribute(1, colours);
  frame.buffers->DrawPoints();
  RETURN_IF_ERROR(gl::CheckGl("render: draw points"));
  return frame.target->ReadRgb();
}

StatusOr<Image> RenderMesh(const TriangleMesh& mesh, const Bounds& bounds, const View& view,
                           const RenderOptions& options) {
  if (mesh.triangles.size() > gl::kMaxDrawCount / 3) {
    return ResourceExhausted("render: " + std::to_string(mesh.triangles.size()) +
                             " triangles exceed one draw call's limit of " + std::to_string(gl::kMaxDrawCount / 3));
  }
  Frame frame;
  RETURN_IF_ERROR(Begin(frame, options, kMeshVertex, kMeshFragment, "mesh"));
  SetCamera(frame.program, view, bounds, options);
  glUniform3fv(glGetUniformLocation(frame.program, "eye"), 1, view.eye.data());
  glUniform1f(glGetUniformLocation(frame.program, "grey"), kMeshGrey);
  glUniform1f(glGetUniformLocation(frame.program, "ambient"), kMeshAmbient);
  frame.buffers->AddAttribute(0, mesh.vertices);
  frame.buffers->AddAttribute(1, VertexNormals(mesh));
  frame.buffers->SetTriangles(mesh.triangles);
  frame.buffers->DrawTriangles();
  RETURN_IF_ERROR(gl::CheckGl("render: draw mesh"));
  return frame.target->ReadRgb();
}

}  // namespace vscan::render
