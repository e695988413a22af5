#pragma once
// PCL 1.13 as a benchmark peer: point-to-plane ICP (IterativeClosestPointWithNormals with
// TransformationEstimationPointToPlaneLLS, in double) and normal estimation. PCL stays in the .cpp.

#include <memory>

#include "icp_bench_data.h"

namespace vscan::bench {

// PCL's own stopping rules; zero turns one off, so the run lasts max_iterations.
struct PclIcpSettings {
  int max_iterations = 50;
  // On the squared translation of one iteration's update (m^2).
  double translation_epsilon = 0.0;
  // On the cosine of one iteration's rotation update; 0 keeps PCL's 1 - translation_epsilon.
  double rotation_epsilon = 0.0;
  // On the relative change of the pairs' mean squared distance.
  double relative_mse = 0.0;
};

class PclPeer {
 public:
  // Converts the clouds once, outside any timing.
  explicit PclPeer(const IcpPair& pair);
  ~PclPeer();

  // From the identity, with the files' normals, pairs within max_distance; the target's kd-tree
  // is built inside, as it is for the other methods.
  IcpOutcome Icp(const PclIcpSettings& settings, double max_distance) const;
  // NormalEstimationOMP on both clouds (k nearest, 2 threads), kd-trees included.
  void EstimateNormals(int k) const;

 private:
  struct Clouds;
  std::unique_ptr<Clouds> clouds_;
};

}  // namespace vscan::bench
