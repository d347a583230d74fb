#include "viewer_app.h"

#include <glad/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "image_display.h"
#include "orbit_camera.h"
#include "penumbra/base/input_error.h"
#include "penumbra/render/glfw_context.h"
#include "penumbra/render/png_writer.h"
#include "penumbra/render/tone_mapping.h"
#include "penumbra/scene/scene_camera.h"
#include "penumbra/scene/scene_loader.h"
#include "scene_view.h"

namespace penumbra::viewer {
namespace {

constexpr int kPanelWidth = 340;  // the ImGui panel sits right of the image, never over it
constexpr int kMinWindowHeight = 480;

// What the keyboard and wheel ask for between two frames (GLFW callbacks fill it; ImGui's
// backend chains to them).
struct Input {
  bool togglePlay = false;
  int step = 0;
  int method = -1;
  bool resetCamera = false;
  bool screenshot = false;
  double scroll = 0;
};

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard) return;
  auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
  switch (key) {
    case GLFW_KEY_SPACE:
      input->togglePlay = action == GLFW_PRESS;
      break;
    case GLFW_KEY_RIGHT:
      ++input->step;
      break;
    case GLFW_KEY_LEFT:
      --input->step;
      break;
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3:
      input->method = key - GLFW_KEY_1;
      break;
    case GLFW_KEY_R:
      input->resetCamera = true;
      break;
    case GLFW_KEY_P:
      input->screenshot = action == GLFW_PRESS;
      break;
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      break;
    default:
      break;
  }
}

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
  static_cast<Input*>(glfwGetWindowUserPointer(window))->scroll += dy;
}

