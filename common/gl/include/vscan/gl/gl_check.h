#pragma once
// Turns pending OpenGL errors into a Status. Threading: reads the error queue of the context
// current on the calling thread.

#include <string_view>

#include "vscan/common/status.h"

namespace vscan::gl {

// Drains the GL error queue: OK when empty, ResourceExhausted on GL_OUT_OF_MEMORY, else Internal.
// The message is "<what>: <error>", so `what` names the caller and the step, e.g. "raster: drawing".
Status CheckGl(std::string_view what);

}  // namespace vscan::gl
