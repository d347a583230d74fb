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
#include <optional>
#include <string>
#include <vector>

#include "camera_ray.h"
#include "drag_script.h"
#include "image_display.h"
#include "object_drag.h"
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
constexpr double kRotationStepDegrees = 5;  // one Q/E press

// What the keyboard and wheel ask for between two frames (GLFW callbacks fill it; ImGui's
// backend chains to them).
struct Input {
  bool togglePlay = false;
  int step = 0;
  int method = -1;
  bool resetCamera = false;
  bool screenshot = false;
  int rotateSteps = 0;  // Q: +1 (counter-clockwise seen from above), E: -1
  double scroll = 0;
};

// What a left-button drag does, chosen when the button goes down.
enum class MouseDrag {
  kNone,
  kOrbit,   // plain drag: the camera
  kObject,  // Ctrl+drag that picked an object: the object
  kIgnore,  // until release (Ctrl+click on nothing, or the drag ended by a rotation)
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
    case GLFW_KEY_4:
    case GLFW_KEY_5:
      input->method = key - GLFW_KEY_1;
      break;
    case GLFW_KEY_R:
      input->resetCamera = true;
      break;
    case GLFW_KEY_P:
      input->screenshot = action == GLFW_PRESS;
      break;
    case GLFW_KEY_Q:
      ++input->rotateSteps;
      break;
    case GLFW_KEY_E:
      --input->rotateSteps;
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

bool isKeyDown(GLFWwindow* window, int left, int right) {
  return glfwGetKey(window, left) == GLFW_PRESS || glfwGetKey(window, right) == GLFW_PRESS;
}

// The panel's account of the last pose change: what moved, what the engines did, what it cost.
void showLastUpdate(const SceneView& view) {
  const SceneUpdate& u = view.lastUpdate();
  if (u.changes == 0) return;
  std::string moved;
  for (int object : u.movedObjects)
    moved += (moved.empty() ? "" : ", ") + view.live().scene().objects[object].name;
  ImGui::TextWrapped("last update: %d change%s, moved %s", u.changes, u.changes == 1 ? "" : "s",
                     moved.empty() ? "nothing" : moved.c_str());
  if (u.engine == ViewMethod::kRaytrace)
    ImGui::TextUnformatted("raytrace: reads the moved grid and caster");
  else if (u.radiositySolvesAfresh)
    ImGui::Text("%s: solved afresh for the image", methodName(u.engine));
  else
    ImGui::Text("%s update %.2f ms", methodName(u.engine), 1e3 * u.engineSeconds);
  ImGui::Text("volumes: %d rebuilt, %d occluder moves,", u.volumes.rebuilds,
              u.volumes.occluderMoves);
  ImGui::Text("  %d light moves, %d unchanged", u.volumes.lightMoves, u.volumes.unchanged);
  ImGui::Text("grid %.3f ms, ray caster %.3f ms", 1e3 * u.gridSeconds, 1e3 * u.raySeconds);
  if (u.extentGrew) ImGui::TextWrapped("left the scene's reach: grid and caster rebuilt");
}

}  // namespace

