// End-to-end tests of the `penumbra` executable: the contract of DESIGN.md §6 (CSV format, exit
// codes, messages naming files and lines).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/run_command.h"
#include "support/scene_test_name.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

using test::RunResult;

RunResult runPenumbra(const std::string& arguments) {
  return test::runCommand(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra --quiet " + arguments);
}

const char* kScene = R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] },
                 "lamp": { "reflectance": [0, 0, 0], "emission": [1, 2, 3] } },
  "objects": [
    { "name": "lamp", "material": "lamp", "polygons": [ [[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]] ] },
    { "name": "floor", "material": "white", "polygons": [ [[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]] ] },
    { "name": "blocker", "material": "white",
      "polygons": [ [[-3,-3,1],[3,-3,1],[3,3,1],[-3,3,1]] ],
      "motion": [ { "frame": 0 }, { "frame": 1, "translate": [0, 0, -5] } ] } ] })";

TEST(Cli, ProbeReferencePrintsCsvWithSeventeenDigits) {
  test::TempDir dir;
  const std::string scene = dir.write("scene.json", kScene);
  const std::string points = dir.write("points.txt", "# header\n\n0 0 0 0 0 2\n0.5 0.25 0 0 0 1\n");
  // Frame 1: the blocker has moved below the floor; the light is fully visible.
  const RunResult r = runPenumbra("probe " + scene + " --points " + points + " --frame 1");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::istringstream lines(r.output);
  std::string header, first, second;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_EQ(header, "x,y,z,nx,ny,nz,r,g,b");
  EXPECT_EQ(first.substr(0, 12), "0,0,0,0,0,2,");  // the normal is echoed as given
  // r = 4·F_corner(1,1,2) with the closed form of the parallel rectangle form factor.
  const double ac = std::hypot(1.0, 2.0);
  const double corner = 2 * (1 / ac) * std::atan(1 / ac) / (2 * std::numbers::pi);
  double x, y, z, nx, ny, nz, red, green, blue;
  ASSERT_EQ(std::sscanf(first.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &x, &y, &z, &nx, &ny,
                        &nz, &red, &green, &blue),
            9);
  EXPECT_NEAR(red, 4 * corner, 1e-15);
  EXPECT_NEAR(green, 2 * red, 1e-15);
  EXPECT_NEAR(blue, 3 * red, 1e-15);
  EXPECT_NE(second.find("0.5,0.25,0,0,0,1,"), std::string::npos);
  // Frame 0: the blocker hides the light completely.
  const RunResult umbra = runPenumbra("probe " + scene + " --points " + points);
  EXPECT_NE(umbra.output.find("0,0,0,0,0,2,0,0,0"), std::string::npos) << umbra.output;
}

// The r column of a probe CSV, row by row.
std::vector<double> redColumn(const std::string& csv) {
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // header
  std::vector<double> values;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string field;
    for (int column = 0; column <= 6; ++column) std::getline(fields, field, ',');
    values.push_back(std::stod(field));
  }
  return values;
}

TEST(Cli, ProbeDmEqualsTheReferenceAcrossAPenumbra) {
  test::TempDir dir;
  const std::string lampAndFloor = R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] },
                 "lamp": { "reflectance": [0, 0, 0], "emission": [1, 1, 1] } },
  "objects": [
    { "name": "lamp", "material": "lamp", "polygons": [ [[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]] ] },
    { "name": "floor", "material": "white", "polygons": [ [[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]] ] })";
  const std::string unblocked = dir.write("unblocked.json", lampAndFloor + " ] }");
  // A tilted card smaller than the light: no umbra, a penumbra all around.
  const std::string scene = dir.write("scene.json", lampAndFloor + R"(,
    { "name": "card", "material": "white",
      "polygons": [ [[-0.3,-0.2,0.96],[0.4,-0.3,1.025],[0.35,0.4,1.055],[-0.25,0.3,0.99]] ] } ] })");
  std::string grid;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j)
      grid += std::to_string(-1.75 + 0.25 * i + 0.013 * j) + " " +
              std::to_string(-1.75 + 0.25 * j + 0.007 * i) + " 0 0 0 1\n";
  const std::string points = dir.write("points.txt", grid);
  const RunResult dm = runPenumbra("probe " + scene + " --points " + points + " --method dm");
  const RunResult reference = runPenumbra("probe " + scene + " --points " + points);
  const RunResult open = runPenumbra("probe " + unblocked + " --points " + points);
  ASSERT_EQ(dm.exitCode, 0) << dm.output;
  ASSERT_EQ(open.exitCode, 0) << open.output;
  ASSERT_EQ(reference.exitCode, 0) << reference.output;
  const std::vector<double> a = redColumn(dm.output), b = redColumn(reference.output),
                            lit = redColumn(open.output);
  ASSERT_EQ(a.size(), 225u);
  ASSERT_EQ(b.size(), 225u);
  int penumbra = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], 1e-9 * std::max(b[i], 1e-3)) << "point " << i;
    penumbra += b[i] > 0 && b[i] < 0.999 * lit[i] ? 1 : 0;
  }
  EXPECT_GT(penumbra, 5);  // the grid does cross the card's penumbra
  // A point on no receiver is an error naming its line.
  const std::string off = dir.write("off.txt", "0 0 0 0 0 1\n0 0 0.5 0 0 1\n");
  const RunResult bad = runPenumbra("probe " + scene + " --points " + off + " --method dm");
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.output.find("off.txt:2"), std::string::npos) << bad.output;
}

TEST(Cli, ProbePointsRoundedOffTheirReceiverStillSeeTheLight) {
  // A point written with rounding that puts it 1e-7 behind the floor is still on the floor: the
  // floor must not occlude it.
  test::TempDir dir;
  const std::string scene = dir.write("scene.json", kScene);
  const std::string points = dir.write("points.txt", "0 0 0 0 0 1\n0 0 -1e-7 0 0 1\n");
  const RunResult r = runPenumbra("probe " + scene + " --points " + points + " --frame 1");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::istringstream lines(r.output);
  std::string header, onFloor, behind;
  std::getline(lines, header);
  std::getline(lines, onFloor);
  std::getline(lines, behind);
  const double exact = std::stod(onFloor.substr(onFloor.rfind(',') + 1));
  const double rounded = std::stod(behind.substr(behind.rfind(',') + 1));
  EXPECT_GT(exact, 0.1);
  EXPECT_NEAR(rounded, exact, 1e-6 * exact);
}

