#include "normals/plane_fit.h"

#include <Eigen/Eigenvalues>

namespace vscan::normals {

Eigen::Vector3f FitPlaneNormal(const spatial::KdTree& tree, std::span<const spatial::Neighbor> neighbours) {
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const spatial::Neighbor& nb : neighbours) centroid += tree.point(nb.slot);
  centroid /= static_cast<float>(neighbours.size());

  // Centring first keeps float accuracy independent of how far the cloud is from the origin.
  float xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (const spatial::Neighbor& nb : neighbours) {
    const Eigen::Vector3f d = tree.point(nb.slot) - centroid;
    xx += d.x() * d.x();
    xy += d.x() * d.y();
    xz += d.x() * d.z();
    yy += d.y() * d.y();
    yz += d.y() * d.z();
    zz += d.z() * d.z();
  }
  Eigen::Matrix3f cov;
  cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver;
  solver.computeDirect(cov, Eigen::ComputeEigenvectors);
  // Eigenvalues come sorted ascending.
  return solver.eigenvectors().col(0).normalized();
}

}  // namespace vscan::normals
