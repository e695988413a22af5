#include "api/localization/grasp_scoring_request.h"

#include "api/picking/pick_request.h"

namespace vscan::api {

StatusOr<std::optional<service::GraspScoring>> ParseGraspScoring(bool has_gripper, const v1::Gripper& gripper,
                                                                 const v1::GraspOptions& options, bool has_up,
                                                                 const v1::Vector3& up) {
  if (!has_gripper) return std::optional<service::GraspScoring>();
  service::GraspScoring out;
  ASSIGN_OR_RETURN(out.gripper, ParseGripper(gripper));
  out.grasp_options = ParseGraspOptions(options);
  if (has_up) {
    ASSIGN_OR_RETURN(out.up, service::UnitUp(Eigen::Vector3d(up.x(), up.y(), up.z()), "up"));
  }
  RETURN_IF_ERROR(service::ValidateGraspScoring(out));
  return std::optional<service::GraspScoring>(std::move(out));
}

}  // namespace vscan::api