TEST(Cli, ExitCodesAndMessages) {
  test::TempDir dir;
  const std::string scene = dir.write("scene.json", kScene);
  const std::string badPoints = dir.write("bad.txt", "0 0 0 0 0 1\n1 2 3\n");
  const RunResult badLine = runPenumbra("probe " + scene + " --points " + badPoints);
  EXPECT_EQ(badLine.exitCode, 2);
  EXPECT_NE(badLine.output.find("bad.txt:2"), std::string::npos) << badLine.output;

  const RunResult zeroNormal =
      runPenumbra("probe " + scene + " --points " + dir.write("zero.txt", "0 0 0 0 0 0\n"));
  EXPECT_EQ(zeroNormal.exitCode, 2);
  EXPECT_NE(zeroNormal.output.find("zero.txt:1"), std::string::npos);

  const RunResult badScene = runPenumbra("info " + dir.write("broken.json", "{ \"penumbra\": 1, "));
  EXPECT_EQ(badScene.exitCode, 2);
  EXPECT_NE(badScene.output.find("broken.json:1:"), std::string::npos) << badScene.output;

  EXPECT_EQ(runPenumbra("").exitCode, 1);
  EXPECT_EQ(runPenumbra("probe " + scene).exitCode, 1);  // --points is required
  EXPECT_EQ(runPenumbra("probe " + scene + " --points " + badPoints + " --frame 9").exitCode, 1);
  EXPECT_EQ(runPenumbra("info " + scene).exitCode, 0);
}

TEST(Cli, InfoReportsCounts) {
  test::TempDir dir;
  const RunResult r = runPenumbra("info --json " + dir.write("scene.json", kScene));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("\"polygons\": 3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"lights\": 1"), std::string::npos);
  EXPECT_NE(r.output.find("\"dynamic_objects\": 1"), std::string::npos);
  EXPECT_NE(r.output.find("\"frames\": 2"), std::string::npos);
  EXPECT_NE(r.output.find("\"closed\": false"), std::string::npos);
}

// A closed scene made of objects open by themselves (the Cornell box's walls) says both without
// the second reading as a contradiction of the first.
TEST(Cli, InfoTellsTheClosedSceneFromItsOpenObjects) {
  const RunResult r = runPenumbra("info " + std::string(PENUMBRA_SOURCE_DIR) +
                                  "/scenes/cornell-box/cornell-box.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("closed           yes (every edge of the scene is shared"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("open objects     5, each open by itself (closed by the others):"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("  room-white: 8 open edges"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(Cli, RenderVolumesWritesAPng) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string out = dir.path("out/volumes.png");
  const RunResult r = runPenumbra(
      "render " + scene + " --method volumes --light-samples 4 --frame 2 --size 64x48 -o " + out);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  FILE* file = std::fopen(out.c_str(), "rb");
  ASSERT_NE(file, nullptr);
  unsigned char signature[8] = {};
  EXPECT_EQ(std::fread(signature, 1, 8, file), 8u);
  std::fclose(file);
  EXPECT_EQ(signature[1], 'P');
  EXPECT_EQ(signature[2], 'N');
  EXPECT_EQ(signature[3], 'G');
  EXPECT_EQ(
      runPenumbra("render " + scene + " --method volumes --light-samples 0 -o " + out).exitCode, 1);
}

TEST(Cli, ShadowsFullWritesAReportAndAMeshPerFrame) {
  test::TempDir dir;
  const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json";
  const std::string report = dir.path("report.json");
  const std::string meshes = dir.path("meshes");
  const RunResult r = runPenumbra("shadows " + scene + " --frames 1:2 --mode full --report " +
                                  report + " --out " + meshes);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(report);
  std::stringstream text;
  text << in.rdbuf();
  for (const char* key :
       {"\"frames\"", "\"frame\": 1", "\"frame\": 2", "\"seconds\"", "\"peak_memory_bytes\"",
        "\"ev_non_emitter\"", "\"faces\"", "\"stored_intersections\"", "\"receivers\"",
        "\"light_plane_segments\"", "\"horizon_segments\""})
    EXPECT_NE(text.str().find(key), std::string::npos) << key;
  for (const char* ply : {"/frame-1.ply", "/frame-2.ply"}) {
    std::ifstream mesh(meshes + ply);
    std::string magic;
    std::getline(mesh, magic);
    EXPECT_EQ(magic, "ply") << ply;
  }
  EXPECT_EQ(runPenumbra("shadows " + scene + " --mode sometimes").exitCode, 1);
  EXPECT_EQ(runPenumbra("shadows " + scene + " --frames 2:9").exitCode, 1);
}

// --mode verify runs the engine held across frames (told each change through update) beside one
// built from scratch per frame, and reports each frame as identical or not.
TEST(Cli, ShadowsVerifyComparesUpdatesWithFullRecomputation) {
  test::TempDir dir;
  const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json";
  const std::string report = dir.path("report.json");
  const RunResult r = runPenumbra("shadows " + scene + " --mode verify --report " + report);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(report);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("\"identical_to_full\": true"), std::string::npos);
  EXPECT_EQ(text.str().find("\"identical_to_full\": false"), std::string::npos);
  EXPECT_NE(text.str().find("\"moved_objects\": 1"), std::string::npos);
  // The glTF animation's 25 frames: at frame 13 a kept mesh once listed an edge's surfaces in
  // another order than a rebuilt one (edges now list them sorted).
  const RunResult gltf = runPenumbra("shadows " + std::string(PENUMBRA_SOURCE_DIR) +
                                     "/scenes/gltf/animated-box.gltf --mode verify");
  EXPECT_EQ(gltf.exitCode, 0) << gltf.output;
}

// A point where the Cornell box's short block stands on the floor: the face's backprojection is
// degenerate there (Lambert's formula meets zero-length edges: it printed -nan), so the point is
// answered by the exact reference, the report says so, and the value equals `--method reference`.
TEST(Cli, ProbeDmAtAContactCornerIsFiniteAndReportsHowItWasAnswered) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string points = dir.write("points.txt", "0.29 0 0.114 0 1 0\n0.5 0 0.5 0 1 0\n");
  const std::string report = dir.path("report.json");
  const RunResult dm =
      runPenumbra("probe " + scene + " --points " + points + " --method dm --report " + report);
  ASSERT_EQ(dm.exitCode, 0) << dm.output;
  EXPECT_EQ(dm.output.find("nan"), std::string::npos) << dm.output;
  const RunResult reference = runPenumbra("probe " + scene + " --points " + points);
  ASSERT_EQ(reference.exitCode, 0) << reference.output;
  std::istringstream a(dm.output), b(reference.output);
  std::string lineA, lineB;
  std::getline(a, lineA);
  std::getline(b, lineB);
  for (int i = 0; i < 2; ++i) {
    std::getline(a, lineA);
    std::getline(b, lineB);
    double va[9], vb[9];
    ASSERT_EQ(std::sscanf(lineA.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &va[0], &va[1],
                          &va[2], &va[3], &va[4], &va[5], &va[6], &va[7], &va[8]),
              9);
    ASSERT_EQ(std::sscanf(lineB.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &vb[0], &vb[1],
                          &vb[2], &vb[3], &vb[4], &vb[5], &vb[6], &vb[7], &vb[8]),
              9);
    for (int c = 6; c < 9; ++c) EXPECT_NEAR(va[c], vb[c], 1e-9 * std::max(1.0, vb[c])) << i;
  }
  std::ifstream in(report);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("\"answered_by_mesh\": 1"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("\"answered_at_point\": 1"), std::string::npos) << text.str();
  // The block's corner on the floor lies on the block's polygons: a contact, answered at the
  // point (it was answered as "degenerate" once the backprojection there gave NaN).
  EXPECT_NE(text.str().find("\"on_another_polygon\": 1"), std::string::npos) << text.str();
}

