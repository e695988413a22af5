#pragma once
// Analytic inputs for the render tests.

#include <array>
#include <cstdint>
#include <functional>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/render/image.h"
#include "vscan/render/view.h"

namespace vscan::render::test {

// Points on a regular grid of samples x samples over [-half, half]^2, mapped to 3D by place(u, v).
PointCloud GridCloud(float half, int samples, const std::function<Eigen::Vector3f(float, float)>& place);

Bounds BoundsOf(const std::vector<Eigen::Vector3f>& points);

// The index t/(n-1) of the Turbo sample nearest in RGB to the pixel.
float InverseTurbo(const std::array<uint8_t, 3>& rgb);

}  // namespace vscan::render::test
