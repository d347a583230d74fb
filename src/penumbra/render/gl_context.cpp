#include "penumbra/render/gl_context.h"

// glad first: it must define the GL prototypes before anything else could pull in a GL header.
#include <glad/gl.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>

#include "penumbra/render/render_error.h"

namespace penumbra {

void GlContext::loadGlFunctions(ProcLoader loader) {
  if (gladLoadGL(loader) == 0) {
    throw RenderError("OpenGL: could not load the GL 3.3 core entry points (gladLoadGL failed)");
  }
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  version_ = version ? version : "";
  renderer_ = renderer ? renderer : "";
  glGetIntegerv(GL_MAJOR_VERSION, &major_);
  glGetIntegerv(GL_MINOR_VERSION, &minor_);
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  core_ = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  if (major_ < 3 || (major_ == 3 && minor_ < 3) || !core_) {
    throw RenderError("OpenGL: need a 3.3 core profile context, got '" + version_ + "' on '" +
                      renderer_ + "'");
  }
}

namespace {

std::string eglErrorText(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    default: {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "EGL error 0x%04x", static_cast<unsigned>(error));
      return buffer;
    }
  }
}

[[noreturn]] void throwEgl(const std::string& step) {
  throw RenderError("EGL headless context: " + step + " failed (" + eglErrorText(eglGetError()) +
                    "); headless rendering needs Mesa's EGL with the surfaceless platform "
                    "(packages libegl-mesa0 libgl1-mesa-dri)");
}

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool startsWord = p == list || p[-1] == ' ';
    const bool endsWord = p[length] == ' ' || p[length] == '\0';
    if (startsWord && endsWord) return true;
  }
  return false;
}

// The surfaceless platform hands out one display per process; eglTerminate on it would pull the
// display from under every other live context, so contexts share it and the last one terminates.
std::mutex displayMutex;
std::map<EGLDisplay, int> displayUsers;

void retainDisplay(EGLDisplay display) {
  std::lock_guard lock(displayMutex);
  ++displayUsers[display];
}

void releaseDisplay(EGLDisplay display) {
  std::lock_guard lock(displayMutex);
  auto it = displayUsers.find(display);
  if (it == displayUsers.end()) return;
  if (--it->second == 0) {
    displayUsers.erase(it);
    eglTerminate(display);
  }
}

class EglContext final : public GlContext {
 public:
  EglContext() = default;
  ~EglContext() override {
    if (context_ != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == context_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      }
      eglDestroyContext(display_, context_);
    }
    if (display_ != EGL_NO_DISPLAY) releaseDisplay(display_);
  }

  void create() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
      throw RenderError(std::string("EGL headless context: EGL_MESA_platform_surfaceless is not "
                                    "offered (client extensions: '") +
                        (clientExtensions ? clientExtensions : "none") +
                        "'); headless rendering needs Mesa's EGL (packages libegl-mesa0 "
                        "libgl1-mesa-dri)");
    }
    const auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr) throwEgl("eglGetProcAddress(eglGetPlatformDisplayEXT)");

    EGLDisplay display =
        getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) throwEgl("eglGetPlatformDisplayEXT(surfaceless)");
    EGLint eglMajor = 0, eglMinor = 0;
    if (!eglInitialize(display, &eglMajor, &eglMinor)) throwEgl("eglInitialize");
    display_ = display;
    retainDisplay(display_);

    // A pbuffer-capable config is what Mesa's surfaceless platform offers; we never create the
    // pbuffer itself (all drawing goes into our own framebuffer objects).
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                       EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configCount = 0;
    if (!eglChooseConfig(display_, configAttributes, &config, 1, &configCount)) {
      throwEgl("eglChooseConfig");
    }
    if (configCount < 1) {
      throw RenderError("EGL headless context: no pbuffer config with OpenGL rendering");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throwEgl("eglBindAPI(EGL_OPENGL_API)");

    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        3,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttributes);
    if (context_ == EGL_NO_CONTEXT) throwEgl("eglCreateContext(OpenGL 3.3 core)");
    makeCurrent();
    loadGlFunctions(eglGetProcAddress);
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throwEgl("eglMakeCurrent(no surface)");
    }
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<GlContext> GlContext::createHeadless() {
  auto context = std::make_unique<EglContext>();
  context->create();  // on failure the destructor releases what was acquired
  return context;
}

}  // namespace penumbra
