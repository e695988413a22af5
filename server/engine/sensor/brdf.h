#pragma once
// The reflectance of a Material: a Lambertian diffuse term and a GGX microfacet specular term
// (Walter et al. 2007) with separable Smith masking-shadowing and Schlick's Fresnel.

#include <Eigen/Core>

#include "sensor/material.h"

namespace vscan::sensor {

// The BRDF in 1/sr for light arriving from direction `to_light` and leaving towards `to_viewer`
// (unit vectors pointing away from the surface), about the unit normal `normal`:
//   f = (1 - metallic) (1 - F) albedo / pi + D G F / (4 (n.l) (n.v)),
//   F = SchlickFresnel(F0, h.v), F0 = (1 - metallic) specular_reflectance + metallic albedo,
//   D = GGX(alpha = max(roughness, kMinRoughness)^2), G = G1(l) G1(v).
// Zero when either direction lies at or below the surface. Reciprocal in its two directions.
double EvaluateBrdf(const Material& material, const Eigen::Vector3d& normal, const Eigen::Vector3d& to_light,
                    const Eigen::Vector3d& to_viewer);

// Schlick's Fresnel F0 + (F90 - F0) (1 - cos_d)^5 with F90 = min(1, 50 F0) (Schuler 2009, as
// Filament does): F90 is 1 for every real surface (F0 >= 0.02), and F0 = 0 reflects nothing at any
// angle, so that such a dielectric is exactly Lambertian.
double SchlickFresnel(double f0, double cos_d);
// GGX's normal distribution D(h) for cos(theta_h) = n.h and width alpha.
double GgxDistribution(double cos_h, double alpha);
// Smith's masking for GGX, one direction at cos(theta) = n.v.
double GgxMasking(double cos_v, double alpha);

}  // namespace vscan::sensor