// Reflectance 1 is in most real OBJ/MTL files (`Kd 1 1 1`): such a scene loads, renders and
// probes (direct light does not depend on reflectance).
TEST(Cli, ObjWithKdOneLoadsAndRenders) {
  test::TempDir dir;
  dir.write("white.mtl", "newmtl white\nKd 1 1 1\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n");
  const std::string obj = dir.write("room.obj",
                                    "mtllib white.mtl\n"
                                    "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
                                    "v -0.2 2 -0.2\nv 0.2 2 -0.2\nv 0.2 2 0.2\nv -0.2 2 0.2\n"
                                    "usemtl white\nf 4 3 2 1\n"
                                    "usemtl lamp\nf 5 6 7 8\n");
  EXPECT_EQ(runPenumbra("info " + obj).exitCode, 0);
  const std::string png = dir.path("white.png");
  const RunResult render =
      runPenumbra("render " + obj + " --method raytrace --size 32x24 -o " + png);
  EXPECT_EQ(render.exitCode, 0) << render.output;
  std::ifstream image(png, std::ios::binary);
  EXPECT_TRUE(image.good());
  const std::string points = dir.write("points.txt", "0 0 0 0 1 0\n");
  const RunResult dm = runPenumbra("probe " + obj + " --points " + points + " --method dm");
  EXPECT_EQ(dm.exitCode, 0) << dm.output;
}

// Repeated vertices, as real files have them (a closing repeat of the first corner, a consecutive
// duplicate, an OBJ face `f a b b c d`), are removed on loading: the scene gives exactly what the
// same scene without them gives (they crashed the exact engine).
TEST(Cli, RepeatedVerticesGiveTheSameShadowsAsWithoutThem) {
  test::TempDir dir;
  const auto sceneWith = [](const std::string& blocker) {
    return std::string(R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] },
                 "lamp": { "reflectance": [0, 0, 0], "emission": [1, 1, 1] } },
  "objects": [
    { "name": "lamp", "material": "lamp", "polygons": [ [[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]] ] },
    { "name": "floor", "material": "white", "polygons": [ [[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]] ] },
    { "name": "blocker", "material": "white", "polygons": [ )") +
           blocker + " ] } ] }";
  };
  const std::string clean =
      dir.write("clean.json", sceneWith("[[-0.5,-0.5,1],[0.5,-0.5,1],[0.5,0.5,1],[-0.5,0.5,1]]"));
  const std::string repeated = dir.write(
      "repeated.json",
      sceneWith(
          "[[-0.5,-0.5,1],[0.5,-0.5,1],[0.5,-0.5,1],[0.5,0.5,1],[-0.5,0.5,1],[-0.5,-0.5,1]]"));
  dir.write("white.mtl", "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
  const std::string obj = dir.write("repeated.obj",
                                    "mtllib white.mtl\n"
                                    "v -1 -1 2\nv -1 1 2\nv 1 1 2\nv 1 -1 2\n"
                                    "v -5 -5 0\nv 5 -5 0\nv 5 5 0\nv -5 5 0\n"
                                    "v -0.5 -0.5 1\nv 0.5 -0.5 1\nv 0.5 0.5 1\nv -0.5 0.5 1\n"
                                    "usemtl lamp\nf 1 2 3 4\n"
                                    "usemtl white\nf 5 6 7 8\nf 9 10 10 11 12\n");
  const std::string points =
      dir.write("points.txt", "0 0 0 0 0 1\n0.6 0.3 0 0 0 1\n0.9 0.9 0 0 0 1\n-1.2 0.4 0 0 0 1\n");
  const RunResult expected = runPenumbra("probe " + clean + " --points " + points + " --method dm");
  ASSERT_EQ(expected.exitCode, 0) << expected.output;
  for (const std::string& scene : {repeated, obj}) {
    const RunResult shadows = runPenumbra("shadows " + scene + " --mode full");
    EXPECT_EQ(shadows.exitCode, 0) << scene << ": " << shadows.output;
    const RunResult dm = runPenumbra("probe " + scene + " --points " + points + " --method dm");
    ASSERT_EQ(dm.exitCode, 0) << scene << ": " << dm.output;
    EXPECT_EQ(dm.output, expected.output) << scene;
  }
}

// A tolerance finer than the scene warrants stops at the refinement budget with a message naming
// --tolerance and the budget, instead of taking all memory; the budget is an option.
TEST(Cli, RadiosityStopsAtItsBudget) {
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const RunResult fine = runPenumbra("radiosity " + scene + " --frames 0:0 --tolerance 1e-12");
  EXPECT_EQ(fine.exitCode, 2) << fine.output;
  EXPECT_NE(fine.output.find("--tolerance"), std::string::npos) << fine.output;
  EXPECT_NE(fine.output.find("1000000 links"), std::string::npos) << fine.output;
  EXPECT_NE(fine.output.find("--max-links"), std::string::npos) << fine.output;
  const RunResult elements =
      runPenumbra("radiosity " + scene + " --frames 0:0 --tolerance 1e-2 --max-elements 50");
  EXPECT_EQ(elements.exitCode, 2) << elements.output;
  EXPECT_NE(elements.output.find("50 elements"), std::string::npos) << elements.output;
  // The default tolerance fits the default budget; a budget past the range is a usage error.
  const RunResult fits = runPenumbra("radiosity " + scene + " --frames 0:0 --tolerance 1e-2");
  EXPECT_EQ(fits.exitCode, 0) << fits.output;
  for (const char* value : {"0", "-3", "1e15", "4294967297000000000000"}) {
    const RunResult r = runPenumbra("radiosity " + scene + " --frames 0:0 --max-links " + value);
    EXPECT_EQ(r.exitCode, 1) << value << ": " << r.output;
  }
  // The Galerkin core keeps the same budget.
  test::TempDir dir;
  const std::string points = dir.write("p.txt", "0.3 0 0.1 0 1 0\n");
  const RunResult galerkin = runPenumbra("probe " + scene + " --points " + points +
                                         " --method galerkin --tolerance 1e-9 --max-links 5000");
  EXPECT_EQ(galerkin.exitCode, 2) << galerkin.output;
  EXPECT_NE(galerkin.output.find("5000 links"), std::string::npos) << galerkin.output;
  EXPECT_NE(galerkin.output.find("--max-links"), std::string::npos) << galerkin.output;
}

// Numbers that used to be accepted silently: a negative frame range, a NaN tolerance, an integer
// that wraps in the scene file, a keyframe whose frame count would overflow.
TEST(Cli, OutOfRangeNumbersAreRefused) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const RunResult negative = runPenumbra("shadows " + scene + " --frames -5:-4");
  EXPECT_EQ(negative.exitCode, 1) << negative.output;
  EXPECT_NE(negative.output.find("--frames"), std::string::npos) << negative.output;
  const std::string out = dir.path("r.png");
  for (const char* value : {"nan", "inf", "-1", "0"}) {
    const RunResult r = runPenumbra("render " + scene + " --method radiosity --tolerance " +
                                    std::string(value) + " -o " + out);
    EXPECT_EQ(r.exitCode, 1) << value << ": " << r.output;
  }
  const auto sceneFile = [&](const std::string& name, const std::string& moreObjects,
                             const std::string& moreKeys) {
    return dir.write(name, std::string(R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] },
                 "lamp": { "reflectance": [0, 0, 0], "emission": [1, 1, 1] } },
  "objects": [
    { "name": "lamp", "material": "lamp", "polygons": [ [[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]] ] },
    { "name": "floor", "material": "white", "polygons": [ [[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]] ] })") +
                               moreObjects + " ]" + moreKeys + " }");
  };
  const std::string wraps = sceneFile("wraps.json", "",
                                      ", \"camera\": { \"eye\": [0, -4, 3], \"target\": [0, 0, 0], "
                                      "\"width\": 4294967297, \"height\": 48 }");
  const RunResult wrapped = runPenumbra("info " + wraps);
  EXPECT_EQ(wrapped.exitCode, 2) << wrapped.output;
  EXPECT_NE(wrapped.output.find("/camera/width"), std::string::npos) << wrapped.output;
  EXPECT_NE(wrapped.output.find("out of range"), std::string::npos) << wrapped.output;
  const std::string late =
      sceneFile("late.json",
                ", { \"name\": \"box\", \"material\": \"white\", \"polygons\": "
                "[ [[0,0,1],[1,0,1],[1,1,1],[0,1,1]] ], \"motion\": [ { \"frame\": 0 }, "
                "{ \"frame\": 2147483647 } ] }",
                "");
  const RunResult overflow = runPenumbra("info " + late);
  EXPECT_EQ(overflow.exitCode, 2) << overflow.output;
  EXPECT_NE(overflow.output.find("frame"), std::string::npos) << overflow.output;
}

