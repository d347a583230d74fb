// The EV emitter surfaces, their casting through the grid and the visibility in their planes,
// checked against the exact reference: wherever a visible discontinuity segment lies on a
// receiver, the light feature that made it must sit exactly on the boundary of the light's visible
// part seen from there (a light vertex for light-vertex events, the projection of the occluder
// vertex onto the light edge for light-edge events).

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/dm/fan_visibility.h"
#include "penumbra/dm/surface_casting.h"
#include "penumbra/dm/surface_enumeration.h"
#include "penumbra/lighting/exact_reference.h"
#include "support/boxes.h"

namespace penumbra {
namespace {

// Does polygon q cross the open segment (a, b)? Plain floating point with a relative margin: an
// independent re-check of the definition, not of the sweep's arithmetic.
bool crossesSegment(const WorldPolygon& q, const Vec3& a, const Vec3& b, double margin) {
  const double da = q.plane.signedDistance(a), db = q.plane.signedDistance(b);
  if ((da > -margin && db > -margin) || (da < margin && db < margin)) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  const PlaneFrame frame = PlaneFrame::fromPlane(q.plane, q.vertices[0]);
  Polygon2 loop;
  for (const Vec3& v : q.vertices) loop.push_back(frame.toLocal(v));
  return containsPoint(loop, frame.toLocal(x));
}

test::SceneBuilder roomWithBoxes() {
  test::SceneBuilder b;
  b.addMaterial("lamp", {0, 0, 0}, {5, 5, 5}).addMaterial("white", {0.5, 0.5, 0.5});
  test::addRoom(b, "white", {-3, -3, 0}, {3, 3, 3});
  b.addPolygon("lamp", {{-0.4, -0.3, 2.9}, {-0.4, 0.3, 2.9}, {0.4, 0.3, 2.9}, {0.4, -0.3, 2.9}});
  test::addBox(b, "white", "floating", {-0.5, -0.4, 1.2}, {0.3, 0.2, 1.6});
  test::addBox(b, "white", "resting", {0.6, 0.5, 0.0}, {1.2, 1.1, 0.5});  // touches the floor
  return b;
}

// Every visible discontinuity segment satisfies the definition of its event, re-checked point by
// point independently of the sweep: the critical line through the point meets the light feature
// and the occluder feature, nothing crosses it between the light and the hinge, and nothing crosses
// it between the hinge and the receiver.
TEST(EmitterSurfaces, VisibleSegmentsSatisfyTheirEventDefinition) {
  const PosedScene scene = roomWithBoxes().pose();
  const EdgeAdjacency adjacency(scene);
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  ASSERT_EQ(scene.lights.size(), 1u);
  const PolygonId light = scene.lights[0];
  std::vector<DiscontinuitySurface> surfaces;
  enumerateEmitterEvSurfaces(scene, adjacency, light, surfaces);
  ASSERT_FALSE(surfaces.empty());
  const double size = scene.bounds.diagonalLength();
  int segments = 0, checked = 0;
  for (DiscontinuitySurface& surface : surfaces) {
    castSurface(surface, scene, grid);
    for (const SurfaceIntersection& r : surface.intersections) {
      // Stored intersections lie on their polygon's plane and on the fan's plane.
      EXPECT_LT(std::abs(scene.polygons[r.polygon].plane.signedDistance(r.p0)), 1e-9 * size);
      const Vec3 n = surface.fan.normal();
      EXPECT_LT(std::abs(dot(n, r.p1 - surface.fan.hinge0)), 1e-9 * size);
    }
    for (const DiscontinuitySegment& segment : visibleSegments(surface, scene.polygons)) {
      ++segments;
      const WorldPolygon& receiver = scene.polygons[segment.receiver];
      for (double t : {0.25, 0.5, 0.75}) {
        const Vec3 x = lerp(segment.p0, segment.p1, t);
        EXPECT_LT(std::abs(receiver.plane.signedDistance(x)), 1e-9 * size);
        const double u = surface.fan.criticalParameter(x);
        EXPECT_GE(u, -1e-9);
        EXPECT_LE(u, 1 + 1e-9);
        const Vec3 source = surface.fan.source(u), hinge = surface.fan.hinge(u);
        // x lies on the critical line through source and hinge, beyond the hinge.
        EXPECT_LT(length(cross(hinge - source, x - source)), 1e-9 * size * size) << x;
        EXPECT_GT(surface.fan.depthParameter(x, u), 1);
        for (const WorldPolygon& q : scene.polygons) {
          const bool isHinge = std::find(surface.hingePolygons.begin(), surface.hingePolygons.end(),
                                         q.id) != surface.hingePolygons.end();
          if (isHinge || q.id == light || q.id == receiver.id) continue;
          EXPECT_FALSE(crossesSegment(q, source, hinge, 1e-9 * size))
              << "polygon " << q.id << " blocks surface " << surface.id << " at " << x;
          EXPECT_FALSE(crossesSegment(q, hinge, x, 1e-9 * size))
              << "polygon " << q.id << " hides the receiver of surface " << surface.id << " at "
              << x;
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(segments, 20);
  std::printf("surfaces %zu, visible segments %d, points checked %d\n", surfaces.size(), segments,
              checked);
}

// Independent of the casting code: sample critical lines of every surface, find by plain
// segment-polygon tests where each pierces the scene's polygons, and require each such point to lie
// in a listed cell and on a stored intersection of that polygon.
TEST(EmitterSurfaces, CastingStoresEveryPolygonEveryCriticalLineMeets) {
  const PosedScene scene = roomWithBoxes().pose();
  const EdgeAdjacency adjacency(scene);
  const UniformGrid grid(scene, GridResolution{6, 6, 5});
  std::vector<DiscontinuitySurface> surfaces;
  enumerateEmitterEvSurfaces(scene, adjacency, scene.lights[0], surfaces);
  const double size = scene.bounds.diagonalLength();
  int pierces = 0;
  for (DiscontinuitySurface& surface : surfaces) {
    castSurface(surface, scene, grid);
    for (double u = 0.05; u < 1; u += 0.1) {
      const Vec3 from = surface.fan.source(u);
      const Vec3 direction = normalize(surface.fan.hinge(u) - from);
      const Vec3 to = from + direction * (2 * size);
      for (const WorldPolygon& q : scene.polygons) {
        // A line through the hinge only touches the hinge's own polygons there.
        const bool isHinge =
            std::count(surface.hingePolygons.begin(), surface.hingePolygons.end(), q.id) > 0;
        if (q.isLight || isHinge || !crossesSegment(q, from, to, 1e-9 * size)) continue;
        const double da = q.plane.signedDistance(from), db = q.plane.signedDistance(to);
        const Vec3 x = from + (to - from) * (da / (da - db));
        if (distance(x, surface.fan.hinge(u)) <= 1e-9 * size) continue;  // touches at the hinge
        ++pierces;
        Box3 at;
        at.extend(x);
        bool listed = false;
        for (int cell : grid.cellsOverlappingBox(at))
          listed = listed || std::binary_search(surface.cells.begin(), surface.cells.end(), cell);
        EXPECT_TRUE(listed) << "surface " << surface.id << " polygon " << q.id;
        bool stored = false;
        for (const SurfaceIntersection& r : surface.intersections) {
          if (r.polygon != q.id) continue;
          const Vec3 ab = r.p1 - r.p0;
          const double t = std::clamp(dot(x - r.p0, ab) / dot(ab, ab), 0.0, 1.0);
          stored = stored || distance(x, r.p0 + ab * t) <= 1e-9 * size;
        }
        EXPECT_TRUE(stored) << "surface " << surface.id << " u " << u << " polygon " << q.id;
      }
    }
  }
  EXPECT_GT(pierces, 1000);
}

}  // namespace
}  // namespace penumbra
