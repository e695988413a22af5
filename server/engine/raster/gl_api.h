#pragma once
// The OpenGL core API for the raster module's .cpp files. Entry points come straight from
// GLVND's libOpenGL, which forwards each call to the vendor of the context current on the thread,
// so no loader is needed.

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
