#include "penumbra/render/glfw_context.h"

// glad first: GLFW must not pull in a system GL header before it.
#include <glad/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>

#include "penumbra/render/render_error.h"

namespace penumbra {
namespace {

// GLFW reports the reason for a failure only through its error callback; keep the last one so
// that the exception can say why (e.g. "X11: The DISPLAY environment variable is missing").
std::mutex errorMutex;
std::string lastError;

void recordError(int code, const char* description) {
  std::lock_guard lock(errorMutex);
  lastError = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

std::string takeError() {
  std::lock_guard lock(errorMutex);
  std::string error = lastError.empty() ? "no description" : lastError;
  lastError.clear();
  return error;
}

}  // namespace

std::unique_ptr<GlfwContext> GlfwContext::createWindow(const WindowOptions& options) {
  glfwSetErrorCallback(recordError);
  if (glfwInit() == GLFW_FALSE) {
    throw RenderError("GLFW window: glfwInit failed (" + takeError() +
                      "); a window needs a display: run under `xvfb-run -a` where there is none");
  }
  std::unique_ptr<GlfwContext> context(new GlfwContext());
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_STENCIL_BITS, 8);
  glfwWindowHint(GLFW_SAMPLES, 0);  // pixels are compared with the CLI's: no multisampling
  glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);  // images arrive tone-mapped to sRGB already
  context->window_ =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (context->window_ == nullptr) {
    const std::string error = takeError();
    glfwTerminate();
    throw RenderError("GLFW window: glfwCreateWindow with an OpenGL 3.3 core context failed (" +
                      error + ")");
  }
  context->makeCurrent();
  glfwSwapInterval(options.vsync ? 1 : 0);
  context->loadGlFunctions(glfwGetProcAddress);  // throws; the destructor cleans up
  return context;
}

GlfwContext::~GlfwContext() {
  if (window_ != nullptr) glfwDestroyWindow(window_);
  glfwTerminate();
}

void GlfwContext::makeCurrent() {
  glfwMakeContextCurrent(window_);
}

void GlfwContext::swapBuffers() {
  glfwSwapBuffers(window_);
}

bool GlfwContext::shouldClose() const {
  return glfwWindowShouldClose(window_) != 0;
}

void GlfwContext::framebufferSize(int& width, int& height) const {
  glfwGetFramebufferSize(window_, &width, &height);
}

}  // namespace penumbra
