#pragma once
// The registration reference pair (data/registration) for the ICP benchmark, as plain Eigen
// arrays, and the pose errors every method is judged by.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace vscan::bench {

struct IcpCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
};

struct IcpPair {
  IcpCloud source;
  IcpCloud target;
  // Lays the source onto the target: the inverse of T_gt_src_from_tgt.txt.
  Eigen::Matrix4d target_from_source;
};

// What one alignment returned.
struct IcpOutcome {
  Eigen::Matrix4d target_from_source = Eigen::Matrix4d::Identity();
  int iterations = 0;
};

// Loads the pair once (vscan's PCD reader); exits with a message when the files are missing.
const IcpPair& ReferencePair();

double RotationErrorDeg(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth);
double TranslationErrorMm(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth);

}  // namespace vscan::bench