// MTL colours tinyobjloader reads as 0 (a light channel vanished silently) are bad input naming
// the MTL file and line.
TEST(Cli, MtlColoursThatAreNotNumbersAreBadInput) {
  for (const char* colour : {"Kd red", "Kd nan 0 0", "Ke inf 1 1", "Ke 1 2"}) {
    test::TempDir dir;
    dir.write("m.mtl", std::string("newmtl m\n") + colour + "\n");
    const std::string obj =
        dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
    const RunResult r = runPenumbra("info " + obj);
    EXPECT_EQ(r.exitCode, 2) << colour << ": " << r.output;
    EXPECT_NE(r.output.find("m.mtl:2"), std::string::npos) << colour << ": " << r.output;
  }
}

// Outputs: a write error is an error (not "wrote"), no partial file is left, the scene is never
// overwritten, and a failing --exr leaves no PNG behind.
TEST(Cli, OutputsAreWrittenWholeOrNotAtAll) {
  test::TempDir dir;
  const std::string scene = dir.write("scene.json", kScene);
  const RunResult full =
      runPenumbra("render " + scene + " --method raytrace --size 16x12 -o /dev/full");
  EXPECT_EQ(full.exitCode, 2) << full.output;
  EXPECT_EQ(full.output.find("wrote"), std::string::npos) << full.output;
  const RunResult over =
      runPenumbra("render " + scene + " --method raytrace --size 16x12 -o " + scene);
  EXPECT_EQ(over.exitCode, 1) << over.output;
  std::ifstream kept(scene);
  std::stringstream text;
  text << kept.rdbuf();
  EXPECT_EQ(text.str(), kScene);
  const std::string png = dir.path("image.png");
  const RunResult exr = runPenumbra("render " + scene + " --method raytrace --size 16x12 -o " +
                                    png + " --exr /dev/full");
  EXPECT_NE(exr.exitCode, 0) << exr.output;
  EXPECT_FALSE(std::ifstream(png).good()) << "a PNG was left behind";
  const RunResult good =
      runPenumbra("render " + scene + " --method raytrace --size 16x12 -o " + png);
  EXPECT_EQ(good.exitCode, 0) << good.output;
  EXPECT_TRUE(std::ifstream(png).good());
  for (const auto& entry : std::filesystem::directory_iterator(dir.path("")))
    EXPECT_EQ(entry.path().string().find(".partial-"), std::string::npos) << entry.path();
}

// Drawing the discontinuity edges does not change the automatic exposure (it made the picture 3.5x
// darker): the exposure comes from the picture without them.
TEST(Cli, EdgesDoNotChangeTheExposure) {
  test::TempDir dir;
  const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json";
  const auto exposure = [&](const std::string& extra) {
    const RunResult r =
        test::runCommand(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra render " + scene +
                         " --method dm --size 80x60 -o " + dir.path("e.png") + extra);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    const size_t at = r.output.find("exposure ");
    return at == std::string::npos ? std::string() : r.output.substr(at, 20);
  };
  const std::string plain = exposure("");
  EXPECT_FALSE(plain.empty());
  EXPECT_EQ(exposure(" --edges"), plain);
}

// An OBJ whose lines end with CR alone is bad input naming the file (it failed with
// vector::_M_range_check and no file named).
TEST(Cli, ObjWithCarriageReturnLineEndingsIsBadInputNamingTheFile) {
  test::TempDir dir;
  const std::string obj = dir.write("mac.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r");
  const RunResult r = runPenumbra("info " + obj);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("mac.obj:1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("carriage return"), std::string::npos) << r.output;
}

// A folder where a file is expected opened as an empty stream: no rows, an empty object, exit 0.
TEST(Cli, FoldersWhereFilesAreExpectedAreBadInput) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const RunResult points = runPenumbra("probe " + scene + " --points " + dir.path(""));
  EXPECT_EQ(points.exitCode, 2) << points.output;
  EXPECT_NE(points.output.find("folder"), std::string::npos) << points.output;
  const std::string folderObj =
      dir.write("folder.json",
                R"({ "penumbra": 1, "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] } },
  "objects": [ { "name": "room", "obj": ".", "material": "white" } ] })");
  const RunResult obj = runPenumbra("info " + folderObj);
  EXPECT_EQ(obj.exitCode, 2) << obj.output;
  EXPECT_NE(obj.output.find("folder"), std::string::npos) << obj.output;
}

// Global options are accepted after the verb too (DESIGN.md §6), as the README shows them.
TEST(Cli, GlobalOptionsAfterTheVerb) {
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const RunResult r = test::runCommand(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra info " +
                                       scene + " --quiet --threads 1");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  const RunResult shadows =
      test::runCommand(std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra shadows " + scene +
                       " --frames 0:0 --mode full --quiet");
  EXPECT_EQ(shadows.exitCode, 0) << shadows.output;
  EXPECT_EQ(shadows.output, "");  // --quiet silences the per-frame lines
}

