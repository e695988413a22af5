#pragma once
// CheckUrdfTree on a URDF's text, before urdfdom parses it: urdfdom links a looping joint graph
// into links that own each other, and when it then refuses the document (no root or two, a joint
// naming a missing link, ...) it leaks them. Refusing loops first keeps them from urdfdom.

#include <string>

#include "vscan/common/status.h"

namespace vscan::robot {

// CheckUrdfTree's verdict and messages on the links and joints of the document's <robot> element,
// read with TinyXML as urdfdom reads them; OK for a document TinyXML cannot read (urdfdom then
// refuses it on its own, before linking anything).
Status CheckUrdfTreeBeforeParse(const std::string& xml);

}  // namespace vscan::robot
