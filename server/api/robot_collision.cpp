#include "api/robot_collision.h"

namespace vscan::api {

StatusOr<std::optional<std::string>> FindRobotCollision(ServiceContext&, const std::string&, const Eigen::VectorXd&,
                                                        double) {
  return Unimplemented("reject_collisions: collision checking is not supported by this server version");
}

}  // namespace vscan::api
