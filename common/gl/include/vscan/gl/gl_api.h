#pragma once
// The OpenGL core API, for the .cpp files that draw and nowhere else (keep it out of headers that
// other code includes). Entry points come straight from GLVND's libOpenGL, which forwards each
// call to the vendor of the context current on the calling thread, so no loader is needed.
// Threading: a GL call acts on the context current on its thread (see egl_context.h).

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
