// Motion as data, end to end: `penumbra probe --frame K` reaches frame K by building frame 0 and
// walking every frame through the engines' update() (the shared grid and ray caster moved, not
// rebuilt), and must print exactly what `--full` prints after building frame K from scratch. Every
// bundled moving scene and the glTF animation, for every deterministic method; points on every
// receiver plus adversarial ones: the moving object's own corners (its polygons move under the
// points' feet) and points on the floor right beside it. (The Galerkin solver's line-space update
// keeps its refinement history, so it is not a fresh build: `radiosity --update verify` checks
// it, and the GalerkinUpdate tests.)

#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

struct Case {
  const char* scene;
  std::vector<const char*> methods;
};

void PrintTo(const Case& c, std::ostream* out) {
  *out << c.scene;
}

std::string formatPoint(const Vec3& p, const Vec3& n) {
  char line[256];
  std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", p.x, p.y, p.z, n.x, n.y,
                n.z);
  return line;
}

// Random points on receivers at frame `frame`, and the corners of every dynamic object's
// non-emitting polygons pulled 1e-6 of the way to the centroid (still on the polygon).
std::string probePoints(const Scene& scene, int frame) {
  const PosedScene posed = poseAt(scene, frame);
  std::string text;
  for (const ReceiverPoint& r : sampleReceiverPoints(posed, 60, 7)) text += formatPoint(r.p, r.n);
  for (const WorldPolygon& polygon : posed.polygons) {
    if (polygon.isLight || !scene.objects[polygon.objectIndex].isDynamic()) continue;
    const Vec3 c = centroid(polygon.vertices);
    for (const Vec3& v : polygon.vertices)
      text += formatPoint(v + (c - v) * 1e-6, polygon.plane.normal);
  }
  return text;
}

std::string probe(const std::string& scene, const std::string& points, const char* method,
                  int frame, bool full) {
  const bool radiosity = std::string(method) == "radiosity" || std::string(method) == "combined";
  const std::string extra = radiosity                             ? " --tolerance 1e-2"
                            : std::string(method) == "montecarlo" ? " --samples 16 --batches 2"
                                                                  : "";
  const test::RunResult r =
      test::runCommand(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra probe " + scene +
                       " --points " + points + " --method " + method + " --frame " +
                       std::to_string(frame) + extra + " --quiet" + (full ? " --full" : ""));
  EXPECT_EQ(r.exitCode, 0) << method << " " << scene << ": " << r.output;
  return r.output;
}

class UpdateEqualsFull : public testing::TestWithParam<Case> {};

TEST_P(UpdateEqualsFull, ProbeAfterWalkingEveryFrameEqualsBuildingTheLastOne) {
  const Case& c = GetParam();
  const std::string scenePath = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + c.scene;
  const Scene scene = loadScene(scenePath);
  ASSERT_GE(scene.dynamicObjectCount(), 1);
  test::TempDir dir;
  // The last frame (every step walked) and a middle one.
  for (const int frame : {scene.frames - 1, scene.frames / 2}) {
    const std::string points =
        dir.write("points-" + std::to_string(frame) + ".txt", probePoints(scene, frame));
    for (const char* method : c.methods) {
      const std::string walked = probe(scenePath, points, method, frame, false);
      const std::string full = probe(scenePath, points, method, frame, true);
      EXPECT_GT(walked.size(), 100u);
      EXPECT_EQ(walked, full) << method << " at frame " << frame;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    BundledMotion, UpdateEqualsFull,
    testing::Values(
        Case{"cornell-box/cornell-box.json",
             {"reference", "dm", "radiosity", "combined", "montecarlo"}},
        Case{"cornell-box/cornell-mirror.json", {"reference", "dm"}},
        // Three objects move at each step, the light among them.
        Case{"cornell-box/cornell-everything-moves.json", {"reference", "dm", "radiosity"}},
        Case{"gltf/animated-box.gltf", {"reference", "dm", "radiosity", "combined", "montecarlo"}},
        Case{"office-desk/desk-145.json", {"reference", "dm", "montecarlo"}},
        Case{"office-desk/desk-145-close.json", {"reference", "dm"}},
        Case{"office-desk/desk-307.json", {"reference", "dm"}},
        Case{"office-desk/desk-475.json", {"reference", "dm"}},
        Case{"chair-room/chair-room.json", {"reference", "dm", "radiosity"}},
        // 4 s per DM frame: its DM walk is left to `shadows --mode verify` runs.
        Case{"chair-room/furnished-room.json", {"reference", "montecarlo"}}),
    [](const testing::TestParamInfo<Case>& info) {
      std::string name = info.param.scene;
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

}  // namespace
}  // namespace penumbra
