#include "service/datasets/format/dataset_picks_plan.h"

#include <variant>

namespace vscan::service::dataset {

const char* GripperKind(const grasping::Gripper& gripper) {
  return std::holds_alternative<grasping::SuctionCup>(gripper) ? "suction" : "jaws";
}

}  // namespace vscan::service::dataset