TEST(Cli, RenderDmWritesAPng) {
  test::TempDir dir;
  const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json";
  const std::string out = dir.path("dm.png");
  const RunResult r =
      runPenumbra("render " + scene + " --method dm --edges --size 64x48 -o " + out);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream png(out, std::ios::binary);
  char signature[4] = {};
  png.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  EXPECT_EQ(runPenumbra("render " + scene + " --method raytrace --edges -o " + out).exitCode, 1);
}

// `render --method combined` (exact direct light on the discontinuity mesh, radiosity's indirect
// light added at its corners) writes a PNG; `probe --method combined` gives at least the exact
// direct irradiance (the reference's) and adds light reflected by the room.
TEST(Cli, CombinedRendersAndProbes) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string out = dir.path("combined.png");
  const RunResult render =
      runPenumbra("render " + scene + " --method combined --tolerance 1e-2 --size 48x48 -o " + out);
  ASSERT_EQ(render.exitCode, 0) << render.output;
  std::ifstream png(out, std::ios::binary);
  char signature[4] = {};
  png.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  // The floor in the open and the ceiling (no direct light: the lamp faces down).
  const std::string points = dir.write("p.txt", "0.1 0 0.45 0 1 0\n0.2 0.5488 0.4 0 -1 0\n");
  const RunResult combined =
      runPenumbra("probe " + scene + " --points " + points + " --method combined --tolerance 1e-2");
  const RunResult direct = runPenumbra("probe " + scene + " --points " + points);
  ASSERT_EQ(combined.exitCode, 0) << combined.output;
  ASSERT_EQ(direct.exitCode, 0) << direct.output;
  const std::vector<double> total = redColumn(combined.output), exact = redColumn(direct.output);
  ASSERT_EQ(total.size(), 2u);
  ASSERT_EQ(exact.size(), 2u);
  EXPECT_GT(total[0], exact[0] * 1.1);  // reflected light adds at least a tenth on the floor
  EXPECT_EQ(exact[1], 0);
  EXPECT_GT(total[1], 0.05);  // the ceiling is lit by the room only
}

// `radiosity --report`: per-frame statistics with memory per structure (elements, active and
// passive links, shafts) and the shafts by kind.
TEST(Cli, RadiosityReportAccountsMemoryPerStructure) {
  test::TempDir dir;
  const std::string report = dir.path("report.json");
  const RunResult r = runPenumbra("radiosity " + std::string(PENUMBRA_SOURCE_DIR) +
                                  "/scenes/cornell-box/cornell-box.json --frames 0:0 --update full "
                                  "--tolerance 1e-2 --report " +
                                  report);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  FILE* file = std::fopen(report.c_str(), "r");
  ASSERT_NE(file, nullptr);
  std::string text;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) text.append(buffer.data(), n);
  std::fclose(file);
  for (const char* key :
       {"\"frames\"", "\"seconds\"", "\"peak_memory_bytes\"", "\"links\"", "\"passive_links\"",
        "\"shafts\"", "\"polygon_shafts\"", "\"memory_bytes\"", "\"elements\"", "\"active_links\""})
    EXPECT_NE(text.find(key), std::string::npos) << key;
}

// The Galerkin core over frames: one entry per frame with its links, elements, stages and memory,
// the same solution whether reached by stepping or built at the frame.
TEST(Cli, RadiosityGalerkinReportsEveryFrame) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string walked = dir.path("walked.json"), built = dir.path("built.json");
  const RunResult r = runPenumbra(
      "radiosity " + scene + " --frames 0:2 --solver galerkin --tolerance 1e-2 --report " + walked);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const RunResult alone = runPenumbra(
      "radiosity " + scene + " --frames 2:2 --solver galerkin --tolerance 1e-2 --report " + built);
  ASSERT_EQ(alone.exitCode, 0) << alone.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(walked));
  const nlohmann::json single = nlohmann::json::parse(std::ifstream(built));
  EXPECT_EQ(report["method"], "galerkin");
  ASSERT_EQ(report["frames"].size(), 3u);
  for (const nlohmann::json& frame : report["frames"]) {
    EXPECT_GT(frame["links"].get<long long>(), 100);
    EXPECT_GT(frame["seconds"].get<double>(), 0);
    EXPECT_GT(frame["memory_bytes"]["total"].get<long long>(), 0);
  }
  EXPECT_EQ(report["frames"][2]["links"], single["frames"][0]["links"]);
  EXPECT_EQ(report["frames"][2]["point_pairs"], single["frames"][0]["point_pairs"]);
  const RunResult unknown = runPenumbra("radiosity " + scene + " --solver bogus");
  EXPECT_EQ(unknown.exitCode, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("--solver"), std::string::npos) << unknown.output;
}

// The line-space update over frames (`--update verify`): every frame after the first is an update
// whose pairs all equal fresh estimates (else exit 3), reported with what it touched and its
// distance from a fresh build at the same pose; the light moves too in this scene.
TEST(Cli, RadiosityLineSpaceUpdateIsVerifiedAtEveryFrame) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-everything-moves.json";
  const std::string path = dir.path("verify.json");
  // DESIGN §6's form, without --solver: the line-space update is the Galerkin solver's.
  const RunResult r =
      runPenumbra("radiosity " + scene + " --update verify --tolerance 3e-3 --report " + path);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(path));
  EXPECT_EQ(report["method"], "galerkin");
  EXPECT_EQ(report["update"], "verify");
  ASSERT_EQ(report["frames"].size(), 4u);
  for (size_t f = 1; f < report["frames"].size(); ++f) {
    const nlohmann::json& frame = report["frames"][f];
    EXPECT_EQ(frame["moved_objects"], 3);
    EXPECT_FALSE(frame["update"]["rebuilt"].get<bool>());
    EXPECT_GT(frame["update"]["links_met"].get<long long>(), 0);
    for (const char* stage : {"repose", "traverse", "refine", "solve"})
      EXPECT_GE(frame["update"]["stage_seconds"][stage].get<double>(), 0) << stage;
    EXPECT_LT(frame["fresh"]["relative_l2_difference"].get<double>(), 0.02);
    EXPECT_GT(frame["fresh"]["active_links"].get<long long>(), 100);
    // The update ended with a pass that changed nothing, and verify checked one more.
    EXPECT_TRUE(frame["settled"].get<bool>());
    EXPECT_EQ(frame["pending_splits"], 0);
    EXPECT_EQ(frame["pending_clean_ups"], 0);
  }
  for (const std::string& wrong :
       {"radiosity " + scene + " --solver hierarchical --update linespace",  // it has none
        "radiosity " + scene + " --solver galerkin --update sideways",
        // a frame budget makes the hierarchy depend on the machine: not with verify
        "radiosity " + scene + " --solver galerkin --update verify --frame-budget 5"}) {
    const RunResult refused = runPenumbra(wrong);
    EXPECT_EQ(refused.exitCode, 1) << wrong << ": " << refused.output;
    EXPECT_NE(refused.output.find("--update"), std::string::npos) << refused.output;
  }
}

