#include "registration/pair_information.h"

#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "synthetic_shapes.h"

namespace vscan::registration {
namespace {

using V = Eigen::Vector3f;

struct Plane {
  std::vector<V> points;
  std::vector<V> normals;
};

// A 21 x 21 grid with 5 mm spacing on z = 0 whose corner is at (x0, y0), normals +z.
Plane Grid(float x0, float y0) {
  Plane plane;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      plane.points.emplace_back(x0 + 0.005f * static_cast<float>(i), y0 + 0.005f * static_cast<float>(j), 0.0f);
      plane.normals.emplace_back(0.0f, 0.0f, 1.0f);
    }
  }
  return plane;
}

IcpResult Fit(double scale) {
  IcpResult fit;
  fit.rejection_distance = 0.004;
  fit.residual_scale = scale;
  return fit;
}

// For a plane z = 0, J = (y, -x, 0, 0, 0, 1): the sums of y^2, x^2, xy, x, y and the count.
Matrix6d PlaneHessian(const Plane& plane) {
  double sxx = 0, syy = 0, sxy = 0, sx = 0, sy = 0;
  for (const V& p : plane.points) {
    sxx += double{p.x()} * p.x();
    syy += double{p.y()} * p.y();
    sxy += double{p.x()} * p.y();
    sx += p.x();
    sy += p.y();
  }
  Matrix6d h = Matrix6d::Zero();
  h(0, 0) = syy;
  h(1, 1) = sxx;
  h(0, 1) = h(1, 0) = -sxy;
  h(0, 5) = h(5, 0) = sy;
  h(1, 5) = h(5, 1) = -sx;
  h(5, 5) = static_cast<double>(plane.points.size());
  return h;
}

TEST(PairInformationTest, APlaneOnItselfGivesTheClosedFormHessianAtTheFloorScale) {
  const Plane plane = Grid(0.1f, -0.02f);
  const TargetIndex target(plane.points, plane.normals);
  constexpr double kFloor = 1e-5;
  const PairInformation info =
      ComputePairInformation(plane.points, plane.normals, target, Pose3::Identity(), Fit(0.0), IcpOptions{}, kFloor);
  EXPECT_EQ(info.weight_sum, static_cast<double>(plane.points.size()));
  EXPECT_EQ(info.sigma, kFloor);
  const Matrix6d expected = PlaneHessian(plane) / (kFloor * kFloor);
  EXPECT_LT((info.information - expected).norm(), 1e-9 * expected.norm());
  // Sliding in the plane and turning about its normal are not pinned at all.
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(info.information);
  EXPECT_LT(eigen.eigenvalues()[2], 1e-9 * eigen.eigenvalues()[5]);
  EXPECT_GT(eigen.eigenvalues()[3], 1e-6 * eigen.eigenvalues()[5]);
}

TEST(PairInformationTest, ResidualsSetTheScaleAndFarPairsAreLeftOut) {
  const Plane target_plane = Grid(0.0f, 0.0f);
  Plane source = target_plane;
  // Alternate points 0.2 mm above and below the plane; one more point 1 cm above it (beyond the
  // rejection distance).
  for (size_t i = 0; i < source.points.size(); ++i) source.points[i].z() = i % 2 == 0 ? 2e-4f : -2e-4f;
  source.points.emplace_back(0.05f, 0.05f, 0.01f);
  source.normals.emplace_back(0.0f, 0.0f, 1.0f);
  const TargetIndex target(target_plane.points, target_plane.normals);
  IcpOptions options;
  options.kernel = RobustKernel::kNone;
  const PairInformation info =
      ComputePairInformation(source.points, source.normals, target, Pose3::Identity(), Fit(2e-4), options, 1e-6);
  EXPECT_EQ(info.weight_sum, static_cast<double>(target_plane.points.size()));
  EXPECT_NEAR(info.sigma, 2e-4, 1e-9);
  // The residuals do not change the Jacobians: points and normals are those of the target.
  const Matrix6d expected = PlaneHessian(target_plane) / (info.sigma * info.sigma);
  EXPECT_LT((info.information - expected).norm(), 1e-5 * expected.norm());
}

TEST(PairInformationTest, ABoxAndASpherePinEveryDirection) {
  const testing::Cloud cloud = testing::BoxAndSphere(5000, 3);
  const TargetIndex target(cloud.points, cloud.normals);
  const PairInformation info =
      ComputePairInformation(cloud.points, cloud.normals, target, Pose3::Identity(), Fit(1e-4), IcpOptions{}, 1e-4);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(info.information);
  EXPECT_GT(eigen.eigenvalues()[0], 1e-4 * eigen.eigenvalues()[5]);
}

}  // namespace
}  // namespace vscan::registration
