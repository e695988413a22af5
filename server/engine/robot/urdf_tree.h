#pragma once
// The joint graph of a parsed URDF must be a tree: urdfdom accepts cycles and links with two
// parent joints as long as exactly one link has no parent, and walks over such a graph never end.

#include "vscan/common/status.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot {

// InvalidArgument naming the joints: a joint whose parent is its child ("joints['j']: ..."), a
// cycle ("joints: cycle through joints j1 -> j2 -> j1"), a link that hangs from two joints
// ("links['a']: ..."). urdfdom itself refuses graphs with no root or with two roots.
Status CheckUrdfTree(const urdf::ModelInterface& model);

}  // namespace vscan::robot
