#include "grasping/gripper_sweep.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vscan::grasping {
namespace {

void AddQuad(TriangleMesh& mesh, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  mesh.triangles.push_back({a, b, c});
  mesh.triangles.push_back({a, c, d});
}

std::vector<TriangleMesh> CupSweep(const SuctionCup& cup, const ToolSweep& sweep) {
  return {CylinderMesh(cup.diameter_m / 2, -(sweep.body_length_m + sweep.approach_m), 0)};
}

std::vector<TriangleMesh> JawSweep(const ParallelJaws& jaws, const ToolSweep& sweep) {
  const double half_w = jaws.finger_width_m / 2, inner = jaws.max_opening_m / 2;
  const double outer = inner + jaws.finger_thickness_m;
  const double tip = jaws.finger_depth_m / 2;
  const double root = std::min(tip - jaws.finger_length_m, -1e-4);  // where the fingers meet the palm
  const double back = std::min(-sweep.body_length_m, root - 1e-4);
  std::vector<TriangleMesh> out;
  for (double side : {-1.0, 1.0}) {
    const double y0 = side * inner, y1 = side * outer;
    out.push_back(BoxMesh({-half_w, std::min(y0, y1), root - sweep.approach_m}, {half_w, std::max(y0, y1), tip}));
  }
  out.push_back(BoxMesh({-half_w, -outer, back - sweep.approach_m}, {half_w, outer, root}));
  return out;
}

}  // namespace

TriangleMesh BoxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(float(i & 1 ? hi.x() : lo.x()), float(i & 2 ? hi.y() : lo.y()),
                               float(i & 4 ? hi.z() : lo.z()));
  }
  AddQuad(mesh, 0, 2, 3, 1);  // z low
  AddQuad(mesh, 4, 5, 7, 6);  // z high
  AddQuad(mesh, 0, 1, 5, 4);  // y low
  AddQuad(mesh, 2, 6, 7, 3);  // y high
  AddQuad(mesh, 0, 4, 6, 2);  // x low
  AddQuad(mesh, 1, 3, 7, 5);  // x high
  return mesh;
}

TriangleMesh CylinderMesh(double radius, double z_lo, double z_hi, int sides) {
  TriangleMesh mesh;
  const double r = radius / std::cos(std::numbers::pi / sides);
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides;
    mesh.vertices.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), float(z_lo));
    mesh.vertices.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), float(z_hi));
  }
  const auto n = uint32_t(sides);
  const uint32_t bottom = 2 * n, top = 2 * n + 1;
  mesh.vertices.emplace_back(0.f, 0.f, float(z_lo));
  mesh.vertices.emplace_back(0.f, 0.f, float(z_hi));
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    AddQuad(mesh, 2 * i, 2 * j, 2 * j + 1, 2 * i + 1);
    mesh.triangles.push_back({bottom, 2 * j, 2 * i});
    mesh.triangles.push_back({top, 2 * i + 1, 2 * j + 1});
  }
  return mesh;
}

std::vector<TriangleMesh> GripperSweep(const Gripper& gripper, const ToolSweep& sweep) {
  if (const auto* cup = std::get_if<SuctionCup>(&gripper)) return CupSweep(*cup, sweep);
  return JawSweep(std::get<ParallelJaws>(gripper), sweep);
}

}  // namespace vscan::grasping
