// The discontinuity-mesh engine against the exact reference (independent: polygon booleans of the
// light minus every occluder's projection, per point, no mesh): at random receiver points, the
// irradiance from the located face's backprojection equals the reference to 1e-9 relative.

#include "penumbra/dm/discontinuity_mesh_engine.h"

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/geometry/quaternion.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "support/boxes.h"

namespace penumbra {
namespace {

// A closed 4 x 4 x 3 room with a 1 x 1 light just below the ceiling.
test::SceneBuilder litRoom() {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5}).addMaterial("lamp", {0, 0, 0}, {10, 10, 10});
  test::addRoom(b, "white", {0, 0, 0}, {4, 4, 3});
  b.addPolygon("lamp", {{1.5, 1.5, 2.9}, {1.5, 2.5, 2.9}, {2.5, 2.5, 2.9}, {2.5, 1.5, 2.9}});
  return b;
}

struct Comparison {
  int points = 0, failures = 0;
  double worst = 0;
  std::string firstFailure;
};

Comparison compareWithReference(const PosedScene& scene, int count, std::uint64_t seed) {
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  Comparison c;
  for (const ReceiverPoint& q : sampleReceiverPoints(scene, count, seed)) {
    const Rgb expected = reference.irradiance(q.p, q.n, q.receiver);
    const std::optional<Rgb> got = engine.irradiance(q.p, q.n);
    ++c.points;
    // Relative to the value; in the umbra (0) relative to the light's exitance (10), times 1e-12.
    const double scale = std::max(1e-11, expected.maxComponent());
    const double error = got ? std::abs(got->r - expected.r) / scale : INFINITY;
    c.worst = std::max(c.worst, error);
    if (!(error <= 1e-9)) {
      if (c.failures++ == 0)
        c.firstFailure = "at (" + std::to_string(q.p.x) + ", " + std::to_string(q.p.y) + ", " +
                         std::to_string(q.p.z) + ") on polygon " + std::to_string(q.receiver) +
                         ": dm " + (got ? std::to_string(got->r) : "none") + ", reference " +
                         std::to_string(expected.r);
    }
  }
  return c;
}

void expectExact(const PosedScene& scene, int count, std::uint64_t seed) {
  const Comparison c = compareWithReference(scene, count, seed);
  EXPECT_EQ(c.failures, 0) << c.failures << " of " << c.points
                           << " points differ by more than 1e-9 (worst " << c.worst << "), first "
                           << c.firstFailure;
}

TEST(DiscontinuityMeshEngine, FloatingBoxIsExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "box", {1.6, 1.7, 1.2}, {2.3, 2.2, 1.6});
  expectExact(b.pose(), 1500, 1);
}

TEST(DiscontinuityMeshEngine, BoxRestingOnTheFloorIsExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "box", {1.2, 1.4, 0}, {2.1, 2.0, 0.8});
  expectExact(b.pose(), 1500, 2);
}

TEST(DiscontinuityMeshEngine, TiltedTriangleIsExact) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.3, 1.2, 1.0}, {2.6, 1.9, 1.5}, {1.9, 2.8, 1.2}});
  expectExact(b.pose(), 1500, 3);
}

TEST(DiscontinuityMeshEngine, RotatedBoxIsExact) {
  test::SceneBuilder b = litRoom();
  // A box turned about a tilted axis: no face parallel to the light or to the room.
  const Quaternion turn = Quaternion::fromAxisAngle(normalize(Vec3{1, 2, 0.5}), 0.7);
  for (Polygon3 face : test::boxFaces({-0.35, -0.25, -0.2}, {0.35, 0.25, 0.2})) {
    for (Vec3& v : face) v = turn.toMatrix() * v + Vec3{2.1, 1.9, 1.3};
    b.addPolygon("white", face, "box");
  }
  expectExact(b.pose(), 1500, 4);
}

TEST(DiscontinuityMeshEngine, TwoBoxesWithSeparateShadowsAreExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "near", {0.4, 0.5, 0.9}, {0.9, 1.0, 1.3});
  test::addBox(b, "white", "far", {3.0, 2.9, 0.9}, {3.5, 3.4, 1.5});
  expectExact(b.pose(), 1500, 5);
}

}  // namespace
}  // namespace penumbra