// Frame-rate control: with a budget smaller than any update, every update defers its splits and
// says so in the report.
TEST(Cli, RadiosityFrameBudgetDefersSplits) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-everything-moves.json";
  const std::string path = dir.path("budget.json");
  const RunResult r = runPenumbra("radiosity " + scene +
                                  " --solver galerkin --update linespace --tolerance 3e-3 "
                                  "--frame-budget 1e-6 --report " +
                                  path);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(path));
  for (size_t f = 1; f < report["frames"].size(); ++f) {
    const nlohmann::json& update = report["frames"][f]["update"];
    EXPECT_TRUE(update["over_budget"].get<bool>());
    EXPECT_GT(update["deferred_splits"].get<long long>(), 0);
    EXPECT_EQ(update["refined"], 0);
    EXPECT_FALSE(report["frames"][f]["settled"].get<bool>());
  }
}

// --shafts all|managed (DESIGN §6): the same solution, and each frame reports the shaft bytes
// held and what every pair's would take; managed holds fewer. Other values, and managed shafts
// for the solver without a line-space update, are usage errors.
TEST(Cli, RadiosityShaftPoliciesReportTheirBytes) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  nlohmann::json reports[2];
  const char* policies[2] = {"all", "managed"};
  for (int p = 0; p < 2; ++p) {
    const std::string path = dir.path(std::string(policies[p]) + ".json");
    const RunResult r = runPenumbra("radiosity " + scene +
                                    " --solver galerkin --update verify --tolerance 3e-3 "
                                    "--shafts " +
                                    policies[p] + " --report " + path);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    reports[p] = nlohmann::json::parse(std::ifstream(path));
    EXPECT_EQ(reports[p]["shaft_policy"], policies[p]);
  }
  ASSERT_EQ(reports[0]["frames"].size(), reports[1]["frames"].size());
  for (size_t f = 0; f < reports[0]["frames"].size(); ++f) {
    const nlohmann::json &all = reports[0]["frames"][f], &managed = reports[1]["frames"][f];
    EXPECT_EQ(all["active_links"], managed["active_links"]);
    EXPECT_EQ(all["absorbed_over_emitted"], managed["absorbed_over_emitted"]);
    EXPECT_EQ(all["all_shaft_bytes"], managed["all_shaft_bytes"]);
    EXPECT_GT(managed["all_shaft_bytes"].get<long long>(), 0);
    EXPECT_LT(managed["shaft_bytes"].get<long long>(), all["shaft_bytes"].get<long long>());
    if (f > 0) {
      EXPECT_TRUE(managed["update"]["shafts"].contains("made_on_the_fly"));
    }
  }
  for (const std::string& wrong :
       {"radiosity " + scene + " --solver galerkin --update linespace --shafts some",
        "radiosity " + scene + " --solver hierarchical --shafts managed"}) {
    const RunResult refused = runPenumbra(wrong);
    EXPECT_EQ(refused.exitCode, 1) << wrong << ": " << refused.output;
    EXPECT_NE(refused.output.find("--shafts"), std::string::npos) << refused.output;
  }
}

// Exit code 2 (bad input) from every verb that reads a scene, with a message naming the file:
// malformed JSON (file, line and column) and well-formed JSON that is not a valid scene (file and
// JSON pointer).
TEST(Cli, MalformedScenesAreBadInputForEveryVerb) {
  test::TempDir dir;
  const std::string points = dir.write("points.txt", "0 0 0 0 0 1\n");
  const std::string broken = dir.write("broken.json", "{ \"penumbra\": 1, ");
  const std::string unknownMaterial = dir.write("chalk.json", R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] } },
  "objects": [
    { "name": "floor", "material": "chalk", "polygons": [ [[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]] ] } ] })");
  const std::string png = dir.path("out.png");
  for (const auto& [scene, where] :
       {std::pair{broken, std::string("broken.json:1:")},
        std::pair{unknownMaterial, std::string("chalk.json: /objects/0/material")}}) {
    for (const std::string& verb :
         {"render " + scene + " --method raytrace --size 16x12 -o " + png,
          "render " + scene + " --method radiosity --tolerance 1e-2 --size 16x12 -o " + png,
          "render " + scene + " --method galerkin --tolerance 1e-2 --size 16x12 -o " + png,
          "shadows " + scene, "shadows " + scene + " --mode verify", "radiosity " + scene,
          "probe " + scene + " --points " + points,
          "probe " + scene + " --points " + points + " --method combined",
          "probe " + scene + " --points " + points + " --method galerkin"}) {
      const RunResult r = runPenumbra(verb);
      EXPECT_EQ(r.exitCode, 2) << verb << ": " << r.output;
      EXPECT_NE(r.output.find(where), std::string::npos) << verb << ": " << r.output;
    }
  }
  EXPECT_FALSE(std::ifstream(png).good()) << "no image from a bad scene";
}

// `generate` reads no input: its mistakes are usage (exit 1) and a scene it cannot write, which
// exits 2 as every write failure does (images, meshes, reports), naming the file and not claiming
// to have written it.
// Magnitudes the engines cannot represent (coordinates of 1e150 gave SIGFPE and SIGSEGV, a
// camera at 1e308 Embree's assertion) are refused on load, naming the object, keyframe or line:
// every pose stays within 1e9 of the origin and scales within 1e-6..1e6.
TEST(Cli, ExtremeMagnitudesAreRefusedNamingWhere) {
  test::TempDir dir;
  const std::string base = kScene;
  const auto variant = [&](const std::string& name, const std::string& from,
                           const std::string& to) {
    std::string text = base;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return dir.write(name, text);
  };
  const std::string huge = variant("huge.json", "[[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]]",
                                   "[[-5e150,-5e150,0],[5e150,-5e150,0],[5e150,5e150,0],[-5e150,"
                                   "5e150,0]]");
  const std::string far =
      variant("far.json", "\"translate\": [0, 0, -5]", "\"translate\": [0, 0, 1e308]");
  const std::string scaled =
      variant("scaled.json", "\"translate\": [0, 0, -5]", "\"scale\": [1e10, 1e10, 1e10]");
  for (const auto& [scene, where] : std::vector<std::pair<std::string, std::string>>{
           {huge, "huge.json: object 'floor'"},
           {far, "far.json: object 'blocker'"},
           {scaled, "scaled.json: object 'blocker' keyframe 1"}})
    for (const auto& [verb, options] : std::vector<std::pair<std::string, std::string>>{
             {"shadows ", " --mode full"},
             {"render ", " --method raytrace -o " + dir.path("x.png")}}) {
      const RunResult r = runPenumbra(verb + scene + options);
      EXPECT_EQ(r.exitCode, 2) << verb << scene << ": " << r.output;
      EXPECT_NE(r.output.find(where), std::string::npos) << r.output;
    }
  const std::string scene = dir.write("fine.json", base);
  const std::string points = dir.write("far.txt", "0 0 0 0 0 1\n1e308 0 0 0 0 1\n");
  const RunResult probe = runPenumbra("probe " + scene + " --points " + points);
  EXPECT_EQ(probe.exitCode, 2) << probe.output;
  EXPECT_NE(probe.output.find("far.txt:2"), std::string::npos) << probe.output;
}

