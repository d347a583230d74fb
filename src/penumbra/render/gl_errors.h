#pragma once
// GL error checks for this library's GL code. Includes the loader, so only GL-using .cpp files
// include it, never a public header.

#include <glad/gl.h>

#include <string>

namespace penumbra {

// "GL_INVALID_ENUM" etc., or the number in hex for codes this version does not name.
std::string glErrorName(GLenum error);

// Drains the GL error queue; if it held errors, throws RenderError "`where`: GL_... [, GL_...]".
// Called after each logical step (upload, draw, read-back) rather than after every call: errors
// stay attributable to a step while the checks cost a handful of glGetError calls per frame.
void throwOnGlError(const char* where);

}  // namespace penumbra
