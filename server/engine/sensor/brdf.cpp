#include "sensor/brdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vscan::sensor {

double GgxDistribution(double cos_h, double alpha) {
  if (cos_h <= 0) return 0;
  const double a2 = alpha * alpha;
  const double d = cos_h * cos_h * (a2 - 1) + 1;
  return a2 / (std::numbers::pi * d * d);
}

double GgxMasking(double cos_v, double alpha) {
  if (cos_v <= 0) return 0;
  const double a2 = alpha * alpha;
  return 2 * cos_v / (cos_v + std::sqrt(a2 + (1 - a2) * cos_v * cos_v));
}

double SchlickFresnel(double f0, double cos_d) {
  const double f90 = std::min(1.0, 50 * f0);
  const double x = 1 - std::clamp(cos_d, 0.0, 1.0), x2 = x * x;  // (1 - c)^5 without pow, per ray
  return f0 + (f90 - f0) * x2 * x2 * x;
}

double EvaluateBrdf(const Material& material, const Eigen::Vector3d& normal, const Eigen::Vector3d& to_light,
                    const Eigen::Vector3d& to_viewer) {
  const double cos_l = normal.dot(to_light), cos_v = normal.dot(to_viewer);
  if (!(cos_l > 0) || !(cos_v > 0)) return 0;
  const Eigen::Vector3d half = (to_light + to_viewer).normalized();
  const double cos_h = normal.dot(half);
  const double f0 = (1 - material.metallic) * material.specular_reflectance + material.metallic * material.albedo;
  // h.v == h.l, so the Fresnel term, and with it the whole BRDF, is the same both ways round.
  const double fresnel = SchlickFresnel(f0, half.dot(to_viewer));
  const double roughness = std::max(material.roughness, kMinRoughness);
  const double alpha = roughness * roughness, a2 = alpha * alpha;
  // G1(l) G1(v) / (4 n.l n.v) with G1(c) = 2c / (c + sqrt(a2 + (1 - a2) c^2)): one division, not three.
  const double visibility = 1.0 / ((cos_l + std::sqrt(a2 + (1 - a2) * cos_l * cos_l)) *
                                   (cos_v + std::sqrt(a2 + (1 - a2) * cos_v * cos_v)));
  const double specular = GgxDistribution(cos_h, alpha) * visibility * fresnel;
  // Light that enters the surface crosses its interface twice, in along l and out along v; weighting
  // by h.v instead would return more than arrives at grazing views.
  const double diffuse = (1 - material.metallic) * (1 - SchlickFresnel(f0, cos_l)) * (1 - SchlickFresnel(f0, cos_v)) *
                         material.albedo / std::numbers::pi;
  return diffuse + specular;
}

}  // namespace vscan::sensor
