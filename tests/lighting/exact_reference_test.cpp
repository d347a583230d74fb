#include "penumbra/lighting/exact_reference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "penumbra/lighting/form_factor.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/uniform_grid.h"
#include "support/boxes.h"
#include "support/scene_builder.h"

namespace penumbra {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

double parallelCornerFormFactor(double a, double b, double c) {
  const double ac = std::hypot(a, c), bc = std::hypot(b, c);
  return (a / ac * std::atan(b / ac) + b / bc * std::atan(a / bc)) / kTwoPi;
}
// Form factor from the origin (normal +z) to the axis-aligned rectangle [x0,x1]x[y0,y1] at height
// c, by inclusion-exclusion of corner rectangles (valid for any signs of the bounds).
double parallelRectangleFormFactor(double x0, double x1, double y0, double y1, double c) {
  const auto corner = [c](double x, double y) {
    const double sx = x < 0 ? -1 : 1, sy = y < 0 ? -1 : 1;
    return sx * sy * parallelCornerFormFactor(std::abs(x), std::abs(y), c);
  };
  return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

// A unit-exitance square light [-1,1]^2 at height 2 facing down, over a floor at z = 0.
test::SceneBuilder lightOverFloor() {
  test::SceneBuilder b;
  b.addMaterial("lamp", {0, 0, 0}, {1, 1, 1});
  b.addMaterial("white", {0.5, 0.5, 0.5});
  b.addPolygon("lamp", {{-1, -1, 2}, {-1, 1, 2}, {1, 1, 2}, {1, -1, 2}});
  b.addPolygon("white", {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}});
  return b;
}

// lightOverFloor with 40 small tilted triangles scattered between floor and light (drawn from rng).
PosedScene lightOverScatteredTriangles(std::mt19937_64& rng) {
  test::SceneBuilder b = lightOverFloor();
  std::uniform_real_distribution<double> u(-3, 3), h(0.2, 1.8), s(0.05, 0.4);
  for (int i = 0; i < 40; ++i) {
    const double x = u(rng), y = u(rng), z = h(rng), r = s(rng);
    b.addPolygon("white", {{x - r, y - r, z}, {x + r, y - r, z + 0.1}, {x, y + r, z}});
  }
  return b.pose();
}

TEST(ExactReference, UnoccludedMatchesClosedForm) {
  const PosedScene scene = lightOverFloor().pose();
  const ExactReference reference(scene);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{u(rng), u(rng), 0};
    const double expected = parallelRectangleFormFactor(-1 - p.x, 1 - p.x, -1 - p.y, 1 - p.y, 2);
    EXPECT_NEAR(reference.irradiance(p, {0, 0, 1}).r, expected, 1e-13);
  }
}

TEST(ExactReference, ParallelOccluderHidesItsProjection) {
  // An occluder at height 1 covering x in [0, 3]: from the origin it hides the light where x > 0
  // (central projection doubles distances at height 2), leaving the light's half x in [-1, 0].
  test::SceneBuilder b = lightOverFloor();
  b.addPolygon("white", {{0, -3, 1}, {3, -3, 1}, {3, 3, 1}, {0, 3, 1}});
  const PosedScene scene = b.pose();
  const ExactReference reference(scene);
  const double expected = parallelRectangleFormFactor(-1, 0, -1, 1, 2);
  EXPECT_NEAR(reference.irradiance({0, 0, 0}, {0, 0, 1}).r, expected, 1e-14);
  // From (-0.25, 0, 0) the occluder edge projects to x = 0.25.
  const double shifted = parallelRectangleFormFactor(-1 + 0.25, 0.25 + 0.25, -1, 1, 2);
  EXPECT_NEAR(reference.irradiance({-0.25, 0, 0}, {0, 0, 1}).r, shifted, 1e-14);
}

TEST(ExactReference, HoleInTheVisibleLight) {
  // A small square occluder [-0.1, 0.1]^2 at height 1 hides [-0.2, 0.2]^2 of the light from the
  // origin: the visible region is a ring, whose form factor is outer minus inner.
  test::SceneBuilder b = lightOverFloor();
  b.addPolygon("white", {{-0.1, -0.1, 1}, {0.1, -0.1, 1}, {0.1, 0.1, 1}, {-0.1, 0.1, 1}});
  const PosedScene scene = b.pose();
  const ExactReference reference(scene);
  const double expected = parallelRectangleFormFactor(-1, 1, -1, 1, 2) -
                          parallelRectangleFormFactor(-0.2, 0.2, -0.2, 0.2, 2);
  EXPECT_NEAR(reference.irradiance({0, 0, 0}, {0, 0, 1}).r, expected, 1e-14);
  const VisibleLight visible = reference.visibleLight({0, 0, 0}, {0, 0, 1}, 0);
  EXPECT_EQ(visible.rings.size(), 2u);
}

