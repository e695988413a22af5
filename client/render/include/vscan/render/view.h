#pragma once
// Where the preview camera stands and how it projects: a pinhole with a fixed vertical field of
// view, looking from eye at target.

#include <optional>

#include <Eigen/Core>

namespace vscan::render {

inline constexpr float kVerticalFovDeg = 40.0f;

struct View {
  Eigen::Vector3f eye = Eigen::Vector3f(1, 0, 0);
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();
};

// Axis-aligned bounds of what is drawn.
struct Bounds {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  Eigen::Vector3f Centre() const { return (min + max) / 2; }
  float Radius() const { return (max - min).norm() / 2; }
};

// The direction the default view looks from, in the frame of up: equal parts "x", "-y" and up,
// where x is the world x axis made perpendicular to up (the y axis when up is along x).
Eigen::Vector3f ObliqueDirection(const Eigen::Vector3f& up);

// The box fills at most this fraction of the image's width or height in a fitted view.
inline constexpr float kFitFill = 0.95f;

// Looks at target (the box centre when not given) along ObliqueDirection(up), from the nearest
// distance at which every corner of the box lies within kFitFill of the image's half-width and
// half-height.
View FitView(const Bounds& bounds, const Eigen::Vector3f& up, const std::optional<Eigen::Vector3f>& target,
             float aspect);

// OpenGL clip coordinates from world coordinates for an image of the given aspect (width / height);
// near and far enclose the bounds as seen from the eye.
Eigen::Matrix4f ClipFromWorld(const View& view, const Bounds& bounds, float aspect);

}  // namespace vscan::render
