#include "localization/score_gripper_args.h"

namespace vscan::cli {

void AddScoreGripperOptions(CLI::App* command, ScoreGripperArgs& a) {
  AddGripperOptions(command, a.gripper);
  command->add_option("--up", a.up, "X Y Z: against gravity in the poses' frame, for the grasp success (0 0 1)")
      ->expected(3);
}

StatusOr<std::optional<v1::Gripper>> BuildScoreGripper(const ScoreGripperArgs& a) {
  ASSIGN_OR_RETURN(v1::Gripper gripper, BuildGripper(a.gripper));
  if (gripper.kind_case() == v1::Gripper::KIND_NOT_SET) return std::optional<v1::Gripper>();
  return std::optional<v1::Gripper>(std::move(gripper));
}

std::optional<v1::Vector3> ScoreUp(const ScoreGripperArgs& a) {
  if (a.up.size() != 3) return std::nullopt;
  v1::Vector3 up;
  up.set_x(a.up[0]);
  up.set_y(a.up[1]);
  up.set_z(a.up[2]);
  return up;
}

}  // namespace vscan::cli