TEST(ExactReference, UmbraAndBackFacingGiveZero) {
  test::SceneBuilder b = lightOverFloor();
  b.addPolygon("white", {{-3, -3, 1}, {3, -3, 1}, {3, 3, 1}, {-3, 3, 1}});
  const PosedScene scene = b.pose();
  const ExactReference reference(scene);
  EXPECT_EQ(reference.irradiance({0, 0, 0}, {0, 0, 1}).r, 0.0);
  // A point above the light sees its back: nothing.
  const PosedScene openScene = lightOverFloor().pose();
  const ExactReference open(openScene);
  EXPECT_EQ(open.irradiance({0, 0, 3}, {0, 0, -1}).r, 0.0);
  // A receiver facing away from the light gets nothing.
  EXPECT_EQ(open.irradiance({0, 0, 0}, {0, 0, -1}).r, 0.0);
}

TEST(ExactReference, ClosedSolidIsOpaqueWhateverItsFacesOrientation) {
  // A closed box: its top face is seen from the front, its bottom face from the back. Their
  // projections have opposite orientations and must not cancel in the union. The box covers the
  // light's projection [-2,2]^2 at height 1..1.5 from the origin (it needs [-1,1]^2 at z = 1).
  test::SceneBuilder b = lightOverFloor();
  const double x0 = -1.2, x1 = 1.2, z0 = 1.0, z1 = 1.5;
  for (const Polygon3& f :
       std::vector<Polygon3>{{{x0, x0, z0}, {x0, x1, z0}, {x1, x1, z0}, {x1, x0, z0}},
                             {{x0, x0, z1}, {x1, x0, z1}, {x1, x1, z1}, {x0, x1, z1}}})
    b.addPolygon("white", f, "box");
  const PosedScene scene = b.pose();
  const ExactReference reference(scene);
  EXPECT_EQ(reference.irradiance({0, 0, 0}, {0, 0, 1}).r, 0.0);
  // Half-covered from the side: the box's edge x = 1.2 at height 1.5 projects from (2, 0, 0) to
  // x = 2 - 0.8·(2/1.5) ≈ 0.933; at height 1 to x = 0.4, so the top edge bounds the visible part.
  const double edge = 2 - 0.8 * 2 / 1.5;
  const Vec3 p{2, 0, 0};
  EXPECT_NEAR(reference.irradiance(p, {0, 0, 1}).r,
              parallelRectangleFormFactor(edge - 2, 1 - 2, -1, 1, 2), 1e-14);
}

TEST(ExactReference, TiltedReceiverClipsTheLight) {
  // A receiver whose tangent plane x = 0 cuts the light in half sees only the half x > 0.
  const PosedScene scene = lightOverFloor().pose();
  const ExactReference reference(scene);
  const Vec3 p{0, 0, 0.5};
  const Vec3 n{1, 0, 0};
  const Polygon3 half{{0, -1, 2}, {0, 1, 2}, {1, 1, 2}, {1, -1, 2}};
  EXPECT_NEAR(reference.irradiance(p, n).r, pointToPolygonFormFactor(p, n, half), 1e-15);
}

TEST(ExactReference, GridAndBruteForceAgree) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  const PosedScene scene = lightOverScatteredTriangles(rng);
  const UniformGrid grid(scene);
  const ExactReference withGrid(scene, &grid), bruteForce(scene);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{u(rng), u(rng), 0};
    EXPECT_EQ(withGrid.irradiance(p, {0, 0, 1}).r, bruteForce.irradiance(p, {0, 0, 1}).r);
  }
}

