#pragma once
// The object of the model-job tests.

#include "vscan/common/mesh.h"

namespace vscan::service::testing {

// An L-shaped prism 8 cm long (x), 6 cm deep (y) and 7 cm tall (z), standing on z = 0 about the
// origin: closed, and without a symmetry along which alignment could slide. Area 0.026 m^2.
TriangleMesh LBlock();

}  // namespace vscan::service::testing
