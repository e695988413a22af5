#include "robot/reach.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "robot/kinematics_kernel.h"

namespace vscan::robot {

Eigen::Vector3d FirstJointOrigin(const KinematicChain& chain) {
  return chain.joints().front().T_prev_joint.translation();
}

double ReachUpperBound(const KinematicChain& chain) {
  const std::vector<ChainJoint>& joints = chain.joints();
  double reach = chain.last_joint_from_tool().translation().norm();
  for (size_t i = 0; i < joints.size(); ++i) {
    if (i > 0) reach += joints[i].T_prev_joint.translation().norm();
    if (joints[i].type == JointType::kPrismatic) reach += std::max(std::abs(joints[i].lower), std::abs(joints[i].upper));
  }
  return reach;
}

double SampledReach(const KinematicChain& chain, int samples, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Eigen::Vector3d origin = FirstJointOrigin(chain);
  double reach = 0.0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::VectorXd q = RandomJointPositions(chain, rng);
    reach = std::max(reach, (ToolPose(chain, q.data()).translation() - origin).norm());
  }
  return reach;
}

Status CheckWithinReach(const KinematicChain& chain, const Eigen::Vector3d& base_position, std::string_view field,
                        double* miss_distance) {
  const double distance = (base_position - FirstJointOrigin(chain)).norm();
  const double bound = ReachUpperBound(chain);
  const double miss = std::max(0.0, distance - bound);
  if (miss_distance != nullptr) *miss_distance = miss;
  if (miss <= 0.0) return Status::Ok();
  std::ostringstream out;
  out << "unreachable, " << distance << " m from the first joint of " << chain.base_link() << " -> "
      << chain.tip_link() << " whose reach is at most " << bound << " m; misses by " << miss << " m";
  return OutOfRange(std::string(field), out.str());
}

}  // namespace vscan::robot