// The discontinuity mesh works to 1e-12..1e-9 of the scene's size in its own coordinates: a scene
// lying farther from the origin than 32,768 times its size is refused by the commands that build
// it (exit 2, naming the file and the figures), and still rendered by the others. Here a room 10.8
// across (over both frames) moved 1e6 away: 9.3e4 times its size.
TEST(Cli, SceneTooFarForItsSizeIsRefusedByTheExactShadows) {
  test::TempDir dir;
  std::string text = kScene;
  for (const char* name : {"\"lamp\", ", "\"floor\", "}) {
    const size_t at = text.find(name);
    ASSERT_NE(at, std::string::npos);
    text.insert(at + std::string(name).size(), "\"transform\": { \"translate\": [1e6, 0, 0] }, ");
  }
  for (const char* key : {"{ \"frame\": 0 }", "\"translate\": [0, 0, -5]"}) {
    const size_t at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, std::string(key).size(),
                 key[0] == '{' ? "{ \"frame\": 0, \"translate\": [1e6, 0, 0] }"
                               : "\"translate\": [1e6, 0, -5]");
  }
  const std::string scene = dir.write("far-room.json", text);
  const std::string points = dir.write("p.txt", "1000000 0 0 0 0 1\n");
  for (const std::string& command :
       std::vector<std::string>{"shadows " + scene + " --mode full",
                                "probe " + scene + " --points " + points + " --method dm"}) {
    const RunResult r = runPenumbra(command);
    EXPECT_EQ(r.exitCode, 2) << command << ": " << r.output;
    EXPECT_NE(r.output.find("far-room.json: the scene lies too far from the origin"),
              std::string::npos)
        << r.output;
  }
  const RunResult reference =
      runPenumbra("probe " + scene + " --points " + points + " --method reference");
  EXPECT_EQ(reference.exitCode, 0) << reference.output;
}

// A report that cannot be written is a failure (exit 2) naming it, even a small one whose
// write error a buffered stream kept until after the check.
TEST(Cli, UnwritableReportFails) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string points = dir.write("p.txt", "0.1 0 0.45 0 1 0\n");
  const RunResult r = runPenumbra("probe " + scene + " --points " + points + " --report /dev/full");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("/dev/full"), std::string::npos) << r.output;
}

TEST(Cli, GenerateRefusesBadOptionsAndUnwritableOutputs) {
  test::TempDir dir;
  EXPECT_EQ(runPenumbra("generate --polygons 10 -o " + dir.path("small.json")).exitCode, 1);
  EXPECT_EQ(runPenumbra("generate --polygons 100 --frames 0 -o " + dir.path("f.json")).exitCode, 1);
  EXPECT_EQ(runPenumbra("generate --polygons 100").exitCode, 1);  // -o is required
  for (const std::string& out : {std::string("/dev/full"), dir.path("no/such/folder/g.json")}) {
    const RunResult r = test::runCommand(std::string(PENUMBRA_BINARY_DIR) +
                                         "/bin/penumbra generate --polygons 100 -o " + out);
    EXPECT_EQ(r.exitCode, 2) << out << ": " << r.output;  // as every write failure
    EXPECT_NE(r.output.find(out), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
  }
  const std::string good = dir.path("good.json");
  const RunResult r = runPenumbra("generate --polygons 100 --frames 3 -o " + good);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const RunResult info = runPenumbra("info --json " + good);
  EXPECT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("\"polygons\": 100"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("\"frames\": 3"), std::string::npos) << info.output;
}

// Points in the Cornell box for the end-to-end checks below: a grid over the floor (lit, in
// penumbrae, and under the blocks), two on the ceiling (no direct light), one on each side wall
// and one on the back wall.
std::string cornellPoints(const test::TempDir& dir) {
  std::string text;
  char line[96];
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      std::snprintf(line, sizeof line, "%.4f 0 %.4f 0 1 0\n", 0.06 + 0.1 * i + 0.003 * j,
                    0.06 + 0.1 * j + 0.002 * i);
      text += line;
    }
  text +=
      "0.1 0.5488 0.1 0 -1 0\n0.45 0.5488 0.5 0 -1 0\n0 0.3 0.3 1 0 0\n0.556 0.2 0.4 -1 0 0\n"
      "0.3 0.25 0.5592 0 0 -1\n";
  return dir.write("cornell-points.txt", text);
}

const std::vector<std::string> kProbeMethods = {"reference",
                                                "montecarlo",
                                                "dm",
                                                "radiosity --tolerance 1e-2",
                                                "combined --tolerance 1e-2",
                                                "galerkin --tolerance 1e-3"};

// Results do not depend on --threads: every method's CSV is the same byte for byte on one thread
// and on two (work is split by point, by wave of links and by receiver; seeds come from
// identities, never from the order in which threads finish).
TEST(Cli, ProbeResultsAreIdenticalAcrossThreads) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string points = cornellPoints(dir);
  for (const std::string& method : kProbeMethods) {
    for (const char* frame : {"0", "2"}) {
      const std::string arguments =
          "probe " + scene + " --points " + points + " --frame " + frame + " --method " + method;
      const RunResult one = runPenumbra("--threads 1 " + arguments);
      const RunResult two = runPenumbra("--threads 2 " + arguments);
      ASSERT_EQ(one.exitCode, 0) << arguments << ": " << one.output;
      ASSERT_EQ(two.exitCode, 0) << arguments << ": " << two.output;
      EXPECT_EQ(redColumn(one.output).size(), 30u) << arguments;
      EXPECT_EQ(one.output, two.output) << arguments;
    }
  }
}

// The irradiance columns of a probe CSV, every row: all finite and non-negative, and the count.
void expectFiniteNonNegativeCsv(const std::string& csv, size_t rows, const std::string& what) {
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "x,y,z,nx,ny,nz,r,g,b") << what;
  size_t count = 0;
  while (std::getline(lines, line)) {
    ++count;
    std::istringstream fields(line);
    std::string field;
    for (int column = 0; std::getline(fields, field, ','); ++column) {
      if (column < 6) continue;
      // strtod reads "nan" and "inf" (stod would throw on some spellings of them).
      const double value = std::strtod(field.c_str(), nullptr);
      EXPECT_TRUE(std::isfinite(value) && value >= 0) << what << ": " << line;
    }
  }
  EXPECT_EQ(count, rows) << what;
}

