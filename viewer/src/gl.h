// OpenGL 3.3 core entry points: the system's libGL exports them (Mesa, through GLVND)
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
