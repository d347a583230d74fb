#include "penumbra/render/gl_errors.h"

#include <cstdio>

#include "penumbra/render/render_error.h"

namespace penumbra {

std::string glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default: {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "GL error 0x%04x", static_cast<unsigned>(error));
      return buffer;
    }
  }
}

void throwOnGlError(const char* where) {
  std::string errors;
  // Bounded: a lost context can report errors forever on some drivers.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR) break;
    if (!errors.empty()) errors += ", ";
    errors += glErrorName(error);
  }
  if (!errors.empty()) throw RenderError(std::string(where) + ": " + errors);
}

}  // namespace penumbra
