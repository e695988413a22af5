#pragma once
// Turns pending OpenGL errors into a Status.

#include <string_view>

#include "vscan/common/status.h"

namespace vscan::raster {

// Drains the GL error queue: OK when empty, ResourceExhausted on GL_OUT_OF_MEMORY, else Internal.
Status CheckGl(std::string_view what);

}  // namespace vscan::raster