// mayOcclude's contract (what the discontinuity mesh's update relies on to keep a face): a
// polygon inside a box for which it says no never enters visibleLight's boolean operation. Checked
// with each polygon's own bounds at random floor points; the run must see both answers, and
// polygons that do occlude.
TEST(ExactReference, MayOccludeIsFalseOnlyForPolygonsTheLightNeverConsiders) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-3, 3);
  const PosedScene scene = lightOverScatteredTriangles(rng);
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const PolygonId light = scene.lights[0];
  int excluded = 0, admitted = 0, occluding = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 p{u(rng), u(rng), 0};
    const VisibleLight visible = reference.visibleLight(p, {0, 0, 1}, light);
    for (const WorldPolygon& q : scene.polygons) {
      if (q.id == light) continue;
      const bool may = reference.mayOcclude(p, {0, 0, 1}, light, std::span(&q.bounds, 1));
      const bool entered = std::find(visible.occluders.begin(), visible.occluders.end(), q.id) !=
                           visible.occluders.end();
      EXPECT_TRUE(may || !entered) << "polygon " << q.id << " at (" << p.x << ", " << p.y << ")";
      excluded += may ? 0 : 1;
      admitted += may ? 1 : 0;
      occluding += entered ? 1 : 0;
    }
  }
  EXPECT_GT(excluded, 1000);
  EXPECT_GT(admitted, 100);
  EXPECT_GT(occluding, 100);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// Lambert's sum over an umbra's sliver cancels to a few ulps of either sign; the reference reports
