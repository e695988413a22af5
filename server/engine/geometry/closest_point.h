#pragma once
// The closest point of a triangle to a point, by region tests on the barycentric parameters
// (Ericson, Real-Time Collision Detection, 5.1.5), in float or double.

#include <cmath>

#include <Eigen/Core>

namespace vscan::geometry {

// A degenerate triangle (no area) gives a.
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> ClosestPointOnTriangle(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                   const Eigen::Matrix<Scalar, 3, 1>& a,
                                                   const Eigen::Matrix<Scalar, 3, 1>& b,
                                                   const Eigen::Matrix<Scalar, 3, 1>& c) {
  using Vector = Eigen::Matrix<Scalar, 3, 1>;
  const Vector ab = b - a, ac = c - a, ap = p - a;
  const Scalar d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vector bp = p - b;
  const Scalar d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Scalar vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vector cp = p - c;
  const Scalar d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Scalar vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const Scalar va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const Scalar denominator = va + vb + vc;
  if (!(std::abs(denominator) > 0)) return a;
  return a + ab * (vb / denominator) + ac * (vc / denominator);
}

}  // namespace vscan::geometry
