#pragma once
// Command line of penumbra-view (parsed in main.cpp).

#include <string>

namespace penumbra::viewer {

struct ViewerOptions {
  std::string scene;
  std::string method = "volumes";  // raytrace | radiosity | volumes
  int frame = 0;                   // first frame shown
  int lightSamples = 1;            // volumes: jittered point lights per area light
  int width = 0, height = 0;       // image size; 0: the scene camera's
  double exposure = 0;             // 0: automatic per image, as `penumbra render`
  double tolerance = 1e-3;         // radiosity refinement tolerance
  int threads = 0;                 // raytrace worker threads (0: all)
  bool play = false;               // start playing the motion
  // Non-interactive: draw `frames` frames, advancing the motion one frame per drawn frame from
  // `frame` (wrapping at the end), write the window's image of the last one to this PNG, exit.
  std::string screenshot;
  int frames = 1;
  bool captureWindow = false;  // screenshot the whole window, panel included, not just the image
};

}  // namespace penumbra::viewer
