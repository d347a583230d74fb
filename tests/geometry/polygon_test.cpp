#include "penumbra/geometry/polygon.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

const Polygon3 kUnitSquare{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
// An L shape (non-convex), area 3.
const Polygon3 kLShape{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};

TEST(Polygon, NormalAreaCentroid) {
  EXPECT_EQ(newellNormal(kUnitSquare), (Vec3{0, 0, 2}));
  EXPECT_DOUBLE_EQ(area(kLShape), 3.0);
  const Vec3 c = centroid(kLShape);  // union of three unit squares at (.5,.5),(1.5,.5),(.5,1.5)
  EXPECT_NEAR(c.x, 2.5 / 3, 1e-15);
  EXPECT_NEAR(c.y, 2.5 / 3, 1e-15);
  const Plane plane = supportingPlane(kUnitSquare);
  EXPECT_EQ(plane.normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(plane.offset, 0.0);
}

TEST(Polygon, ClipByPlaneKeepsFrontPart) {
  const Plane halfX = Plane::fromPointNormal({0.25, 0, 0}, {1, 0, 0});
  const Polygon3 clipped = clipByPlane(kUnitSquare, halfX);
  EXPECT_DOUBLE_EQ(area(clipped), 0.75);
  // Non-convex: clipping the L at x >= 0.5 leaves 2 - 0.5 + 0.5 ... = area of x in [0.5, 2].
  const Polygon3 clippedL = clipByPlane(kLShape, Plane::fromPointNormal({0.5, 0, 0}, {1, 0, 0}));
  EXPECT_DOUBLE_EQ(area(clippedL), 3.0 - 1.0);
  EXPECT_TRUE(clipByPlane(kUnitSquare, Plane::fromPointNormal({2, 0, 0}, {1, 0, 0})).empty());
}

TEST(Polygon, PlaneFrameIsRightHanded) {
  for (const Vec3& n : {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{0, -1, 0}, normalize(Vec3{1, 2, 3})}) {
    const PlaneFrame f = PlaneFrame::fromPlane(Plane::fromPointNormal({1, 2, 3}, n), {1, 2, 3});
    EXPECT_NEAR(dot(cross(f.u, f.v), f.n), 1.0, 1e-15);
    const Vec3 p{4, -2, 7};
    const Vec3 back = f.toWorld(f.toLocal(p));
    // Round trip is exact for points on the plane only; project first.
    const Vec3 onPlane = Plane::fromPointNormal({1, 2, 3}, n).project(p);
    EXPECT_NEAR(distance(f.toWorld(f.toLocal(onPlane)), onPlane), 0, 1e-13);
    (void)back;
  }
}

TEST(PolygonDefect, AcceptsGoodPolygons) {
  EXPECT_FALSE(findPolygonDefect(kUnitSquare));
  EXPECT_FALSE(findPolygonDefect(kLShape));
}

TEST(PolygonDefect, RejectsEachDefect) {
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}})->find("fewer than 3"), std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 0}})->find("fewer than 3"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}})->find("zero area"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}})->find("non-planar"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}})->find("self-inter"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {std::nan(""), 0, 0}, {0, 1, 0}})->find("NaN"),
            std::string::npos);
}

TEST(Polygon2, ContainsAndSignedArea) {
  const Polygon2 square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(signedArea(square), 1.0);
  EXPECT_TRUE(containsPoint(square, {0.5, 0.5}));
  EXPECT_FALSE(containsPoint(square, {1.5, 0.5}));
}

}  // namespace
}  // namespace penumbra
