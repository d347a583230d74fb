// The probe points reader (src/app/cli/points_file.h; compiled into this test from the CLI's
// sources): normals of extreme magnitudes are normalised exactly enough, or refused naming the
// line. Found by fuzz/points_file_fuzzer (fuzz/README.md).

#include "points_file.h"

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/base/input_error.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

// A unit vector computed in double precision is within a few ulps of length 1.
constexpr double kUnitTolerance = 1e-15;

TEST(PointsFile, TinyAndHugeNormalsComeOutUnit) {
  test::TempDir dir;
  const auto points = cli::readPointsFile(dir.write(
      "points.txt", "0 0 0 1e-160 0 0\n0 0 0 1e300 1e300 0\n0 0 0 0 1e-300 0\n0 0 0 -3 4 0\n"));
  ASSERT_EQ(points.size(), 4u);
  const Vec3 expected[] = {
      {1, 0, 0}, {std::sqrt(0.5), std::sqrt(0.5), 0}, {0, 1, 0}, {-0.6, 0.8, 0}};
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(length(points[i].normal), 1, kUnitTolerance) << "line " << points[i].line;
    EXPECT_NEAR(distance(points[i].normal, expected[i]), 0, kUnitTolerance)
        << "line " << points[i].line;
  }
  // The raw normal is echoed as written.
  EXPECT_EQ(points[1].rawNormal, (Vec3{1e300, 1e300, 0}));
}

TEST(PointsFile, ZeroNormalNamesTheLine) {
  test::TempDir dir;
  const std::string path = dir.write("points.txt", "# header\n0 0 0 1 0 0\n1 1 1 0 -0 0\n");
  try {
    cli::readPointsFile(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path + ":3");
    EXPECT_NE(e.problem().find("zero vector"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra
