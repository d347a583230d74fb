// Reflectance lies in [0, 1] per channel (issue 15 item 6): `Kd 1 1 1`, the white of most MTL
// files, loads as exactly 1; a channel above 1 (or below 0) is an InputError naming the MTL file,
// the line and the material (JSON: the file and the JSON path), never clamped. Direct light does
// not depend on the receiver's reflectance, checked against the exact reference and a closed form.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "penumbra/base/input_error.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/uniform_grid.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

// The InputError loading `path` throws (a failure when there is none).
InputError loadError(const std::string& path) {
  try {
    loadScene(path);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << path;
  return InputError("", "");
}

void expectContains(const std::string& message, const std::string& fragment) {
  EXPECT_NE(message.find(fragment), std::string::npos)
      << "message '" << message << "' lacks '" << fragment << "'";
}

// One square face using the MTL material `paint`.
const char* kSquareObj = R"(mtllib paint.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
usemtl paint
f 1 2 3 4
)";

// A JSON scene of the OBJ above.
std::string writeObjScene(const test::TempDir& dir, const std::string& mtl) {
  dir.write("square.obj", kSquareObj);
  dir.write("paint.mtl", mtl);
  return dir.write("scene.json", R"({ "penumbra": 1, "objects": [ { "obj": "square.obj" } ] })");
}

std::string writeJsonMaterialScene(const test::TempDir& dir, const std::string& reflectance) {
  return dir.write("materials.json", R"({ "penumbra": 1,
  "materials": { "m": { "reflectance": )" +
                                         reflectance + R"( } },
  "objects": [ { "material": "m", "polygons": [ [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] ] } ] })");
}

TEST(ReflectanceRange, MtlKdOneLoadsAsExactlyOne) {
  test::TempDir dir;
  const std::string path = writeObjScene(dir, "newmtl paint\nKd 1 1 1\n");
  for (const Scene& scene : {loadScene(path), loadScene(dir.path("square.obj"))}) {
    ASSERT_EQ(scene.polygonCount(), 1);
    const Material& paint = scene.materials[scene.objects[0].polygonMaterial[0]];
    EXPECT_EQ(paint.name, "paint");
    EXPECT_EQ(paint.reflectance, Rgb(1, 1, 1));  // exactly: "1" is exact in any float format
  }
}

TEST(ReflectanceRange, MtlKdAboveOneNamesFileLineAndMaterial) {
  test::TempDir dir;
  // `paint` is defined on line 4, its Kd is on line 6.
  const std::string path = writeObjScene(dir,
                                         "# two materials\n"
                                         "newmtl other\n"
                                         "Kd 0.2 0.2 0.2\n"
                                         "newmtl paint\n"
                                         "Ka 0 0 0\n"
                                         "Kd 1.2 0.5 0.5\n"
                                         "Ke 0 0 0\n");
  const InputError e = loadError(path);
  EXPECT_EQ(e.location(), dir.path("paint.mtl") + ":6");
  const std::string message = e.what();
  expectContains(message, "paint.mtl:6");
  expectContains(message, "'paint'");
  expectContains(message, "Kd 1.2 0.5 0.5");
  expectContains(message, "[0, 1]");
  expectContains(message, "square.obj:7");  // where the material is used
}

TEST(ReflectanceRange, MtlKdNegativeIsRejected) {
  test::TempDir dir;
  const InputError e = loadError(writeObjScene(dir, "newmtl paint\nKd 0.5 -0.1 0.5\n"));
  EXPECT_EQ(e.location(), dir.path("paint.mtl") + ":2");
  expectContains(e.what(), "'paint'");
}

TEST(ReflectanceRange, MtlLineIsFoundAcrossSeveralMtlFiles) {
  test::TempDir dir;
  // tinyobjloader reads one file per `mtllib` statement, its first name not read before: line 2
  // skips first.mtl and reads second.mtl, where the bad material sits.
  dir.write("two.obj", R"(mtllib first.mtl
mtllib first.mtl second.mtl
v 0 0 0
v 1 0 0
v 0 1 0
usemtl good
f 1 2 3
usemtl bad
f 1 3 2
)");
  dir.write("first.mtl", "newmtl good\nKd 1 1 1\n");
  dir.write("second.mtl", "newmtl spare\n\nnewmtl bad\n  Kd 0.5 2 0.5  \n");
  const std::string path =
      dir.write("two.json", R"({ "penumbra": 1, "objects": [ { "obj": "two.obj" } ] })");
  const InputError e = loadError(path);
  EXPECT_EQ(e.location(), dir.path("second.mtl") + ":4");
  expectContains(e.what(), "'bad'");
  expectContains(e.what(), "two.obj:9");
}

TEST(ReflectanceRange, BareObjWithKdAboveOneIsRejected) {
  test::TempDir dir;
  writeObjScene(dir, "newmtl paint\nKd 1.2 0.5 0.5\n");
  // A bare OBJ scene is checked by validateScene, which names the OBJ and the material.
  const InputError e = loadError(dir.path("square.obj"));
  expectContains(e.what(), "square.obj");
  expectContains(e.what(), "'paint'");
  expectContains(e.what(), "[0, 1]");
}

