#pragma once
// A look at a URDF's joint graph before urdfdom parses it: urdfdom refuses a graph with no root
// link or with two, or whose joints name a link the document lacks, and on those paths leaks the
// links of any loop among its joints.

#include <string>

#include "vscan/common/status.h"

namespace vscan::robot {

// InvalidArgument "urdf: ..." when the joints of the <robot> element loop and its links do not have
// exactly one root or a joint names a missing link (urdfdom would refuse the document, leaking);
// OK otherwise, including for documents it cannot read, which urdfdom then refuses on its own.
Status CheckNoRootlessLoops(const std::string& xml);

}  // namespace vscan::robot
