#pragma once
// Compiles and links one vertex + fragment shader pair. Threading: needs a current context; the
// program belongs to that context and is used and deleted on its thread.

#include "vscan/common/status.h"
#include "vscan/gl/gl_api.h"

namespace vscan::gl {

// The program owns nothing else; delete it with glDeleteProgram. Internal with the compiler's or
// linker's log, naming `name`, when the sources do not build.
StatusOr<GLuint> BuildProgram(const char* vertex_source, const char* fragment_source, const char* name);

}  // namespace vscan::gl
