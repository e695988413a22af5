#pragma once
// Compiles and links one vertex + fragment shader pair.

#include "raster/gl_api.h"
#include "vscan/common/status.h"

namespace vscan::raster {

// The program owns nothing else; delete it with glDeleteProgram.
StatusOr<GLuint> BuildProgram(const char* vertex_source, const char* fragment_source, const char* name);

}  // namespace vscan::raster
