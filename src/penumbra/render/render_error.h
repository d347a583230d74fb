#pragma once
// Failures of the GPU path that callers may want to report rather than abort on: no EGL display,
// no GL 3.3 core context, a shader that does not compile, an incomplete framebuffer, a GL error.
// They are environment problems (or bugs in GL code), never bad user input (that is InputError).

#include <stdexcept>
#include <string>

namespace penumbra {

class RenderError : public std::runtime_error {
 public:
  explicit RenderError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace penumbra