TEST(Cli, ProbesOfEveryMethodAreFiniteAndNonNegative) {
  test::TempDir dir;
  const std::string scene =
      std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json";
  const std::string points = cornellPoints(dir);
  for (const std::string& method : kProbeMethods) {
    for (const char* frame : {"0", "1", "2", "3"}) {
      const std::string arguments =
          "probe " + scene + " --points " + points + " --frame " + frame + " --method " + method;
      const RunResult r = runPenumbra(arguments);
      ASSERT_EQ(r.exitCode, 0) << arguments << ": " << r.output;
      expectFiniteNonNegativeCsv(r.output, 30, arguments);
    }
  }
}

// The vertices of a PLY file: irradiance_r/g/b (and x/y/z) of each, and whether every face's
// corners index existing vertices. Reads the header's properties, so either `format ascii` or
// `format binary_little_endian` with any property order and scalar types.
struct PlyMesh {
  std::vector<std::array<double, 3>> positions, irradiance;
  size_t faces = 0;
  bool facesIndexVertices = true;
  std::string error;  // non-empty when the file could not be read
};

PlyMesh readPly(const std::string& path) {
  PlyMesh mesh;
  std::ifstream in(path, std::ios::binary);
  std::string line, format;
  struct Property {
    std::string type, name, listCount;  // listCount: the count's type for a list property
  };
  struct Element {
    std::string name;
    size_t count = 0;
    std::vector<Property> properties;
  };
  std::vector<Element> elements;
  if (!std::getline(in, line) || line != "ply") {
    mesh.error = "not a PLY file";
    return mesh;
  }
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      Element e;
      words >> e.name >> e.count;
      elements.push_back(e);
    } else if (keyword == "property" && !elements.empty()) {
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.listCount >> p.type;
      words >> p.name;
      elements.back().properties.push_back(p);
    }
  }
  if (format != "ascii" && format != "binary_little_endian") {
    mesh.error = "format " + format;
    return mesh;
  }
  const bool ascii = format == "ascii";
  auto readScalar = [&](const std::string& type) -> double {
    if (ascii) {
      std::string word;
      in >> word;
      return std::strtod(word.c_str(), nullptr);
    }
    auto get = [&](auto value) {
      in.read(reinterpret_cast<char*>(&value), sizeof value);
      return double(value);
    };
    if (type == "float" || type == "float32") return get(float());
    if (type == "double" || type == "float64") return get(double());
    if (type == "uchar" || type == "uint8") return get(std::uint8_t());
    if (type == "char" || type == "int8") return get(std::int8_t());
    if (type == "ushort" || type == "uint16") return get(std::uint16_t());
    if (type == "short" || type == "int16") return get(std::int16_t());
    if (type == "uint" || type == "uint32") return get(std::uint32_t());
    if (type == "int" || type == "int32") return get(std::int32_t());
    mesh.error = "property type " + type;
    return 0;
  };
  for (const Element& e : elements) {
    for (size_t i = 0; i < e.count && mesh.error.empty() && in; ++i) {
      std::array<double, 3> position{}, irradiance{};
      for (const Property& p : e.properties) {
        if (!p.listCount.empty()) {
          const auto n = size_t(readScalar(p.listCount));
          for (size_t k = 0; k < n; ++k) {
            const double index = readScalar(p.type);
            if (e.name == "face" && !(index >= 0 && index < double(mesh.positions.size())))
              mesh.facesIndexVertices = false;
          }
          continue;
        }
        const double value = readScalar(p.type);
        const std::array<std::string, 3> axes = {"x", "y", "z"},
                                         channels = {"irradiance_r", "irradiance_g",
                                                     "irradiance_b"};
        for (int c = 0; c < 3; ++c) {
          if (p.name == axes[c]) position[c] = value;
          if (p.name == channels[c]) irradiance[c] = value;
        }
      }
      if (e.name == "vertex") {
        mesh.positions.push_back(position);
        mesh.irradiance.push_back(irradiance);
      } else if (e.name == "face") {
        ++mesh.faces;
      }
    }
  }
  if (!in && mesh.error.empty()) mesh.error = "file ends before its elements do";
  return mesh;
}

// NaN scan of the exact engine's output: `shadows --mode full --out DIR` over every frame of
// the bundled scenes, every vertex's irradiance finite and non-negative, every face on existing
// vertices. The furnished room (1,300 polygons) is left out: 20 s for its five frames in a
// release build on one core, several minutes under the sanitizers; the chair room stands for it.
//
// Non-negative, exactly: in umbrae Lambert's sum cancels to a few ulps of the light's unoccluded
// contribution, of either sign (before session 9 about 2% of the values were negative, the worst
// -9.98e-16 W/m^2); the engine sets what rounding leaves below zero to zero.
class BundledSceneMeshes : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledSceneMeshes, ShadowsMeshesAreFiniteAndNonNegative) {
  test::TempDir dir;
  const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + GetParam();
  const std::string meshes = dir.path("meshes");
  const RunResult r = runPenumbra("shadows " + scene + " --mode full --out " + meshes);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  int files = 0;
  size_t values = 0, negative = 0, lit = 0;
  double worst = 0;  // the most negative value over the brightest of its file
  for (const auto& entry : std::filesystem::directory_iterator(meshes)) {
    ++files;
    const std::string path = entry.path().string();
    const PlyMesh mesh = readPly(path);
    ASSERT_TRUE(mesh.error.empty()) << path << ": " << mesh.error;
    EXPECT_GT(mesh.faces, 0u) << path;
    EXPECT_TRUE(mesh.facesIndexVertices) << path;
    double brightest = 0;
    for (const auto& e : mesh.irradiance)
      for (double v : e) brightest = std::max(brightest, v);
    ASSERT_GT(brightest, 0) << path;
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const auto& p = mesh.positions[i];
      const auto& e = mesh.irradiance[i];
      EXPECT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
          << path << " vertex " << i;
      for (int c = 0; c < 3; ++c) {
        ++values;
        ASSERT_TRUE(std::isfinite(e[c]) && e[c] >= 0)
            << path << " vertex " << i << " at " << p[0] << " " << p[1] << " " << p[2]
            << " channel " << c << ": " << e[c] << " (brightest " << brightest << ")";
        if (e[c] < 0) ++negative;
        worst = std::min(worst, e[c] / brightest);
      }
      lit += e[0] + e[1] + e[2] > 0 ? 1 : 0;
    }
  }
  std::printf("[ info     ] %d meshes, %zu values, %zu negative, worst %.3g of the brightest\n",
              files, values, negative, worst);
  EXPECT_GE(files, 4);  // one per frame: the bundled motions have 4 frames or more
  EXPECT_GT(lit, values / 3 / 4) << "the meshes carry the light";
}

INSTANTIATE_TEST_SUITE_P(Scenes, BundledSceneMeshes,
                         ::testing::Values("cornell-box/cornell-box.json",
                                           "cornell-box/cornell-mirror.json",
                                           "office-desk/desk-145.json",
                                           "office-desk/desk-145-close.json",
                                           "office-desk/desk-307.json", "office-desk/desk-475.json",
                                           "chair-room/chair-room.json", "gltf/animated-box.gltf"),
                         test::sceneTestName);

}  // namespace
}  // namespace penumbra
