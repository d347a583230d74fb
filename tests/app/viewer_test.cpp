// penumbra-view where there is no display (CI without Xvfb, a shell over ssh): it must fail
// cleanly, saying why and what to do, and reject bad options before it needs a window.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "support/run_command.h"

namespace penumbra {
namespace {

using test::RunResult;

// Runs penumbra-view with no display at all (DISPLAY and WAYLAND_DISPLAY removed).
RunResult runViewerWithoutDisplay(const std::string& arguments) {
  return test::runCommand("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(PENUMBRA_BINARY_DIR) +
                          "/bin/penumbra-view " + arguments);
}

const std::string kScene =
    std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";

TEST(PenumbraView, WithoutADisplayExitsWithAMessageNamingXvfbRun) {
  const RunResult r = runViewerWithoutDisplay(kScene + " --screenshot unused.png");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("cannot open a window"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("DISPLAY"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("xvfb-run -a"), std::string::npos) << r.output;
}

TEST(PenumbraView, BadOptionsAreReportedBeforeAWindowIsNeeded) {
  RunResult r = runViewerWithoutDisplay(kScene + " --method phong");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--method"), std::string::npos) << r.output;

  r = runViewerWithoutDisplay(kScene + " --frame 4");  // frames 0..3
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("0..3"), std::string::npos) << r.output;

  r = runViewerWithoutDisplay("missing-scene.json");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("missing-scene.json"), std::string::npos) << r.output;

  r = runViewerWithoutDisplay(kScene + " --size 640by480");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("--size"), std::string::npos) << r.output;

  r = runViewerWithoutDisplay(kScene + " --frames 0");
  EXPECT_EQ(r.exitCode, 1) << r.output;
}

}  // namespace
}  // namespace penumbra
