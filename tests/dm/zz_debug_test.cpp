#include <gtest/gtest.h>
#include <cstdio>
#include <cstdlib>
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/receiver_mesh.h"
#include "penumbra/scene/scene_loader.h"
using namespace penumbra;
static void printBp(const Backprojection& b) {
  for (auto& c : b.cycles) {
    std::printf("   cycle:");
    for (auto& v : c) std::printf(" [k%d l%d (%d,%d)(%d,%d)]", int(v.kind), v.lightFeature, v.first.polygon, v.first.corner, v.second.polygon, v.second.corner);
    std::printf("\n");
  }
}
TEST(ZzDebug, Desk307) {
  DiscontinuityMeshEngine engine;
  engine.build(loadScene(std::string(PENUMBRA_SOURCE_DIR) + std::getenv("ZZ_SCENE")), 0);
  const PosedScene& s = engine.posedScene();
  for (const WorldPolygon& r : s.polygons) {
    const ReceiverMesh* m = engine.meshOf(r.id);
    if (!m) continue;
    for (const MeshFace& f : m->faces()) {
      if (!engine.isUnresolved(r.id, f.index)) continue;
      std::printf("receiver %d face %d area %g sample %.9g %.9g %.9g n %g %g %g\n", r.id, f.index, f.area,
                  f.samplePoint.x, f.samplePoint.y, f.samplePoint.z, r.plane.normal.x, r.plane.normal.y, r.plane.normal.z);
      for (auto& b : engine.faceBackprojections(r.id, f.index)) printBp(b);
    }
  }
  auto pp = [&](int id) { const WorldPolygon& p = s.polygons[id]; std::printf("poly %d obj %d:", id, p.objectIndex); for (auto& v : p.vertices) std::printf(" (%.6g %.6g %.6g)", v.x, v.y, v.z); std::printf("\n"); };
  
  for (int id : s.lights) pp(id);
  if (std::getenv("ZZ_POLYS")) for (int id : {166, 199}) pp(id);
}
#include <chrono>
TEST(ZzDebug, Cost) {
  for (const char* name : {"/scenes/office-desk/desk-475.json", "/scenes/office-desk/desk-307.json", "/scenes/chair-room/chair-room.json", "/scenes/chair-room/furnished-room.json"}) {
    const Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) + name);
    for (int rep = 0; rep < 2; ++rep)
    for (bool on : {false, true}) {
      DmOptions o; o.coplanarEdgeCrossings = on;
      DiscontinuityMeshEngine engine(o);
      auto t = std::chrono::steady_clock::now();
      engine.build(scene, 0);
      double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
      const DmStats& s = engine.stats();
      std::printf("%s on=%d %.3f s faces %lld unresolved %lld fans %d vis %lld eee %.3f mesh %.3f verif %.3f cast %.3f\n", name, on, sec, s.meshFaces, s.unresolvedFaces, s.surfacesCoplanarEdgeCrossing, s.visibleSegments, s.secondsEee, s.secondsMeshing, s.secondsVerification, s.secondsCasting);
    }
  }
}
#include "penumbra/dm/backprojection.h"
#include "penumbra/lighting/exact_reference.h"
TEST(ZzDebug, Corners) {
  DiscontinuityMeshEngine engine;
  engine.build(loadScene(std::string(PENUMBRA_SOURCE_DIR) + std::getenv("ZZ_SCENE")), 0);
  const PosedScene& s = engine.posedScene();
  const UniformGrid grid(s);
  const ExactReference reference(s, &grid);
  BackprojectionBuilder builder(s, reference);
  for (const WorldPolygon& r : s.polygons) {
    const ReceiverMesh* m = engine.meshOf(r.id);
    if (!m) continue;
    for (const MeshFace& f : m->faces()) {
      if (!engine.isUnresolved(r.id, f.index)) continue;
      std::printf("receiver %d face %d sample %.9g %.9g %.9g\n", r.id, f.index, f.samplePoint.x, f.samplePoint.y, f.samplePoint.z);
      for (const Polygon3& cycle : m->faceBoundary(f.index))
        for (const Vec3& corner : cycle) {
          for (double inset : {1e-3, 1e-2, 1e-1}) {
            const Vec3 p = corner + (f.samplePoint - corner) * inset;
            const double expected = reference.irradiance(p, r.plane.normal, r.id).r;
            const double got = engine.faceIrradianceAt(r.id, f.index, p).r;
            std::printf(" corner %.9g %.9g %.9g inset %g: in face %d nearEEE %d ref %.12g face %.12g\n", corner.x, corner.y, corner.z, inset, m->locate(p) == f.index, engine.isNearEeePolyline(r.id, p), expected, got);
            if (std::abs(expected - got) > 1e-9 * std::max(1e-2, expected))
              for (PolygonId light : s.lights) printBp(builder.compute(light, p, r.plane.normal, r.id));
          }
        }
    }
  }
}
TEST(ZzDebug, Point) {
  DiscontinuityMeshEngine engine;
  engine.build(loadScene(std::getenv("ZZ_ABS")), 0);
  const PosedScene& s = engine.posedScene();
  Vec3 p; std::sscanf(std::getenv("ZZ_POINT"), "%lf %lf %lf", &p.x, &p.y, &p.z);
  const UniformGrid grid(s);
  const ExactReference reference(s, &grid);
  BackprojectionBuilder builder(s, reference);
  for (const WorldPolygon& r : s.polygons) {
    const ReceiverMesh* m = engine.meshOf(r.id);
    if (!m || std::abs(r.plane.signedDistance(p)) > (std::getenv("ZZ_TOL") ? std::atof(std::getenv("ZZ_TOL")) : 1e-12)) continue;
    auto f = m->locate(r.plane.project(p));
    if (!f) continue;
    std::printf("receiver %d face %d unresolved %d atpoint %d\n", r.id, *f, engine.isUnresolved(r.id, *f), engine.isAnsweredAtPoint(r.id, *f));
    const MeshFace& face = m->faces()[*f];
    std::printf(" sample %.17g %.17g %.17g area %g\n", face.samplePoint.x, face.samplePoint.y, face.samplePoint.z, face.area);
    for (auto& b : engine.faceBackprojections(r.id, *f)) printBp(b);
    for (const Polygon3& cycle : m->faceBoundary(*f)) { std::printf(" boundary:"); for (auto& c : cycle) std::printf(" (%.17g %.17g)", c.x, c.y); std::printf("\n"); }
    for (PolygonId light : s.lights) { std::printf(" at point:\n"); printBp(builder.compute(light, p, r.plane.normal, r.id)); }
    std::printf(" ref %.12g\n", reference.irradiance(p, r.plane.normal, r.id).r);
    for (auto& seg : engine.meshInputs(r.id)) std::printf(" seg s%d (%.17g %.17g)-(%.17g %.17g)\n", seg.surface, seg.p0.x, seg.p0.y, seg.p1.x, seg.p1.y);
  }
}
TEST(ZzDebug, Surfaces) {
  DiscontinuityMeshEngine engine;
  engine.build(loadScene(std::getenv("ZZ_ABS")), 0);
  const PosedScene& s = engine.posedScene();
  const EdgeAdjacency& adj = engine.adjacency();
  const int poly = std::atoi(std::getenv("ZZ_POLY")), corner = std::atoi(std::getenv("ZZ_CORNER"));
  const auto& vs = adj.polygonVertices(poly);
  const EdgeId e = adj.edgeBetween(vs[corner], vs[(corner + 1) % vs.size()]);
  std::printf("edge %d: (%.17g %.17g %.17g)-(%.17g %.17g %.17g) sil %d polys", e, adj.position(adj.edges()[e].a).x, adj.position(adj.edges()[e].a).y, adj.position(adj.edges()[e].a).z, adj.position(adj.edges()[e].b).x, adj.position(adj.edges()[e].b).y, adj.position(adj.edges()[e].b).z, adj.edges()[e].canBeSilhouette);
  for (auto p : adj.edges()[e].polygons) std::printf(" %d", p);
  std::printf("\n");
  for (const DiscontinuitySurface& d : engine.surfaces()) {
    if (d.occluderFeature != e || d.kind != SurfaceKind::kEmitterVertexOccluderEdge) continue;
    std::printf("surface %d kind %d lightFeature %d hinge (%.17g %.17g %.17g)-(%.17g %.17g %.17g)\n", d.id, int(d.kind), d.lightFeature, d.fan.hinge0.x, d.fan.hinge0.y, d.fan.hinge0.z, d.fan.hinge1.x, d.fan.hinge1.y, d.fan.hinge1.z);
    for (auto& x : d.intersections) std::printf("   cut poly %d (%.17g %.17g %.17g)-(%.17g %.17g %.17g)\n", x.polygon, x.p0.x, x.p0.y, x.p0.z, x.p1.x, x.p1.y, x.p1.z);
    for (const WorldPolygon& r : s.polygons) if (engine.meshOf(r.id)) for (auto& seg : engine.meshInputs(r.id)) if (seg.surface == d.id) std::printf("   seg on %d (%.17g %.17g)-(%.17g %.17g)\n", r.id, seg.p0.x, seg.p0.y, seg.p1.x, seg.p1.y);
  }
}
