#include "raster/direct_light_glsl.h"

namespace vscan::raster {

// Line for line sensor::GgxDistribution, SchlickFresnel, EvaluateBrdf (Smith's masking as its
// one-division visibility) and DirectRadiance, in single precision, but for one rearrangement:
// GGX's denominator cos^2 (alpha^2 - 1) + 1 is written cos^2 alpha^2 + sin^2 with sin from a cross
// product, since 1 - cos^2 in float loses the narrow lobe of a polished surface (1% at roughness 0.08).
const char* const kDirectLightGlsl = R"(
uniform samplerBuffer materials;  // per slot: albedo, metallic, roughness, specular_reflectance
uniform vec3 emitter_position;    // scene frame
uniform vec3 emitter_axis;        // scene frame, unit
uniform vec2 emitter;             // radiant intensity (W/sr), cos(cone half angle) (-2: no cone)
layout(location = 2) out float radiance;

const float kPi = 3.14159265358979;
const float kMinRoughness = 0.02;

float GgxDistribution(float cos_h, float sin2_h, float alpha) {
  if (cos_h <= 0.0) return 0.0;
  float a2 = alpha * alpha;
  float d = cos_h * cos_h * a2 + sin2_h;
  return a2 / (kPi * d * d);
}

float SchlickFresnel(float f0, float cos_d) {
  float f90 = min(1.0, 50.0 * f0);
  float x = 1.0 - clamp(cos_d, 0.0, 1.0), x2 = x * x;
  return f0 + (f90 - f0) * x2 * x2 * x;
}

// m = (albedo, metallic, roughness, specular_reflectance).
float EvaluateBrdf(vec4 m, vec3 n, vec3 l, vec3 v) {
  float cos_l = dot(n, l), cos_v = dot(n, v);
  if (!(cos_l > 0.0) || !(cos_v > 0.0)) return 0.0;
  vec3 h = normalize(l + v);
  float cos_h = dot(n, h);
  vec3 sin_h = cross(n, h);
  float f0 = (1.0 - m.y) * m.w + m.y * m.x;
  float fresnel = SchlickFresnel(f0, dot(h, v));
  float roughness = max(m.z, kMinRoughness);
  float alpha = roughness * roughness, a2 = alpha * alpha;
  // G1(l) G1(v) / (4 n.l n.v), Smith's masking for GGX in both directions, in one division.
  float visibility = 1.0 / ((cos_l + sqrt(a2 + (1.0 - a2) * cos_l * cos_l)) *
                            (cos_v + sqrt(a2 + (1.0 - a2) * cos_v * cos_v)));
  float specular = GgxDistribution(cos_h, dot(sin_h, sin_h), alpha) * visibility * fresnel;
  float diffuse = (1.0 - m.y) * (1.0 - SchlickFresnel(f0, cos_l)) * (1.0 - SchlickFresnel(f0, cos_v)) * m.x / kPi;
  return diffuse + specular;
}

float DirectRadiance(vec4 m, vec3 p, vec3 n, vec3 camera) {
  vec3 to_emitter = emitter_position - p;
  float d2 = dot(to_emitter, to_emitter);
  if (!(d2 > 0.0)) return 0.0;
  vec3 l = to_emitter / sqrt(d2);
  if (-dot(l, emitter_axis) < emitter.y) return 0.0;
  vec3 v = normalize(camera - p);
  float cos_l = dot(n, l);
  if (!(cos_l > 0.0)) return 0.0;
  return EvaluateBrdf(m, n, l, v) * emitter.x * cos_l / d2;
}

float SurfaceRadiance(vec4 face, vec3 p, vec3 camera) {
  vec3 n = face.xyz;
  if (dot(n, p - camera) > 0.0) n = -n;  // the side the camera sees, as the decoded normals
  return DirectRadiance(texelFetch(materials, int(face.w)), p, n, camera);
}
)";

}  // namespace vscan::raster
