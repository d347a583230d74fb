// penumbra-view in a real window under Xvfb (GLX on Mesa llvmpipe): the non-interactive mode
// (--screenshot OUT.png --frames N) plays the motion frame by frame through the window and reads
// the window back. Its screenshot must equal `penumbra render`'s PNG of the same method and
// frame byte for byte: the viewer is a thin client of the same library calls, and its display
// path (8-bit texture, one texel per window pixel, ImGui panel beside the image) must not change a
// pixel. Registered only where xvfb-run exists (scripts/install-deps.sh installs it).

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

// The test's own PNG reader (stb_image); STATIC keeps it from clashing with libstb.so.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb_image.h>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

using test::RunResult;

RunResult run(const std::string& command) {
  return test::runCommand(command);
}

// A 24-bit screen (xvfb-run's default is 1280x1024x24; said explicitly so GLX gets a visual).
RunResult runViewer(const std::string& arguments) {
  return run(std::string(PENUMBRA_XVFB_RUN) + " -a -s '-screen 0 1600x1200x24' " +
             PENUMBRA_BINARY_DIR + "/bin/penumbra-view " + arguments);
}

RunResult runPenumbra(const std::string& arguments) {
  return run(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra --quiet " + arguments);
}

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Png readPng(const std::string& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &channels, 3);
  if (data == nullptr) return png;
  png.rgb.assign(data, data + std::size_t(png.width) * png.height * 3);
  stbi_image_free(data);
  return png;
}

std::string scene(const std::string& relative) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative;
}

// The viewer's screenshot after `viewerArguments` against `penumbra render` with
// `renderArguments`; both images must be identical and not blank.
void expectSameImage(const std::string& viewerArguments, const std::string& renderArguments) {
  test::TempDir dir;
  const std::string shot = dir.path("viewer.png"), reference = dir.path("render.png");
  const RunResult viewer = runViewer(viewerArguments + " --screenshot " + shot);
  ASSERT_EQ(viewer.exitCode, 0) << viewer.output;
  EXPECT_NE(viewer.output.find("wrote " + shot), std::string::npos) << viewer.output;
  const RunResult render = runPenumbra("render " + renderArguments + " -o " + reference);
  ASSERT_EQ(render.exitCode, 0) << render.output;
  const Png a = readPng(shot), b = readPng(reference);
  ASSERT_FALSE(b.rgb.empty());
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  int differing = 0, lit = 0;
  for (std::size_t i = 0; i < b.rgb.size(); i += 3) {
    if (a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2])
      ++differing;
    if (b.rgb[i] + b.rgb[i + 1] + b.rgb[i + 2] > 0) ++lit;
  }
  std::printf("%s: %d of %d pixels differ, %d not black\n", viewerArguments.c_str(), differing,
              a.width * a.height, lit);
  EXPECT_EQ(differing, 0);
  EXPECT_GT(lit, a.width * a.height / 2);
}

// Frames 0, 1, 2 played through the window (the volumes updated incrementally, as the CLI does),
// with jittered light samples and the mirror composite.
TEST(PenumbraViewWindow, VolumesScreenshotAfterPlayingEqualsRender) {
  const std::string s = scene("cornell-box/cornell-mirror.json");
  expectSameImage(s + " --method volumes --light-samples 4 --frames 3",
                  s + " --method volumes --light-samples 4 --frame 2");
}

// Five frames of a four-frame motion wrap around to frame 0: the volumes are rebuilt.
TEST(PenumbraViewWindow, PlayingWrapsAroundToTheFirstFrame) {
  const std::string s = scene("office-desk/desk-145.json");
  expectSameImage(s + " --method volumes --size 320x240 --frames 5",
                  s + " --method volumes --size 320x240 --frame 0");
}

TEST(PenumbraViewWindow, RadiosityScreenshotEqualsRender) {
  const std::string s = scene("cornell-box/cornell-box.json");
  expectSameImage(s + " --method radiosity --size 128x128 --frame 1",
                  s + " --method radiosity --size 128x128 --frame 1");
}

TEST(PenumbraViewWindow, RaytraceScreenshotEqualsRender) {
  const std::string s = scene("office-desk/desk-145.json");
  expectSameImage(s + " --method raytrace --size 96x72 --frame 1 --frames 2",
                  s + " --method raytrace --size 96x72 --frame 2");
}

// The whole window: the image at the top left, unchanged, and the ImGui panel drawn beside it.
TEST(PenumbraViewWindow, PanelIsDrawnBesideTheImage) {
  test::TempDir dir;
  const std::string s = scene("cornell-box/cornell-box.json");
  const std::string shot = dir.path("window.png"), reference = dir.path("render.png");
  const RunResult viewer = runViewer(s + " --size 160x120 --capture-window --screenshot " + shot);
  ASSERT_EQ(viewer.exitCode, 0) << viewer.output;
  ASSERT_EQ(
      runPenumbra("render " + s + " --method volumes --size 160x120 -o " + reference).exitCode, 0);
  const Png window = readPng(shot), image = readPng(reference);
  // 340-pixel panel; at least 480 rows (viewer_app.cpp).
  ASSERT_EQ(window.width, 160 + 340);
  ASSERT_EQ(window.height, 480);
  int differing = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c)
        if (window.rgb[(std::size_t(y) * window.width + x) * 3 + c] !=
            image.rgb[(std::size_t(y) * 160 + x) * 3 + c])
          ++differing;
  EXPECT_EQ(differing, 0);
  // The panel has text and widgets: many distinct colours, unlike an empty clear colour.
  std::set<int> colours;
  for (int y = 0; y < window.height; ++y)
    for (int x = 160; x < window.width; ++x) {
      const unsigned char* p = &window.rgb[(std::size_t(y) * window.width + x) * 3];
      colours.insert(p[0] << 16 | p[1] << 8 | p[2]);
    }
  EXPECT_GT(colours.size(), 20u);
}

}  // namespace
}  // namespace penumbra
