// OpenGL 3.3 core entry points. On Linux, Mesa's libGL exports every core and extension
// function, so prototypes are enough (no loader). Include this instead of <GL/gl.h>.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
