#pragma once
// An OpenGL 3.3+ core context with a window, through GLFW: the window-system counterpart of the
// EGL headless context (gl_context.h), for the viewer. EGL headless everywhere; GLFW when a
// display exists.
//
// It lives in its own library (penumbra_render_glfw), built only where GLFW is installed, so the
// rest of the render library, the CLI and the tests never depend on a window system. GLFW needs
// a display (X11 here): with none (DISPLAY unset, CI), creation fails with a RenderError that
// says so; run under `xvfb-run -a` to get one.
//
// One GlfwContext at a time per process (GLFW is initialised and terminated with it); create,
// use and destroy it on the main thread, as GLFW requires.

#include <memory>
#include <string>

#include "penumbra/render/gl_context.h"

struct GLFWwindow;

namespace penumbra {

struct WindowOptions {
  int width = 1280;  // client area, in screen coordinates
  int height = 720;
  std::string title = "Penumbra";
  bool vsync = true;  // swap at the display's rate; off for timing runs
};

class GlfwContext final : public GlContext {
 public:
  // Opens a window with an OpenGL 3.3 core context (forward-compatible, double-buffered, 8-bit
  // stencil), makes it current and loads the GL entry points. Throws RenderError naming the step
  // and GLFW's own description when there is no display or no such context.
  static std::unique_ptr<GlfwContext> createWindow(const WindowOptions& options);
  ~GlfwContext() override;

  void makeCurrent() override;
  // Presents the back buffer.
  void swapBuffers();
  // True once the user has asked to close the window.
  bool shouldClose() const;
  // The framebuffer size in pixels (differs from the window size on high-DPI screens).
  void framebufferSize(int& width, int& height) const;

  GLFWwindow* window() const { return window_; }

 private:
  GlfwContext() = default;
  GLFWwindow* window_ = nullptr;
};

}  // namespace penumbra
