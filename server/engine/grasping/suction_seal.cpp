#include "grasping/suction_seal.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "grasping/grasp_kinds.h"

namespace vscan::grasping {
namespace {

// A sample below the plane whose normal faces this far away belongs to the far side of a thin wall.
constexpr double kBackFacingCos = -0.25;

}  // namespace

DiscCells::DiscCells(int cells) : k(cells), inside(size_t(cells) * cells) {
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const double x = (i + 0.5) / k * 2 - 1, y = (j + 0.5) / k * 2 - 1;
      inside[size_t(i) * k + j] = x * x + y * y <= 1;
      count += inside[size_t(i) * k + j];
    }
}

DiscCells DiscCellsFor(const SurfaceSamples& dense, const SuctionCup& cup) {
  const double spacing = std::sqrt(dense.area / double(dense.points.size()));
  return DiscCells(std::clamp(int(cup.diameter_m / (2 * spacing)), 4, 16));
}

SealCheck CheckSeal(const SurfaceSamples& dense, const SampleGrid& grid, const DiscCells& disc,
                    const Eigen::Vector3d& p, const Eigen::Vector3d& n, const SuctionCup& cup,
                    double tolerance) {
  const double r = cup.diameter_m / 2;
  const double cos_tilt = std::cos(cup.max_tilt_deg * std::numbers::pi / 180);
  Eigen::Vector3d u, v;
  PerpendicularBasis(n, u, v);
  const double reach = std::max(r, cup.stroke_m);
  std::vector<char> occupied(disc.inside.size(), 0);
  bool blocked = false;
  double max_deviation = 0, min_cos = 1;
  grid.VisitBox(p.array() - reach, p.array() + reach, [&](uint32_t i) {
    if (blocked) return;
    const Eigen::Vector3d d = dense.points[i] - p;
    const double h = d.dot(n);
    if (h > cup.stroke_m || h < -r) return;
    const double x = d.dot(u), y = d.dot(v);
    if (x * x + y * y > r * r) return;
    const double c = dense.normals[i].dot(n);
    if (h < -tolerance && c < kBackFacingCos) return;
    if (std::abs(h) > tolerance || c < cos_tilt) {
      blocked = true;  // an edge, a hole's wall, curvature or something inside the cup's column
      return;
    }
    max_deviation = std::max(max_deviation, std::abs(h));
    min_cos = std::min(min_cos, c);
    const int ci = std::clamp(int((x + r) / (2 * r) * disc.k), 0, disc.k - 1);
    const int cj = std::clamp(int((y + r) / (2 * r) * disc.k), 0, disc.k - 1);
    occupied[size_t(ci) * disc.k + cj] = 1;
  });
  if (blocked) return {};
  int covered = 0;
  for (size_t c = 0; c < occupied.size(); ++c) covered += occupied[c] && disc.inside[c];
  const double coverage = double(covered) / disc.count;
  if (coverage < cup.min_flat_fraction) return {};
  const double tilt = std::acos(std::clamp(min_cos, -1.0, 1.0)) * 180 / std::numbers::pi;
  const double quality = coverage * (1 - 0.5 * max_deviation / tolerance) * (1 - 0.5 * tilt / cup.max_tilt_deg);
  return {true, std::clamp(quality, 0.0, 1.0)};
}

}  // namespace vscan::grasping
