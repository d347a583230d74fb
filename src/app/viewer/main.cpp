// penumbra-view: an interactive viewer of Penumbra's engines (GLFW + Dear ImGui), and with
// --screenshot a non-interactive one that tests run under xvfb-run. Exit codes as `penumbra`:
// 0 ok, 1 usage (a --drag naming no object of the scene included), 2 bad input or no window (no
// display, no GL 3.3 core).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "penumbra/base/input_error.h"
#include "penumbra/render/render_error.h"
#include "viewer_app.h"
#include "viewer_options.h"

namespace {

// "640x480" into width and height; false when malformed or outside 1..16384.
bool parseSize(const std::string& size, int& width, int& height) {
  const auto x = size.find('x');
  const auto isNumber = [](const std::string& s) {
    return !s.empty() && s.size() <= 5 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (x == std::string::npos || !isNumber(size.substr(0, x)) || !isNumber(size.substr(x + 1)))
    return false;
  width = std::stoi(size.substr(0, x));
  height = std::stoi(size.substr(x + 1));
  return width >= 1 && height >= 1 && width <= 16384 && height <= 16384;
}

}  // namespace

int main(int argc, char** argv) {
  penumbra::viewer::ViewerOptions options;
  std::string size;
  CLI::App app{"penumbra-view: watch Penumbra's engines light a moving scene"};
  app.add_option("scene", options.scene, "Scene file (.json, .obj, .gltf, .glb)")->required();
  app.add_option("--method", options.method,
                 "raytrace | radiosity | volumes | combined | galerkin (default volumes)");
  app.add_option("--frame", options.frame, "First frame shown")->check(CLI::NonNegativeNumber);
  app.add_option("--light-samples", options.lightSamples,
                 "volumes: stratified point lights per area light (1: its centroid)")
      ->check(CLI::Range(1, 65536));
  app.add_option("--size", size, "Image size WxH (default: the scene camera's)");
  app.add_option("--exposure", options.exposure, "Exposure (default: automatic)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--tolerance", options.radiosity.tolerance, "Radiosity: refinement tolerance")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--threads", options.threads, "Ray-tracing threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--play", options.play, "Start playing the motion");
  std::vector<std::string> drags;
  app.add_option("--drag", drags,
                 "Move OBJECT by dx,dy,dz, then turn it by degrees about world up through its "
                 "bounds centre, as a mouse drag would (repeatable, applied in order)")
      ->type_name("OBJECT:dx,dy,dz[:degrees]")
      ->allow_extra_args(false);
  app.add_option("--screenshot", options.screenshot,
                 "Non-interactive: write the window's image to this PNG after --frames frames");
  app.add_option("--frames", options.frames,
                 "With --screenshot: frames to draw, one motion frame each from --frame")
      ->check(CLI::Range(1, 1000000));
  app.add_flag("--capture-window", options.captureWindow,
               "Screenshots show the whole window (image and panel), not just the image");
  try {
    app.parse(argc, argv);
    if (!size.empty() && !parseSize(size, options.width, options.height))
      throw CLI::ValidationError("--size", "must look like 640x480, within 1x1..16384x16384");
    for (const std::string& text : drags) {
      const auto drag = penumbra::viewer::parseScriptedDrag(text);
      if (!drag)
        throw CLI::ValidationError("--drag",
                                   "must look like OBJECT:dx,dy,dz or "
                                   "OBJECT:dx,dy,dz:degrees (finite numbers), got '" +
                                       text + "'");
      options.drags.push_back(*drag);
    }
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  try {
    return penumbra::viewer::runViewer(options);
  } catch (const penumbra::viewer::OptionError& e) {
    std::fprintf(stderr, "penumbra-view: error: %s\n", e.what());
    return 1;
  } catch (const penumbra::InputError& e) {
    std::fprintf(stderr, "penumbra-view: error: %s\n", e.what());
  } catch (const penumbra::RenderError& e) {
    std::fprintf(stderr, "penumbra-view: cannot open a window: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra-view: failed: %s\n", e.what());
  }
  return 2;
}
