#include "raster/scan_programs.h"

#include <string>
#include <utility>

#include "vscan/gl/gl_check.h"
#include "vscan/gl/gl_program.h"

namespace vscan::raster {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 clip_from_scene;
out vec3 scene_position;
void main() {
  scene_position = position;
  gl_Position = clip_from_scene * vec4(position, 1.0);
}
)";

constexpr const char* kDepthFragmentShader = R"(#version 330 core
layout(location = 0) out uint face;
void main() { face = uint(gl_PrimitiveID) + 1u; }
)";

// Without a geometry shader gl_PrimitiveID counts the triangles of the draw call, which draws the
// whole scene, so it indexes the scene's face arrays.
constexpr const char* kColourFragmentShader = R"(#version 330 core
uniform samplerBuffer face_normals;
uniform vec3 eye;
uniform vec2 range_code;
uniform vec4 light;
in vec3 scene_position;
layout(location = 0) out uint face;
layout(location = 1) out vec4 colour;
void main() {
  vec3 ray = scene_position - eye;
  float range = length(ray);
  vec3 normal = texelFetch(face_normals, gl_PrimitiveID).xyz;
  float cos_incidence = abs(dot(normal, ray)) / range;
  float attenuation = light.x + (light.y + light.z * range) * range;
  float code = clamp(round((range - range_code.x) * range_code.y), 0.0, 65535.0);
  float high = floor(code / 256.0);
  // A quarter step up lands on the same byte whether the unorm conversion rounds or truncates.
  colour = vec4(clamp(light.w * cos_incidence / attenuation, 0.0, 1.0), (high + 0.25) / 255.0,
                (code - high * 256.0 + 0.25) / 255.0, 1.0);
  face = uint(gl_PrimitiveID) + 1u;
}
)";

StatusOr<GLuint> Link(const char* fragment_source, const char* name) {
  auto program = gl::BuildProgram(kVertexShader, fragment_source, name);
  if (!program.ok()) return Internal("raster: " + program.status().message());
  return program;
}

}  // namespace

StatusOr<ScanPrograms> ScanPrograms::Build() {
  ScanPrograms programs;
  ASSIGN_OR_RETURN(programs.depth.id, Link(kDepthFragmentShader, "depth"));
  programs.depth.clip_from_scene = glGetUniformLocation(programs.depth.id, "clip_from_scene");
  ASSIGN_OR_RETURN(programs.colour.id, Link(kColourFragmentShader, "colour"));
  const GLuint c = programs.colour.id;
  programs.colour.clip_from_scene = glGetUniformLocation(c, "clip_from_scene");
  programs.colour.eye = glGetUniformLocation(c, "eye");
  programs.colour.range_code = glGetUniformLocation(c, "range_code");
  programs.colour.light = glGetUniformLocation(c, "light");
  programs.colour.face_normals = glGetUniformLocation(c, "face_normals");
  RETURN_IF_ERROR(gl::CheckGl("raster: building shader programs"));
  return programs;
}

ScanPrograms::ScanPrograms(ScanPrograms&& other) noexcept
    : depth(std::exchange(other.depth, {})), colour(std::exchange(other.colour, {})) {}

ScanPrograms::~ScanPrograms() {
  if (depth.id != 0) glDeleteProgram(depth.id);
  if (colour.id != 0) glDeleteProgram(colour.id);
}

}  // namespace vscan::raster