// what rounding leaves below zero as zero (no engine prints a negative irradiance), and anything
// further below would still show. Over the chair room's receivers, uniform and at the points
// where occluder vertices' shadows land (umbra boundaries), every channel is 0 or more; without
// that rule some of them came out near -1e-15 (this test then fails).
TEST(ExactReference, NeverBelowZero) {
  const Scene scene =
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/chair-room/chair-room.json");
  const PosedScene posed = poseAt(scene, 0);
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  std::vector<ReceiverPoint> points = sampleReceiverPoints(posed, 4000, 3);
  for (const WorldPolygon& r : posed.polygons)
    if (!r.isLight && r.area > 0.5) {  // the large receivers: floor, walls, table tops
      const std::vector<ReceiverPoint> shadows =
          vertexShadowPoints(posed, r.id, 1e-9 * posed.extent.diagonalLength());
      points.insert(points.end(), shadows.begin(), shadows.end());
    }
  int zero = 0;
  for (const ReceiverPoint& q : points) {
    const Rgb e = reference.irradiance(q.p, q.n, q.receiver);
    ASSERT_TRUE(e.r >= 0 && e.g >= 0 && e.b >= 0)
        << q.p.x << " " << q.p.y << " " << q.p.z << ": " << e.r << " " << e.g << " " << e.b;
    zero += e.r == 0 ? 1 : 0;
  }
  EXPECT_GT(points.size(), 10000u);
  EXPECT_GT(zero, 100);  // umbrae are probed
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// The faces of an axis-aligned box, counter-clockwise seen from outside (or from inside).
std::vector<Polygon3> boxFaces(const Vec3& lo, const Vec3& hi, bool inward = false) {
  std::vector<Polygon3> faces = test::boxFaces(lo, hi);
  if (inward)
    for (Polygon3& f : faces) std::reverse(f.begin(), f.end());
  return faces;
}

// An L-shaped prism (not convex) between heights z0 and z1, its corner at (x, y).
std::vector<Polygon3> lPrismFaces(double x, double y, double z0, double z1) {
  const std::vector<Vec2> l{
      {x, y},      {x + 0.8, y}, {x + 0.8, y + 0.3}, {x + 0.3, y + 0.3}, {x + 0.3, y + 0.8},
      {x, y + 0.8}};
  Polygon3 bottom, top;
  for (const Vec2& q : l) top.push_back({q.x, q.y, z1});
  for (auto it = l.rbegin(); it != l.rend(); ++it) bottom.push_back({it->x, it->y, z0});
  std::vector<Polygon3> faces{bottom, top};
  for (size_t i = 0; i < l.size(); ++i) {
    const Vec2& a = l[i];
    const Vec2& b = l[(i + 1) % l.size()];
    faces.push_back({{a.x, a.y, z0}, {b.x, b.y, z0}, {b.x, b.y, z1}, {a.x, a.y, z1}});
  }
  return faces;
}

// Closed surfaces of every kind the culling meets, under the light of lightOverFloor: boxes
// floating, standing on the floor, stacked face to face, turned inside out, one crossing the
// light's plane beside it, a tilted box, an L-shaped prism and a two-sided card. (Boxes stacked
// corner to corner would share edges four ways: open, and kept whole.)
test::SceneBuilder closedSolidsUnderTheLight() {
  test::SceneBuilder b = lightOverFloor();
  const auto add = [&](const std::vector<Polygon3>& faces, const std::string& object) {
    for (const Polygon3& f : faces) b.addPolygon("white", f, object);
  };
  add(boxFaces({0.5, -0.3, 0.6}, {1.0, 0.2, 0.9}), "floating");
  add(boxFaces({-2, -0.5, 0}, {-1.2, 0.5, 0.7}), "standing");
  add(boxFaces({0.2, -1.5, 0}, {0.6, -1.1, 0.3}), "stack");
  add(boxFaces({0.3, -1.4, 0.3}, {0.5, -1.2, 0.5}), "stack");
  add(boxFaces({-0.6, 0.8, 1.0}, {-0.2, 1.2, 1.3}, true), "inside-out");
  add(boxFaces({2.5, -0.2, 1.5}, {3.0, 0.2, 2.5}), "through-the-light-plane");
  add(lPrismFaces(1.2, 1.1, 0.3, 0.5), "l-prism");
  // A box turned 30 degrees about z and tilted about x.
  std::vector<Polygon3> tilted = boxFaces({-0.25, -0.15, -0.1}, {0.25, 0.15, 0.1});
  const double c = std::cos(0.52), s = std::sin(0.52), ct = std::cos(0.3), st = std::sin(0.3);
  for (Polygon3& f : tilted)
    for (Vec3& v : f) {
      const Vec3 r{c * v.x - s * v.y, s * v.x + c * v.y, v.z};
      v = Vec3{r.x, ct * r.y - st * r.z, st * r.y + ct * r.z} + Vec3{-1.0, -1.6, 0.8};
    }
  add(tilted, "tilted");
  const Polygon3 card{{1.5, -1.5, 1.1}, {2.1, -1.2, 1.3}, {1.6, -0.8, 1.2}};
  add({card, Polygon3(card.rbegin(), card.rend())}, "two-sided-card");
  return b;
}

// ClosedObjectFaces::kFacingThePoint leaves out about half the polygons of closed surfaces; the
// light they let through must be none. Against the oracle's kAll, at random floor points, at
// points on the floor's lines where boxes' side planes cross it (there the side is edge-on and
// skipped, and which faces face the point is decided by its neighbours), at the contact lines
// of the boxes standing on the floor, and on the boxes' own faces.
TEST(ExactReference, ClosedSurfacesFacingThePointHideWhatTheyWholeHide) {
  const PosedScene scene = closedSolidsUnderTheLight().pose();
  for (const WorldPolygon& q : scene.polygons)
    if (q.objectIndex >= 2) {
      ASSERT_GE(q.closedSurface, 0) << "polygon " << q.id;
    }
  const UniformGrid grid(scene);
  const ExactReference all(scene, &grid), facing(scene, &grid, ClosedObjectFaces::kFacingThePoint);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-3.5, 3.5);
  std::vector<std::pair<Vec3, Vec3>> points;  // point, normal
  const Vec3 up{0, 0, 1}, tilted = normalize(Vec3{1, -0.5, 1});
  for (int i = 0; i < 400; ++i) points.push_back({{u(rng), u(rng), 0}, i % 4 ? up : tilted});
  for (double side : {0.5, 1.0, -2.0, -1.2, 0.2, 0.6, 0.3, -0.6, -0.2, 2.5, 3.0, 1.2, 1.5, 2.0})
    for (int i = 0; i < 20; ++i) {
      points.push_back({{side, u(rng), 0}, up});
      points.push_back({{u(rng), side, 0}, up});
    }
  for (int i = 0; i <= 20; ++i) {  // along and just beside the standing box's foot
    const double t = -0.5 + i * 0.05;
    for (double off : {0.0, 1e-12, 1e-9, 1e-6})
      points.push_back({{-2 - off, t, 0}, up}), points.push_back({{-1.2 + off, t, 0}, up}),
          points.push_back({{-2 + 0.04 * i, -0.5 - off, 0}, up});
  }
  int culledSomewhere = 0;
  for (const auto& [p, n] : points) {
    const Rgb a = all.irradiance(p, n), f = facing.irradiance(p, n);
    EXPECT_NEAR(f.r, a.r, 1e-12) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
    const PolygonId light = scene.lights[0];
    culledSomewhere += facing.visibleLight(p, n, light).occluders.size() <
                               all.visibleLight(p, n, light).occluders.size()
                           ? 1
                           : 0;
  }
  // On the boxes' faces: the receiver's own surface contains the point and is kept whole.
  for (const WorldPolygon& q : scene.polygons) {
    if (q.objectIndex < 2 || q.plane.normal.z < 0.5) continue;
    const Vec3 p = centroid(q.vertices);
    EXPECT_NEAR(facing.irradiance(p, q.plane.normal, q.id).r,
                all.irradiance(p, q.plane.normal, q.id).r, 1e-12)
        << "on polygon " << q.id;
  }
  EXPECT_GT(culledSomewhere, 200);
}

}  // namespace
}  // namespace penumbra
