#pragma once
// Open3D 0.16 (Debian libopen3d-dev) as a benchmark peer: RegistrationICP with
// TransformationEstimationPointToPlane. Open3D stays in the .cpp.

#include <memory>

#include "icp_bench_data.h"

namespace vscan::bench {

class Open3dPeer {
 public:
  // Converts the clouds once (normals from the files), outside any timing.
  explicit Open3dPeer(const IcpPair& pair);
  ~Open3dPeer();

  // From the identity; stops when fitness and inlier RMSE both change by less than `relative`
  // (0: never) or after max_iterations. The target's kd-tree is built inside. Open3D 0.16 does not
  // report how many iterations it ran: the outcome's count is left 0.
  IcpOutcome Icp(double relative, int max_iterations, double max_distance) const;

 private:
  struct Clouds;
  std::unique_ptr<Clouds> clouds_;
};

}  // namespace vscan::bench
