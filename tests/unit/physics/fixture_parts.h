#pragma once
// The machined fixture parts of data/parts at bin scale: angle_block in inches (about 3.4 x 2.5 x
// 3.4 cm) and round scaled to a 6.6 mm x 79 mm pin.

#include "physics/bin_fill.h"

namespace vscan::physics::test {

PartType AngleBlock(size_t count);
PartType RoundPin(size_t count);

}  // namespace vscan::physics::test
