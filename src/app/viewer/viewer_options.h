#pragma once
// Command line of penumbra-view (parsed in main.cpp).

#include <stdexcept>
#include <string>
#include <vector>

#include "drag_script.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/shadow_volume_renderer.h"

namespace penumbra::viewer {

struct ViewerOptions {
  std::string scene;
  std::string method = "volumes";  // raytrace | radiosity | volumes | combined
  int frame = 0;                   // first frame shown
  // volumes: jittered point lights per area light (the renderer's default)
  int lightSamples = ShadowVolumeRenderOptions{}.lightSamples;
  int width = 0, height = 0;   // image size; 0: the scene camera's
  double exposure = 0;         // 0: automatic per image, as `penumbra render`
  RadiosityOptions radiosity;  // the engine's own defaults; --tolerance binds to it
  int threads = 0;             // raytrace worker threads (0: all)
  bool play = false;           // start playing the motion
  // Moves applied in order, as mouse drags would be: before the first image, or with
  // `screenshot` before the last one (a frame step puts moved objects back on their keyframes).
  std::vector<ScriptedDrag> drags;
  // Non-interactive: draw `frames` frames, advancing the motion one frame per drawn frame from
  // `frame` (wrapping at the end), write the window's image of the last one to this PNG, exit.
  std::string screenshot;
  int frames = 1;
  bool captureWindow = false;  // screenshot the whole window, panel included, not just the image
};

// A bad option value that only the scene can reveal (a --drag naming no object). main reports it
// like CLI11's own errors: a usage error, exit code 1.
class OptionError : public std::runtime_error {
 public:
  OptionError(const std::string& option, const std::string& problem)
      : std::runtime_error(option + ": " + problem) {}
};

}  // namespace penumbra::viewer
