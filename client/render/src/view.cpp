#include "vscan/render/view.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace vscan::render {
namespace {

float TanHalfVertical() { return std::tan(kVerticalFovDeg * std::numbers::pi_v<float> / 360.0f); }

Eigen::Matrix4f WorldToCamera(const View& view) {
  const Eigen::Vector3f forward = (view.target - view.eye).normalized();
  Eigen::Vector3f right = forward.cross(view.up);
  // An up parallel to the line of sight leaves no roll; any perpendicular will do.
  if (right.squaredNorm() < 1e-12f) right = forward.unitOrthogonal();
  right.normalize();
  const Eigen::Vector3f camera_up = right.cross(forward);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = right.transpose();
  m.block<1, 3>(1, 0) = camera_up.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -right.dot(view.eye);
  m(1, 3) = -camera_up.dot(view.eye);
  m(2, 3) = forward.dot(view.eye);
  return m;
}

}  // namespace

Eigen::Vector3f ObliqueDirection(const Eigen::Vector3f& up_in) {
  const Eigen::Vector3f up = up_in.normalized();
  Eigen::Vector3f x = Eigen::Vector3f::UnitX() - up.x() * up;
  if (x.squaredNorm() < 1e-6f) x = Eigen::Vector3f::UnitY() - up.y() * up;
  x.normalize();
  const Eigen::Vector3f y = up.cross(x);
  return (x - y + up).normalized();
}

View FitView(const Bounds& bounds, const Eigen::Vector3f& up, const std::optional<Eigen::Vector3f>& target,
             float aspect) {
  View view;
  view.up = up;
  view.target = target.value_or(bounds.Centre());
  const Eigen::Vector3f back = ObliqueDirection(up);  // from the target towards the eye
  const Eigen::Vector3f right = (-back).cross(up).normalized();
  const Eigen::Vector3f camera_up = right.cross(-back);
  const float tan_v = TanHalfVertical() * kFitFill, tan_h = tan_v * aspect;
  // A corner at p from the target, seen from distance d, is in view when |p.right| <= (d - p.back) tan_h
  // and |p.camera_up| <= (d - p.back) tan_v.
  float distance = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3f p =
        Eigen::Vector3f((corner & 1) ? bounds.max.x() : bounds.min.x(), (corner & 2) ? bounds.max.y() : bounds.min.y(),
                        (corner & 4) ? bounds.max.z() : bounds.min.z()) -
        view.target;
    const float along = p.dot(back);
    distance = std::max({distance, along + std::abs(p.dot(right)) / tan_h, along + std::abs(p.dot(camera_up)) / tan_v});
  }
  view.eye = view.target + std::max(distance, 1e-6f) * back;
  return view;
}

Eigen::Matrix4f ClipFromWorld(const View& view, const Bounds& bounds, float aspect) {
  const float centre_distance = (bounds.Centre() - view.eye).norm();
  const float radius = bounds.Radius();
  const float far_plane = std::max((centre_distance + radius) * 1.01f, 1e-5f);
  const float near_plane = std::max(centre_distance - radius, far_plane * 1e-4f) * 0.99f;
  const float t = TanHalfVertical();
  Eigen::Matrix4f projection = Eigen::Matrix4f::Zero();
  projection(0, 0) = 1 / (t * aspect);
  projection(1, 1) = 1 / t;
  projection(2, 2) = -(far_plane + near_plane) / (far_plane - near_plane);
  projection(2, 3) = -2 * far_plane * near_plane / (far_plane - near_plane);
  projection(3, 2) = -1;
  return projection * WorldToCamera(view);
}

}  // namespace vscan::render
