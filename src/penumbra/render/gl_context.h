#pragma once
// An OpenGL 3.3+ core context with the glad loader initialised for it.
//
// Headless rendering (tests, CLI, CI with no display and no GPU) goes through EGL on Mesa's
// surfaceless platform: there is no default framebuffer, so all drawing goes into a Framebuffer.
// A window-system context for the viewer is GlfwContext (glfw_context.h), in the separate
// penumbra_render_glfw library so that this one never needs a window system: it makes its
// context current and calls loadGlFunctions() with glfwGetProcAddress.
//
// A context is current on one thread at a time; GL calls made by this library's classes require
// that the context that created their objects is current on the calling thread.

#include <memory>
#include <string>

namespace penumbra {

class GlContext {
 public:
  // A GL function lookup as both eglGetProcAddress and glfwGetProcAddress have it.
  using ProcLoader = void (*(*)(const char*))();

  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Creates an OpenGL 3.3 core context on EGL's surfaceless Mesa platform (works with no display,
  // no GPU: llvmpipe) and makes it current on the calling thread.
  // Throws RenderError naming the step that failed when EGL or such a context is unavailable.
  static std::unique_ptr<GlContext> createHeadless();

  // Makes this context current on the calling thread. Throws RenderError on failure.
  virtual void makeCurrent() = 0;

  // GL_VERSION / GL_RENDERER / version numbers as queried when the context was created.
  const std::string& versionString() const { return version_; }
  const std::string& rendererString() const { return renderer_; }
  int majorVersion() const { return major_; }
  int minorVersion() const { return minor_; }
  bool isCoreProfile() const { return core_; }

 protected:
  GlContext() = default;

  // Precondition: the new context is current. Loads the GL entry points through `loader`, checks
  // for GL >= 3.3 core and records the strings above. Throws RenderError otherwise.
  void loadGlFunctions(ProcLoader loader);

 private:
  std::string version_;
  std::string renderer_;
  int major_ = 0;
  int minor_ = 0;
  bool core_ = false;
};

}  // namespace penumbra
