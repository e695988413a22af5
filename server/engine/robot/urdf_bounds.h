#pragma once
// Physical bounds (vscan/common/physical_limits.h) on the numbers of a parsed URDF that place
// geometry: joint origins and prismatic limits, visual and collision origins, primitive sizes and
// mesh scales. Checked once at upload, so that no robot can put a coordinate out of range.

#include "vscan/common/status.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot {

// InvalidArgument naming the element and the attribute, e.g. "joints['j1'].origin.xyz: ..." or
// "links['arm'].collision[0].box.size: ...".
Status CheckUrdfBounds(const urdf::ModelInterface& model);

}  // namespace vscan::robot