TEST(ReflectanceRange, JsonReflectanceOneLoads) {
  test::TempDir dir;
  const Scene scene = loadScene(writeJsonMaterialScene(dir, "[1, 1, 1]"));
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].reflectance, Rgb(1, 1, 1));
}

TEST(ReflectanceRange, JsonReflectanceOutOfRangeNamesThePath) {
  for (const char* reflectance : {"[1.5, 0, 0]", "[0.5, 0.5, -0.1]", "[0, 1.0000001, 0]"}) {
    test::TempDir dir;
    const InputError e = loadError(writeJsonMaterialScene(dir, reflectance));
    EXPECT_EQ(e.location(), dir.path("materials.json") + ": /materials/m/reflectance")
        << reflectance;
    expectContains(e.what(), "[0, 1]");
  }
}

// Form factor from the origin (normal +z) to the rectangle [x0,x1]x[y0,y1] at height c parallel
// to it, by inclusion-exclusion of corner rectangles (as in tests/lighting/exact_reference_test).
double parallelRectangleFormFactor(double x0, double x1, double y0, double y1, double c) {
  const auto corner = [c](double x, double y) {
    const double a = std::abs(x), b = std::abs(y);
    const double ac = std::hypot(a, c), bc = std::hypot(b, c);
    const double f =
        (a / ac * std::atan(b / ac) + b / bc * std::atan(a / bc)) / (2 * std::numbers::pi);
    return (x < 0 ? -1 : 1) * (y < 0 ? -1 : 1) * f;
  };
  return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

// A unit-exitance square light [-1,1]² at height 2 facing down, over a floor at z = 0, with an
// occluder at height 1 over x in [0, 3]; floor and occluder come from an OBJ whose MTL gives
// `paint` the reflectance `kd`.
Scene loadLitFloor(const test::TempDir& dir, const std::string& kd) {
  dir.write("floor.obj", R"(mtllib floor.mtl
v -5 -5 0
v 5 -5 0
v 5 5 0
v -5 5 0
v 0 -3 1
v 3 -3 1
v 3 3 1
v 0 3 1
usemtl paint
f 1 2 3 4
f 5 6 7 8
)");
  dir.write("floor.mtl", "newmtl paint\nKd " + kd + "\n");
  return loadScene(dir.write("lit.json", R"({ "penumbra": 1,
  "materials": { "lamp": { "reflectance": [0, 0, 0], "emission": [1, 1, 1] } },
  "objects": [
    { "name": "lamp", "material": "lamp", "polygons": [ [[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]] ] },
    { "name": "floor", "obj": "floor.obj" } ] })"));
}

TEST(ReflectanceRange, DirectIrradianceDoesNotDependOnReflectance) {
  test::TempDir dir;
  const Scene white = loadLitFloor(dir, "1 1 1");
  const Scene gray = loadLitFloor(dir, "0.5 0.5 0.5");
  const PosedScene whitePosed = poseAt(white, 0), grayPosed = poseAt(gray, 0);
  const PolygonId floor = whitePosed.objectFirstPolygon[1];
  ASSERT_EQ(whitePosed.materialOf(whitePosed.polygons[floor]).reflectance, Rgb(1, 1, 1));
  ASSERT_EQ(grayPosed.materialOf(grayPosed.polygons[floor]).reflectance, Rgb(0.5, 0.5, 0.5));
  const UniformGrid whiteGrid(whitePosed), grayGrid(grayPosed);
  const ExactReference whiteReference(whitePosed, &whiteGrid), grayReference(grayPosed, &grayGrid);

  // Closed forms: from the origin the occluder hides the light's half x > 0 (central projection
  // doubles distances at height 2); from (-0.25, 0, 0) its edge projects to x = 0.25; from
  // (-3, 1, 0) it hides nothing (the rays cross height 1 at x in [-2, -1]).
  struct Probe {
    Vec3 p;
    double formFactor;
  };
  const Probe probes[] = {
      {{0, 0, 0}, parallelRectangleFormFactor(-1, 0, -1, 1, 2)},
      {{-0.25, 0, 0}, parallelRectangleFormFactor(-0.75, 0.5, -1, 1, 2)},
      {{-3, 1, 0}, parallelRectangleFormFactor(2, 4, -2, 0, 2)},
  };
  for (const Probe& probe : probes) {
    const Rgb e1 = whiteReference.irradiance(probe.p, {0, 0, 1}, floor);
    const Rgb e05 = grayReference.irradiance(probe.p, {0, 0, 1}, floor);
    // The same geometry through the same code: identical, not merely close.
    EXPECT_EQ(e1, e05) << "at " << probe.p.x << " " << probe.p.y;
    // Exitance 1: E = F. 1e-14 as in exact_reference_test (a few ulps of well-conditioned
    // arctangents and Clipper's 2^-60 snapping).
    for (double channel : {e1.r, e1.g, e1.b}) EXPECT_NEAR(channel, probe.formFactor, 1e-14);
  }
}

}  // namespace
}  // namespace penumbra
