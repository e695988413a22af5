#pragma once
// The shader programs of the raster scanner: the two methods, each also with the returned light's
// direct term (direct_light_glsl.h) written to an R32F attachment.

#include "vscan/common/status.h"
#include "vscan/gl/gl_api.h"

namespace vscan::raster {

// The lit programs' uniforms for the direct term; -1 in the plain programs.
struct LightUniforms {
  GLint face_normals = -1;  // xyz: normal, w: material slot
  GLint eye = -1;           // camera centre, scene frame
  GLint materials = -1;
  GLint emitter_position = -1;
  GLint emitter_axis = -1;
  GLint emitter = -1;  // (radiant intensity, cos(cone half angle))
};

// Depth-buffer method: writes the face index + 1 (0 = background) to an R32UI attachment; the
// depth buffer holds the rest.
struct DepthProgram {
  GLuint id = 0;
  GLint clip_from_scene = -1;
  LightUniforms direct;
};

// Colour-buffer method, as in the paper: the ray length camera-to-fragment as a 16-bit code in
// G (high byte) and B (low byte) of an RGBA8 attachment, the attenuated intensity in R; and the
// face index + 1 in the R32UI attachment as above.
struct ColourProgram {
  GLuint id = 0;
  GLint clip_from_scene = -1;
  GLint eye = -1;         // camera centre, scene frame
  GLint range_code = -1;  // (near_range, 65535 / (far_range - near_range))
  GLint light = -1;       // (constant, linear, quadratic, power / max_intensity)
  GLint face_normals = -1;
  LightUniforms direct;
};

struct ScanPrograms {
  DepthProgram depth;
  ColourProgram colour;
  DepthProgram lit_depth;
  ColourProgram lit_colour;

  static StatusOr<ScanPrograms> Build();
  ScanPrograms() = default;
  ScanPrograms(ScanPrograms&& other) noexcept;
  ScanPrograms& operator=(ScanPrograms&&) = delete;
  ~ScanPrograms();
};

}  // namespace vscan::raster
