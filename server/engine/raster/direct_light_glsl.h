#pragma once
// GLSL of the returned light's direct term, a float mirror of sensor/brdf.cpp and
// sensor::DirectRadiance, for the fragment shaders of scan_programs.cpp.

namespace vscan::raster {

// Declares the emitter and material uniforms, the R32F output `radiance` at location 2, and
// float SurfaceRadiance(vec4 face, vec3 p, vec3 camera): face = (normal, material slot) as the
// face_normals buffer holds it, p and camera in the scene frame.
extern const char* const kDirectLightGlsl;

}  // namespace vscan::raster
