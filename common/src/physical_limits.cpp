#include "vscan/common/physical_limits.h"

namespace vscan {

Status CheckPosition(const Eigen::Vector3d& p, std::string_view field) {
  if (!p.allFinite()) return InvalidArgument(std::string(field) + ": NaN or infinite value");
  if (p.cwiseAbs().maxCoeff() > kMaxCoordinateM) {
    return InvalidArgument(std::string(field) + ": coordinates beyond 10 km (|x|, |y|, |z| <= 1e4 m)");
  }
  return Status::Ok();
}

}  // namespace vscan
