#pragma once
// The names picking.proto and plans give the fields the engine's checks name: the engine's carry
// their unit ("gripper.suction.diameter_m"), the public ones do not ("gripper.suction.diameter").

#include <string_view>

namespace vscan::grasping {

// The public name of a field a grasping check named; any other name as it is.
std::string_view PublicFieldName(std::string_view engine_field);

}  // namespace vscan::grasping
