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

// --drag OBJECT:dx,dy,dz[:degrees] is checked before a window is needed: malformed text by the
// option parser, an object name against the loaded scene; both are usage errors naming --drag.
TEST(PenumbraView, BadDragIsAUsageErrorNamingTheOption) {
  const std::string desk = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-475.json";
  for (const std::string bad :
       {"floating-box", "floating-box:1,2", "floating-box:1,2,3,4", "floating-box:1,,3",
        "floating-box:1,2,x", ":1,2,3", "floating-box:1,2,3:", "floating-box:1,2,3:ten",
        "floating-box:1,2,3:nan", "floating-box:1e999,0,0", "floating-box: 1,2,3"}) {
    const RunResult r = runViewerWithoutDisplay(desk + " --drag '" + bad + "'");
    EXPECT_EQ(r.exitCode, 1) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--drag"), std::string::npos) << bad << ": " << r.output;
    EXPECT_NE(r.output.find(bad), std::string::npos) << bad << ": " << r.output;
  }
  const RunResult r = runViewerWithoutDisplay(desk + " --drag floating-box:0,0,0.1" +
                                              " --drag no-such-box:0.1,0,0:15");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("--drag"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no object named 'no-such-box'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("floating-box"), std::string::npos) << r.output;  // the names there are
}

}  // namespace
}  // namespace penumbra
