// End-to-end tests of the `penumbra` executable: the contract of DESIGN.md §6 (CSV format, exit
// codes, messages naming files and lines).

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include "support/temp_dir.h"

namespace penumbra {
namespace {

struct RunResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr
};

RunResult runPenumbra(const std::string& arguments) {
  const std::string command =
      std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra --quiet " + arguments + " 2>&1";
  RunResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
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

}  // namespace
}  // namespace penumbra