int runViewer(const ViewerOptions& options) {
  const std::optional<ViewMethod> method = parseViewMethod(options.method);
  if (!method)
    throw InputError("--method", "must be raytrace, radiosity, volumes, combined or galerkin");
  Scene scene = loadScene(options.scene);
  if (options.frame < 0 || options.frame >= scene.frames)
    throw InputError("--frame", "frame " + std::to_string(options.frame) +
                                    " is outside the scene's frames 0.." +
                                    std::to_string(scene.frames - 1));
  std::vector<int> dragged;  // the object of each scripted drag, resolved before a window is needed
  for (const ScriptedDrag& drag : options.drags)
    dragged.push_back(findDraggedObject(scene, drag.object));
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
  SceneView view(scene, *method, options.radiosity);
  view.setLightSamples(options.lightSamples);
  view.setThreads(options.threads);
  view.setFrame(options.frame);
  OrbitCamera orbit(sceneCam);
  ImageDisplay display;

  bool playing = options.play, dirty = true, autoExposureOn = options.exposure <= 0;
  float exposure = float(autoExposureOn ? 1.0 : options.exposure);
  float playbackFps = 4;
  int methodIndex = int(*method), lightSamples = options.lightSamples, frame = options.frame;
  double renderSeconds = 0, lastAdvance = 0;
  MouseDrag mouseDrag = MouseDrag::kNone;
  std::optional<ObjectDrag> objectDrag;
  int selected = -1;  // the picked object
  bool dragsApplied = options.drags.empty();
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
      const int rotateSteps = input.rotateSteps;
      const bool wantScreenshot = input.screenshot;
      input = Input{};
      input.screenshot = wantScreenshot;
      // Moves update the engines at once: the shown one must be the one chosen now.
      view.setMethod(ViewMethod(methodIndex));
      if (rotateSteps != 0 && selected >= 0) {
        const double degrees = kRotationStepDegrees * rotateSteps;
        view.moveObject(selected, rotatedAboutUp(view.live().transformOf(selected),
                                                 view.boundsOf(selected).center(), degrees));
        // A drag in progress started from the unturned pose; it ends here.
        if (mouseDrag == MouseDrag::kObject) mouseDrag = MouseDrag::kIgnore;
        dirty = true;
      }
      // The centre of the pixel under the cursor, in image pixels: the image is drawn 1:1 in
      // framebuffer pixels, which differ from window coordinates on high-DPI screens. So a pick
      // follows the ray the ray-traced image cast for that pixel.
      double x = 0, y = 0;
      glfwGetCursorPos(context->window(), &x, &y);
      int windowWidth = 1, windowHeight = 1, fbWidth = 1, fbHeight = 1;
      glfwGetWindowSize(context->window(), &windowWidth, &windowHeight);
      context->framebufferSize(fbWidth, fbHeight);
      const double px = (std::floor(x) + 0.5) * fbWidth / std::max(windowWidth, 1);
      const double py = (std::floor(y) + 0.5) * fbHeight / std::max(windowHeight, 1);
      const bool down = glfwGetMouseButton(context->window(), GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
      if (!down) mouseDrag = MouseDrag::kNone;
      if (down && mouseDrag == MouseDrag::kNone && !ImGui::GetIO().WantCaptureMouse && px < width &&
          py < height) {
        mouseDrag = MouseDrag::kOrbit;
        if (isKeyDown(context->window(), GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL)) {
          mouseDrag = MouseDrag::kIgnore;
          selected = -1;
          if (const auto hit = view.pick(orbit.camera(), width, height, px, py)) {
            selected = hit->object;
            const Camera& c = orbit.camera();
            const bool inViewPlane =
                isKeyDown(context->window(), GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT);
            objectDrag.emplace(selected, view.live().transformOf(selected), hit->point,
                               inViewPlane ? c.eye - c.target : kWorldUp);
            mouseDrag = MouseDrag::kObject;
          }
        }
      }
      if (x != dragX || y != dragY) {
        if (mouseDrag == MouseDrag::kOrbit) {
          orbit.orbit(-(x - dragX) * 0.01, (y - dragY) * 0.01);
          dirty = true;
        } else if (mouseDrag == MouseDrag::kObject) {
          const Camera& c = orbit.camera();
          // At most a scene's size per drag: a ray grazing the plane would fling the object off.
          const std::optional<Transform> moved =
              objectDrag->transformFor(c.eye, cameraRayDirection(c, width, height, px, py),
                                       view.live().extent().diagonalLength());
          if (moved) {
            view.moveObject(objectDrag->object(), *moved);
            dirty = true;
          }
        }
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
      // Scripted drags once their frame is reached (in a screenshot run, the last one: a frame
      // step puts moved objects back on their keyframes).
      if (!dragsApplied && (interactive || drawn + 1 == options.frames)) {
        for (std::size_t i = 0; i < options.drags.size(); ++i) {
          applyScriptedDrag(view, dragged[i], options.drags[i]);
          selected = dragged[i];
        }
        dragsApplied = true;
        const SceneUpdate& u = view.lastUpdate();
        std::fprintf(stderr,
                     "penumbra-view: dragged; last update: %.2f ms (%s), volumes %d rebuilt, "
                     "%d occluder moves, %d light moves\n",
                     1e3 * u.engineSeconds, methodName(u.engine), u.volumes.rebuilds,
                     u.volumes.occluderMoves, u.volumes.lightMoves);
      }
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
    const char* methods[] = {"raytrace", "radiosity", "volumes", "combined", "galerkin"};
    dirty |= ImGui::Combo("method", &methodIndex, methods, 5);
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
    ImGui::Separator();
    if (selected >= 0)
      ImGui::Text("selected: %s", view.live().scene().objects[selected].name.c_str());
    else
      ImGui::TextUnformatted("selected: none");
    ImGui::TextWrapped("Ctrl+click picks, Ctrl+drag moves (+Shift: facing the camera), Q/E turn");
    showLastUpdate(view);
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
