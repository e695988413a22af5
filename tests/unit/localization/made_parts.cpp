#include "made_parts.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "vscan_test/meshes.h"

namespace vscan::localization::testing {
namespace {

// A right prism over a simple polygon (counter-clockwise seen from +z) whose caps are given as
// triangles of its corners; outward faces.
TriangleMesh Extrude(const std::vector<Eigen::Vector2d>& outline, const std::vector<Eigen::Vector3i>& cap,
                     double height) {
  TriangleMesh mesh;
  const auto n = static_cast<int>(outline.size());
  for (const double z : {0.0, height}) {
    for (const auto& p : outline) mesh.vertices.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(z));
  }
  const auto triangle = [&](int a, int b, int c) {
    mesh.triangles.push_back({static_cast<uint32_t>(a), static_cast<uint32_t>(b), static_cast<uint32_t>(c)});
  };
  for (const Eigen::Vector3i& t : cap) {
    triangle(t[0], t[2], t[1]);              // bottom, facing -z
    triangle(t[0] + n, t[1] + n, t[2] + n);  // top, facing +z
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    triangle(i, j, j + n);
    triangle(i, j + n, i + n);
  }
  return mesh;
}

Pose3 TurnAbout(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& through) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  pose.translation() = through - pose.linear() * through;
  return pose;
}

}  // namespace

MadePart Prism(int sides, double radius, double height) {
  std::vector<Eigen::Vector2d> outline;
  std::vector<Eigen::Vector3i> cap;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides;
    outline.emplace_back(radius * std::cos(a), radius * std::sin(a));
    if (i >= 2) cap.emplace_back(0, i - 1, i);
  }
  MadePart part{std::make_shared<TriangleMesh>(Extrude(outline, cap, height)), {}};
  const Eigen::Vector3d middle(0, 0, height / 2);
  for (int i = 1; i < sides; ++i) part.symmetries.discrete.push_back(TurnAbout(Eigen::Vector3d::UnitZ(), 2 * std::numbers::pi * i / sides, middle));
  for (int i = 0; i < sides; ++i) {
    // Half turns about the axes in the middle plane through a corner or an edge's middle.
    const double a = std::numbers::pi * i / sides;
    part.symmetries.discrete.push_back(TurnAbout(Eigen::Vector3d(std::cos(a), std::sin(a), 0), std::numbers::pi, middle));
  }
  return part;
}

MadePart Bracket(double long_arm, double short_arm, double arm_width, double thickness) {
  // The L's corners, counter-clockwise from the origin; its caps are the two rectangles it is made of.
  const std::vector<Eigen::Vector2d> outline = {{0, 0}, {long_arm, 0}, {long_arm, arm_width}, {arm_width, arm_width},
                                                {arm_width, short_arm}, {0, short_arm}};
  const std::vector<Eigen::Vector3i> cap = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  return {std::make_shared<TriangleMesh>(Extrude(outline, cap, thickness)), {}};
}

MadePart SquarePin(double length, double side) {
  MadePart part{test::Share(test::MakeBox(Eigen::Vector3d(0, -side / 2, 0), Eigen::Vector3d(length, side / 2, side))), {}};
  const Eigen::Vector3d middle(length / 2, 0, side / 2);
  for (int i = 1; i < 4; ++i) part.symmetries.discrete.push_back(TurnAbout(Eigen::Vector3d::UnitX(), std::numbers::pi / 2 * i, middle));
  for (int i = 0; i < 4; ++i) {
    const Pose3 flip = TurnAbout(Eigen::Vector3d::UnitZ(), std::numbers::pi, middle);
    part.symmetries.discrete.push_back(TurnAbout(Eigen::Vector3d::UnitX(), std::numbers::pi / 2 * i, middle) * flip);
  }
  return part;
}

}  // namespace vscan::localization::testing