// Dear ImGui on the window, shut down in reverse order of creation.
class ImGuiLayer {
 public:
  explicit ImGuiLayer(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, /*install_callbacks=*/true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~ImGuiLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int runViewer(const ViewerOptions& options) {
  const std::optional<ViewMethod> method = parseViewMethod(options.method);
  if (!method) throw InputError("--method", "must be raytrace, radiosity or volumes");
  Scene scene = loadScene(options.scene);
  if (options.frame < 0 || options.frame >= scene.frames)
    throw InputError("--frame", "frame " + std::to_string(options.frame) +
                                    " is outside the scene's frames 0.." +
                                    std::to_string(scene.frames - 1));
  const Camera sceneCam = sceneCamera(scene, poseAt(scene, options.frame));
  const int width = options.width > 0 ? options.width : sceneCam.width;
  const int height = options.height > 0 ? options.height : sceneCam.height;
  const bool interactive = options.screenshot.empty();

  WindowOptions windowOptions;
  windowOptions.width = width + kPanelWidth;
  windowOptions.height = std::max(height, kMinWindowHeight);
  windowOptions.title = "Penumbra - " + std::filesystem::path(options.scene).filename().string();
  windowOptions.vsync = interactive;
  const auto context = GlfwContext::createWindow(windowOptions);
  Input input;
  glfwSetWindowUserPointer(context->window(), &input);
  glfwSetKeyCallback(context->window(), onKey);
  glfwSetScrollCallback(context->window(), onScroll);
  ImGuiLayer imgui(context->window());

  const int sceneFrames = scene.frames;
  const std::string sceneName = std::filesystem::path(options.scene).filename().string();
  SceneView view(std::move(scene), *method);
  view.setLightSamples(options.lightSamples);
  view.setRadiosityTolerance(options.tolerance);
  view.setThreads(options.threads);
  view.setFrame(options.frame);
  OrbitCamera orbit(sceneCam);
  ImageDisplay display;

  bool playing = options.play, dirty = true, autoExposureOn = options.exposure <= 0;
  float exposure = float(autoExposureOn ? 1.0 : options.exposure);
  float playbackFps = 4;
  int methodIndex = int(*method), lightSamples = options.lightSamples, frame = options.frame;
  double renderSeconds = 0, lastAdvance = 0;
  bool dragging = false;
  double dragX = 0, dragY = 0;
  std::string message;
  const auto start = std::chrono::steady_clock::now();

  auto takeScreenshot = [&](const std::string& path) {
    int fbWidth = 0, fbHeight = 0;
    context->framebufferSize(fbWidth, fbHeight);
    const int w = options.captureWindow ? fbWidth : std::min(display.width(), fbWidth);
    const int h = options.captureWindow ? fbHeight : std::min(display.height(), fbHeight);
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    writePngRgb8(ImageDisplay::readBack(w, h, fbHeight), w, h, path);
    message = "wrote " + path;
    std::fprintf(stderr, "penumbra-view: wrote %s (%dx%d, frame %d, %s)\n", path.c_str(), w, h,
                 view.frame(), methodName(view.method()));
  };

  for (int drawn = 0; interactive ? !context->shouldClose() : drawn < options.frames; ++drawn) {
    glfwPollEvents();
    if (!interactive) {
      frame = (options.frame + drawn) % sceneFrames;
      dirty = true;
    } else {
      // --- input ---
      if (input.togglePlay) playing = !playing;
      if (input.step != 0) {
        frame = ((frame + input.step) % sceneFrames + sceneFrames) % sceneFrames;
        playing = false;
      }
      if (input.method >= 0) methodIndex = input.method;
      if (input.resetCamera) orbit.reset();
      if (input.scroll != 0) orbit.zoom(std::pow(0.9, input.scroll));
      dirty |= input.step != 0 || input.method >= 0 || input.resetCamera || input.scroll != 0;
      const bool wantScreenshot = input.screenshot;
      input = Input{};
      input.screenshot = wantScreenshot;
      double x = 0, y = 0;
      glfwGetCursorPos(context->window(), &x, &y);
      const bool down = glfwGetMouseButton(context->window(), GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
      if (down && !dragging && !ImGui::GetIO().WantCaptureMouse && x < width) dragging = true;
      if (!down) dragging = false;
      if (dragging && (x != dragX || y != dragY)) {
        orbit.orbit(-(x - dragX) * 0.01, (y - dragY) * 0.01);
        dirty = true;
      }
      dragX = x;
      dragY = y;
      if (playing && secondsSince(start) - lastAdvance >= 1.0 / playbackFps) {
        frame = (frame + 1) % sceneFrames;
        lastAdvance = secondsSince(start);
        dirty = true;
      }
    }

    // --- render the image when something changed ---
    if (dirty) {
      view.setMethod(ViewMethod(methodIndex));
      view.setLightSamples(lightSamples);
      view.setFrame(frame);
      const auto t0 = std::chrono::steady_clock::now();
      const Image image = view.render(orbit.camera(), width, height);
      renderSeconds = secondsSince(t0);
      // The same tone mapping as `penumbra render`'s PNG (its exposure is a double too).
      const double e = autoExposureOn ? autoExposure(image) : double(exposure);
      if (autoExposureOn) exposure = float(e);
      display.upload(toSrgb8(image, ToneMapping{e}), width, height);
      dirty = false;
      if (!interactive)
        std::fprintf(stderr, "penumbra-view: frame %d (%s): %.1f ms\n", view.frame(),
                     methodName(view.method()), 1e3 * renderSeconds);
    }

    // --- panel ---
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(float(width), 0));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(windowOptions.height)));
    ImGui::Begin("Penumbra", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::TextUnformatted(sceneName.c_str());
    const char* methods[] = {"raytrace", "radiosity", "volumes"};
    dirty |= ImGui::Combo("method", &methodIndex, methods, 3);
    if (ImGui::SliderInt("frame", &frame, 0, sceneFrames - 1)) {
      playing = false;
      dirty = true;
    }
    if (ImGui::Button(playing ? "pause" : "play")) playing = !playing;
    ImGui::SameLine();
    if (ImGui::Button("step")) {
      frame = (frame + 1) % sceneFrames;
      playing = false;
      dirty = true;
    }
    ImGui::SliderFloat("fps", &playbackFps, 0.5f, 30.0f, "%.1f");
    if (methodIndex == int(ViewMethod::kVolumes))
      dirty |= ImGui::SliderInt("light samples", &lightSamples, 1, 256);
    dirty |= ImGui::Checkbox("auto exposure", &autoExposureOn);
    if (!autoExposureOn)
      dirty |= ImGui::SliderFloat("exposure", &exposure, 0.01f, 100.0f, "%.3f",
                                  ImGuiSliderFlags_Logarithmic);
    if (ImGui::Button("reset camera")) {
      orbit.reset();
      dirty = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("screenshot")) input.screenshot = true;
    ImGui::Separator();
    ImGui::Text("%dx%d, render %.1f ms", width, height, 1e3 * renderSeconds);
    ImGui::TextWrapped("%s", view.status().c_str());
    if (orbit.isModified()) ImGui::TextUnformatted("camera orbited (R resets)");
    if (!message.empty()) ImGui::TextWrapped("%s", message.c_str());
    ImGui::End();
    ImGui::Render();

    int fbWidth = 0, fbHeight = 0;
    context->framebufferSize(fbWidth, fbHeight);
    display.draw(fbWidth, fbHeight);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    if (!interactive && drawn + 1 == options.frames) takeScreenshot(options.screenshot);
    if (interactive && input.screenshot) {
      takeScreenshot("penumbra-view-" + std::string(methodName(view.method())) + "-frame" +
                     std::to_string(view.frame()) + ".png");
      input.screenshot = false;
    }
    context->swapBuffers();
  }
  return 0;
}

}  // namespace penumbra::viewer
