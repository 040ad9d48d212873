// OpenGL 3.3 core for the editor: the function prototypes of Khronos's
// glcorearb.h, resolved by linking libGL (Debian's libglvnd exports every
// core entry point), so no loader library is needed. GLFW is included
// without its own GL header.

#ifndef MSDEFORM_APPS_EDITOR_GL_H_
#define MSDEFORM_APPS_EDITOR_GL_H_

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#endif  // MSDEFORM_APPS_EDITOR_GL_H_
