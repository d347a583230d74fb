// Light-plane events against hand-derived geometry: where a (tilted) light's plane crosses a
// receiver, the event is the receiver's part of the line both planes share — its ends on the
// receiver's boundary, every point on both planes.

#include "penumbra/dm/receiver_plane_events.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

WorldPolygon polygonOf(const Polygon3& vertices, PolygonId id) {
  WorldPolygon p;
  p.id = id;
  p.vertices = vertices;
  p.plane = supportingPlane(vertices);
  p.area = area(vertices);
  p.bounds = boundingBox(vertices);
  return p;
}

// A unit-ish square light centred at `centre`, facing `normal`.
WorldPolygon lightFacing(const Vec3& centre, const Vec3& normal) {
  const Vec3 n = normalize(normal);
  const Vec3 u = normalize(std::abs(n.x) < 0.9 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
  const Vec3 v = cross(n, u);
  // Counter-clockwise about n: u, v, −u, −v corners.
  return polygonOf({centre + (u + v) * 0.3, centre + (v - u) * 0.3, centre - (u + v) * 0.3,
                    centre + (u - v) * 0.3},
                   1);
}

// The wall x = 1, y in [0, 3], z in [0, 4], facing −x (into a room at x < 1).
WorldPolygon wall() {
  return polygonOf({{1, 0, 0}, {1, 0, 4}, {1, 3, 4}, {1, 3, 0}}, 0);
}

TEST(LightPlaneSegments, HorizontalLightCutsTheWallAlongItsHeight) {
  const WorldPolygon light = lightFacing({0.5, 1.5, 2}, {0, 0, -1});  // the plane z = 2
  const auto segments = lightPlaneSegments(wall(), light, 7);
  ASSERT_EQ(segments.size(), 1u);
  const DiscontinuitySegment& s = segments[0];
  EXPECT_EQ(s.surface, 7);
  EXPECT_EQ(s.receiver, 0);
  // From (1, 0, 2) to (1, 3, 2), in either direction.
  const Vec3 low = s.p0.y < s.p1.y ? s.p0 : s.p1, high = s.p0.y < s.p1.y ? s.p1 : s.p0;
  EXPECT_NEAR(distance(low, Vec3{1, 0, 2}), 0, 1e-12);
  EXPECT_NEAR(distance(high, Vec3{1, 3, 2}), 0, 1e-12);
}

TEST(LightPlaneSegments, TiltedLightsCutTheWallOnBothPlanesFromEdgeToEdge) {
  const WorldPolygon receiver = wall();
  int cut = 0;
  for (double tilt : {0.1, 0.4, 0.9, 1.3})
    for (double turn : {0.0, 0.7, 2.0, 3.5}) {
      // Normal tilted by `tilt` from straight down, turned by `turn` about the vertical.
      const Vec3 normal{std::sin(tilt) * std::cos(turn), std::sin(tilt) * std::sin(turn),
                        -std::cos(tilt)};
      const WorldPolygon light = lightFacing({0.4, 1.5, 2.2}, normal);
      const auto segments = lightPlaneSegments(receiver, light, 3);
      // Where the plane meets the wall's rectangle, by hand: on x = 1 the plane reads
      // ny y + nz z = d − nx, a line in (y, z), clipped to [0, 3] x [0, 4].
      const Plane& p = light.plane;
      const double rhs = p.offset - p.normal.x;
      std::vector<Vec3> ends;
      for (double y : {0.0, 3.0})
        if (std::abs(p.normal.z) > 1e-12) {
          const double z = (rhs - p.normal.y * y) / p.normal.z;
          if (z >= 0 && z <= 4) ends.push_back({1, y, z});
        }
      for (double z : {0.0, 4.0})
        if (std::abs(p.normal.y) > 1e-12) {
          const double y = (rhs - p.normal.z * z) / p.normal.y;
          if (y > 0 && y < 3) ends.push_back({1, y, z});
        }
      if (ends.size() < 2) {
        EXPECT_TRUE(segments.empty()) << tilt << " " << turn;
        continue;
      }
      ASSERT_EQ(segments.size(), 1u) << tilt << " " << turn;
      ++cut;
      const DiscontinuitySegment& s = segments[0];
      for (const Vec3& e : {s.p0, s.p1}) {
        EXPECT_NEAR(receiver.plane.signedDistance(e), 0, 1e-12);
        EXPECT_NEAR(p.signedDistance(e), 0, 1e-12);
      }
      const bool direct = distance(s.p0, ends[0]) < distance(s.p0, ends[1]);
      EXPECT_NEAR(distance(direct ? s.p0 : s.p1, ends[0]), 0, 1e-12) << tilt << " " << turn;
      EXPECT_NEAR(distance(direct ? s.p1 : s.p0, ends[1]), 0, 1e-12) << tilt << " " << turn;
    }
  EXPECT_GE(cut, 12);
}

TEST(LightPlaneSegments, ParallelOrMissingPlanesGiveNothing) {
  // A light facing the wall (parallel planes), and a light plane that passes above the wall.
  EXPECT_TRUE(lightPlaneSegments(wall(), lightFacing({0.5, 1.5, 2}, {1, 0, 0}), 0).empty());
  EXPECT_TRUE(lightPlaneSegments(wall(), lightFacing({0.5, 1.5, 9}, {0, 0, -1}), 0).empty());
}

}  // namespace
}  // namespace penumbra
