#include "raster/scan_programs.h"

#include <string>
#include <utility>

#include "raster/direct_light_glsl.h"
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

constexpr const char* kVersion = "#version 330 core\n";

// With DIRECT_LIGHT (kDirectLightGlsl before it) the depth method needs the normals and the eye too.
constexpr const char* kDepthFragmentShader = R"(
layout(location = 0) out uint face;
#ifdef DIRECT_LIGHT
uniform samplerBuffer face_normals;
uniform vec3 eye;
in vec3 scene_position;
#endif
void main() {
  face = uint(gl_PrimitiveID) + 1u;
#ifdef DIRECT_LIGHT
  radiance = SurfaceRadiance(texelFetch(face_normals, gl_PrimitiveID), scene_position, eye);
#endif
}
)";

// Without a geometry shader gl_PrimitiveID counts the triangles of the draw call, which draws the
// whole scene, so it indexes the scene's face arrays.
constexpr const char* kColourFragmentShader = R"(
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
#ifdef DIRECT_LIGHT
  radiance = SurfaceRadiance(texelFetch(face_normals, gl_PrimitiveID), scene_position, eye);
#endif
}
)";

StatusOr<GLuint> Link(const char* body, bool lit, const char* name) {
  std::string fragment = kVersion;
  if (lit) fragment += std::string("#define DIRECT_LIGHT\n") + kDirectLightGlsl;
  fragment += body;
  auto program = gl::BuildProgram(kVertexShader, fragment.c_str(), name);
  if (!program.ok()) return Internal("raster: " + program.status().message());
  return program;
}

void LocateLight(GLuint id, LightUniforms& u) {
  u.face_normals = glGetUniformLocation(id, "face_normals");
  u.eye = glGetUniformLocation(id, "eye");
  u.materials = glGetUniformLocation(id, "materials");
  u.emitter_position = glGetUniformLocation(id, "emitter_position");
  u.emitter_axis = glGetUniformLocation(id, "emitter_axis");
  u.emitter = glGetUniformLocation(id, "emitter");
}

StatusOr<DepthProgram> BuildDepth(bool lit) {
  DepthProgram p;
  ASSIGN_OR_RETURN(p.id, Link(kDepthFragmentShader, lit, lit ? "lit depth" : "depth"));
  p.clip_from_scene = glGetUniformLocation(p.id, "clip_from_scene");
  if (lit) LocateLight(p.id, p.direct);
  return p;
}

StatusOr<ColourProgram> BuildColour(bool lit) {
  ColourProgram p;
  ASSIGN_OR_RETURN(p.id, Link(kColourFragmentShader, lit, lit ? "lit colour" : "colour"));
  const GLuint c = p.id;
  p.clip_from_scene = glGetUniformLocation(c, "clip_from_scene");
  p.eye = glGetUniformLocation(c, "eye");
  p.range_code = glGetUniformLocation(c, "range_code");
  p.light = glGetUniformLocation(c, "light");
  p.face_normals = glGetUniformLocation(c, "face_normals");
  if (lit) LocateLight(c, p.direct);
  return p;
}

}  // namespace

StatusOr<ScanPrograms> ScanPrograms::Build() {
  ScanPrograms programs;
  ASSIGN_OR_RETURN(programs.depth, BuildDepth(false));
  ASSIGN_OR_RETURN(programs.colour, BuildColour(false));
  ASSIGN_OR_RETURN(programs.lit_depth, BuildDepth(true));
  ASSIGN_OR_RETURN(programs.lit_colour, BuildColour(true));
  RETURN_IF_ERROR(gl::CheckGl("raster: building shader programs"));
  return programs;
}

ScanPrograms::ScanPrograms(ScanPrograms&& other) noexcept
    : depth(std::exchange(other.depth, {})),
      colour(std::exchange(other.colour, {})),
      lit_depth(std::exchange(other.lit_depth, {})),
      lit_colour(std::exchange(other.lit_colour, {})) {}

ScanPrograms::~ScanPrograms() {
  for (const GLuint id : {depth.id, colour.id, lit_depth.id, lit_colour.id}) {
    if (id != 0) glDeleteProgram(id);
  }
}

}  // namespace vscan::raster
