#pragma once
// GL 4.5 core entry points come straight from libglvnd's libOpenGL, which
// exports every core function; no loader is needed.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
