// Where the discontinuity mesh is incomplete: for every face that face verification left
// unresolved (its labels just inside a corner differ from those at its sample), the labels that
// differ, and whether they matter there (the sample's labels evaluated at that corner point
// against the exact reference). A face whose differing labels give the reference's value is a
// false alarm (two names for one geometric feature, e.g. collinear edges of different polygons);
// the others are crossed by an event the mesh lacks, and the labels say which kind.
//
// Usage: dm_gaps SCENE.json [--slivers] [--faces N] [--edge K]... [--vertex V]... [--polygon P]...
//   --faces N     the first N unresolved faces in full (default 20), then counts by kind
//   --slivers     the slivers, by the kinds of surfaces on their edges
//   --edge K, --vertex V, --polygon P: scene edges, vertices (with their planar surfaces' visible
//                 pieces) and polygons
// Environment: NOVERIFY=1 builds without face verification (every face wrong at a corner is then
// listed with its labels); NEAR="P x y z r" lists the mesh edges of polygon P within r of a point.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/fan_visibility.h"
#include "penumbra/geometry/predicates.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/uniform_grid.h"

using namespace penumbra;

namespace {

using Label = std::array<int, 4>;  // kind, light feature, scene edge or vertex ids

const char* kindName(int kind) {
  switch (BackprojectionVertexKind(kind)) {
    case BackprojectionVertexKind::kLightVertex:
      return "light-vertex";
    case BackprojectionVertexKind::kLightEdgeHorizon:
      return "light-edge×horizon";
    case BackprojectionVertexKind::kLightEdgeOccluderEdge:
      return "light-edge×edge";
    case BackprojectionVertexKind::kOccluderVertex:
      return "vertex";
    case BackprojectionVertexKind::kOccluderEdgeOccluderEdge:
      return "edge×edge";
    case BackprojectionVertexKind::kOccluderEdgeHorizon:
      return "edge×horizon";
  }
  return "?";
}

std::vector<Label> labelSet(const Backprojection& bp, const EdgeAdjacency& adjacency) {
  const auto vertexOf = [&](const FeatureRef& f) {
    return adjacency.polygonVertices(f.polygon)[f.corner];
  };
  const auto edgeOf = [&](const FeatureRef& f) {
    const std::vector<VertexId>& corners = adjacency.polygonVertices(f.polygon);
    return adjacency.edgeBetween(corners[f.corner], corners[(f.corner + 1) % corners.size()]);
  };
  std::vector<Label> labels;
  for (const auto& cycle : bp.cycles)
    for (const BackprojectionVertex& v : cycle) {
      Label label{int(v.kind), v.lightFeature, -1, -1};
      if (v.kind == BackprojectionVertexKind::kOccluderVertex) label[2] = vertexOf(v.first);
      if (v.kind == BackprojectionVertexKind::kOccluderEdgeOccluderEdge) {
        label[2] = edgeOf(v.first);
        label[3] = edgeOf(v.second);
        if (label[3] < label[2]) std::swap(label[2], label[3]);
      }
      if (v.kind == BackprojectionVertexKind::kLightEdgeOccluderEdge ||
          v.kind == BackprojectionVertexKind::kOccluderEdgeHorizon)
        label[2] = edgeOf(v.first);
      labels.push_back(label);
    }
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  return labels;
}

std::string describe(const std::vector<Label>& labels) {
  std::string out;
  char buffer[96];
  for (const Label& l : labels) {
    const bool onLight = l[0] == int(BackprojectionVertexKind::kLightVertex) ||
                         l[0] == int(BackprojectionVertexKind::kLightEdgeOccluderEdge) ||
                         l[0] == int(BackprojectionVertexKind::kLightEdgeHorizon);
    std::snprintf(buffer, sizeof buffer, " %s", kindName(l[0]));
    out.append(buffer);
    if (onLight) {
      std::snprintf(buffer, sizeof buffer, "(L%d)", l[1]);
      out.append(buffer);
    }
    if (l[3] >= 0)
      std::snprintf(buffer, sizeof buffer, "[%d,%d]", l[2], l[3]);
    else if (l[2] >= 0)
      std::snprintf(buffer, sizeof buffer, "[%d]", l[2]);
    else
      buffer[0] = 0;
    out.append(buffer);
  }
  return out;
}

// The kinds of the labels that differ, as one key ("+edge×edge -light-edge×edge", sorted).
std::string differenceKey(const std::vector<Label>& onlySample,
                          const std::vector<Label>& onlyHere) {
  std::vector<std::string> parts;
  for (const Label& l : onlySample) parts.push_back(std::string(1, '-').append(kindName(l[0])));
  for (const Label& l : onlyHere) parts.push_back(std::string(1, '+').append(kindName(l[0])));
  std::sort(parts.begin(), parts.end());
  std::string key;
  for (const std::string& p : parts) {
    if (!key.empty()) key.push_back(' ');
    key.append(p);
  }
  return key;
}

}  // namespace

static int benchMain(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: dm_gaps SCENE.json [--faces N]\n");
    return 1;
  }
  int listed = 20;
  bool slivers = false;
  std::vector<int> edgesToShow, verticesToShow, polygonsToShow, surfacesToShow;
  for (int i = 2; i + 1 < argc; ++i) {
    if (!std::strcmp(argv[i], "--faces")) listed = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--slivers")) slivers = true;
    if (!std::strcmp(argv[i], "--edge")) edgesToShow.push_back(std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "--vertex")) verticesToShow.push_back(std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "--polygon")) polygonsToShow.push_back(std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "--surface")) surfacesToShow.push_back(std::atoi(argv[i + 1]));
  }
  const Scene scene = loadScene(argv[1]);
  // NOVERIFY=1: every face answers from its labels, and the check of resolved faces below then
  // lists every face wrong at a corner.
  DiscontinuityMeshEngine engine({.verifyFaces = std::getenv("NOVERIFY") == nullptr});
  engine.build(scene, 0);
  const PosedScene& posed = engine.posedScene();
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  const BackprojectionBuilder builder(posed, reference);
  const EdgeAdjacency& adjacency = engine.adjacency();

  for (int e : edgesToShow) {
    const SceneEdge& edge = adjacency.edges()[e];
    const Vec3 a = adjacency.position(edge.a), b = adjacency.position(edge.b);
    std::printf("edge %d: (%.6f %.6f %.6f) - (%.6f %.6f %.6f), silhouette-capable %d, polygons", e,
                a.x, a.y, a.z, b.x, b.y, b.z, int(edge.canBeSilhouette));
    for (PolygonId p : edge.polygons) std::printf(" %d", p);
    std::printf("\n");
    for (const DiscontinuitySurface& surface : engine.surfaces()) {
      if (surface.kind != SurfaceKind::kEmitterVertexOccluderEdge || surface.occluderFeature != e)
        continue;
      std::printf("  surface %d (light vertex %d): %zu stored intersections\n", surface.id,
                  surface.lightFeature, surface.intersections.size());
      for (const DiscontinuitySegment& piece :
           visibleSegments(surface, engine.posedScene().polygons))
        std::printf("    on %d: (%.6f %.6f %.6f) - (%.6f %.6f %.6f)\n", piece.receiver, piece.p0.x,
                    piece.p0.y, piece.p0.z, piece.p1.x, piece.p1.y, piece.p1.z);
    }
  }
  for (int id : surfacesToShow) {
    const DiscontinuitySurface& surface = engine.surfaces()[id];
    const CriticalFan& f = surface.fan;
    std::printf(
        "surface %d kind %d: source (%.6f %.6f %.6f)-(%.6f %.6f %.6f) hinge (%.6f %.6f "
        "%.6f)-(%.6f %.6f %.6f), hinge polygons",
        id, int(surface.kind), f.source0.x, f.source0.y, f.source0.z, f.source1.x, f.source1.y,
        f.source1.z, f.hinge0.x, f.hinge0.y, f.hinge0.z, f.hinge1.x, f.hinge1.y, f.hinge1.z);
    for (PolygonId p : surface.hingePolygons) std::printf(" %d", p);
    std::printf("\n");
    for (const SurfaceIntersection& cut : surface.intersections)
      std::printf("  cut by %d: (%.6f %.6f %.6f) u %.6f s %.6f - (%.6f %.6f %.6f) u %.6f s %.6f\n",
                  cut.polygon, cut.p0.x, cut.p0.y, cut.p0.z, f.criticalParameter(cut.p0),
                  f.depthParameter(cut.p0, f.criticalParameter(cut.p0)), cut.p1.x, cut.p1.y,
                  cut.p1.z, f.criticalParameter(cut.p1),
                  f.depthParameter(cut.p1, f.criticalParameter(cut.p1)));
  }
  for (int id : polygonsToShow) {
    std::printf("polygon %d:", id);
    for (const Vec3& v : posed.polygons[id].vertices)
      std::printf(" (%.6f %.6f %.6f)", v.x, v.y, v.z);
    std::printf("\n");
  }
  for (int v : verticesToShow) {
    const Vec3 x = adjacency.vertices()[v].position;
    std::printf("vertex %d: (%.6f %.6f %.6f), polygons", v, x.x, x.y, x.z);
    for (PolygonId p : adjacency.vertices()[v].polygons) std::printf(" %d", p);
    std::printf("\n");
    // Its planar surfaces (EV with the vertex as hinge) and their visible pieces.
    for (const DiscontinuitySurface& surface : engine.surfaces()) {
      const bool isHinge = (surface.kind == SurfaceKind::kEmitterEdgeOccluderVertex ||
                            surface.kind == SurfaceKind::kNonEmitterVertexEdge ||
                            surface.kind == SurfaceKind::kOccluderPlaneOccluderVertex) &&
                           surface.occluderFeature == v;
      if (!isHinge) continue;
      std::printf("  surface %d kind %d light feature %d second %d: %zu stored intersections\n",
                  surface.id, int(surface.kind), surface.lightFeature, surface.secondFeature,
                  surface.intersections.size());
      for (const DiscontinuitySegment& piece :
           visibleSegments(surface, engine.posedScene().polygons))
        std::printf("    on %d: (%.6f %.6f %.6f) - (%.6f %.6f %.6f)\n", piece.receiver, piece.p0.x,
                    piece.p0.y, piece.p0.z, piece.p1.x, piece.p1.y, piece.p1.z);
    }
  }
  if (const char* near = std::getenv("NEAR")) {
    // Mesh edges of polygon P within R of (x, y, z): "P x y z R".
    int polygon = 0;
    double x = 0, y = 0, z = 0, r = 0;
    std::sscanf(near, "%d %lf %lf %lf %lf", &polygon, &x, &y, &z, &r);
    const Vec3 c{x, y, z};
    for (const auto& [segment, surfaces] : engine.meshOf(polygon)->edges()) {
      const auto [a, b] = segment;
      const Vec3 ab = b - a;
      const double t = std::clamp(dot(c - a, ab) / dot(ab, ab), 0.0, 1.0);
      if (distance(a + ab * t, c) > r) continue;
      std::printf("edge (%.9f %.9f %.9f) - (%.9f %.9f %.9f):", a.x, a.y, a.z, b.x, b.y, b.z);
      for (SurfaceId s : surfaces) std::printf(" %d", s);
      std::printf("\n");
    }
  }
  if (slivers) {
    // Which events bound the slivers: the kinds of the surfaces on their edges.
    const auto kindOf = [&](SurfaceId id) -> std::string {
      if (id >= 0 && id < SurfaceId(engine.surfaces().size()))
        return "planar" + std::to_string(int(engine.surfaces()[id].kind));
      if (id >= 0) return "eee";
      if (id == ReceiverMesh::kBoundary) return "outline";
      if (id == ReceiverMesh::kTile) return "tile";
      const int k = ReceiverMesh::kBoundary - 1 - id, n = int(posed.polygons.size());
      return k < n ? "contact" : k < 2 * n ? "light-plane" : "horizon";
    };
    std::map<std::string, int> byKinds;
    int count = 0;
    for (const WorldPolygon& receiver : posed.polygons) {
      const ReceiverMesh* mesh = engine.meshOf(receiver.id);
      if (!mesh) continue;
      std::map<int, std::vector<std::string>> kinds;
      for (const FaceCrossing& c : mesh->faceCrossings())
        for (int f : {c.face, c.other})
          if (engine.isAnsweredAtPoint(receiver.id, f) && !engine.isUnresolved(receiver.id, f))
            for (SurfaceId id : c.surfaces) kinds[f].push_back(kindOf(id));
      for (auto& [f, names] : kinds) {
        std::sort(names.begin(), names.end());
        names.erase(std::unique(names.begin(), names.end()), names.end());
        std::string key;
        for (const std::string& name : names) key += name + " ";
        ++byKinds[key];
        ++count;
      }
    }
    std::printf("%d slivers by the kinds of surfaces on their edges:\n", count);
    for (const auto& [key, n] : byKinds) std::printf("  %6d  %s\n", n, key.c_str());
  }
  std::map<std::string, int> realByKind, aliasByKind;
  int unresolved = 0, real = 0, alias = 0, shown = 0, verifiedWrong = 0, shownWrong = 0;
  for (const WorldPolygon& receiver : posed.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    const Vec3& n = receiver.plane.normal;
    for (const MeshFace& face : mesh->faces()) {
      if (!engine.isAnsweredAtPoint(receiver.id, face.index)) {
        // A face verification passed: are its labels right at every corner all the same?
        const std::vector<Backprojection>& perLight =
            engine.faceBackprojections(receiver.id, face.index);
        for (const Polygon3& cycle : mesh->faceBoundary(face.index))
          for (const Vec3& corner : cycle) {
            const Vec3 p = corner + (face.samplePoint - corner) *
                                        DiscontinuityMeshEngine::kCornerInsets.front();
            if (mesh->locate(p) != face.index || engine.isNearEeePolyline(receiver.id, p)) continue;
            const Rgb expected = reference.irradiance(p, n, receiver.id);
            const Rgb got = builder.irradiance(perLight, p, n, receiver.id);
            if (std::abs(got.r - expected.r) <= 1e-9 * std::max(1e-2, expected.r)) continue;
            ++verifiedWrong;
            if (shownWrong < listed)
              for (size_t l = 0; l < posed.lights.size(); ++l) {
                const Backprojection here = builder.compute(posed.lights[l], p, n, receiver.id);
                const std::vector<Label> a = labelSet(perLight[l], adjacency),
                                         b = labelSet(here, adjacency);
                std::vector<Label> onlySample, onlyHere;
                std::set_difference(a.begin(), a.end(), b.begin(), b.end(),
                                    std::back_inserter(onlySample));
                std::set_difference(b.begin(), b.end(), a.begin(), a.end(),
                                    std::back_inserter(onlyHere));
                std::printf("  light %zu: sample only%s; corner only%s\n", l,
                            describe(onlySample).c_str(), describe(onlyHere).c_str());
              }
            bool labelled = true;
            for (const Backprojection& bp : perLight) labelled = labelled && bp.isLabelled;
            if (shownWrong++ < listed)
              std::printf(
                  "receiver %d face %d at (%.6f %.6f %.6f) area %.3g VERIFIED BUT WRONG "
                  "(labelled %d): labels at the corner give %.9g, reference %.9g\n",
                  receiver.id, face.index, p.x, p.y, p.z, face.area, int(labelled), got.r,
                  expected.r);
            goto nextFace;
          }
      nextFace:
        continue;
      }
      if (!engine.isUnresolved(receiver.id, face.index)) continue;  // a sliver
      ++unresolved;
      const std::vector<Backprojection>& perLight =
          engine.faceBackprojections(receiver.id, face.index);
      bool found = false;
      for (const Polygon3& cycle : mesh->faceBoundary(face.index)) {
        for (const Vec3& corner : cycle) {
          const Vec3 p =
              corner + (face.samplePoint - corner) * DiscontinuityMeshEngine::kCornerInsets.front();
          if (mesh->locate(p) != face.index) continue;
          for (size_t l = 0; l < posed.lights.size() && !found; ++l) {
            const Backprojection& atSample = perLight[l];
            if (!atSample.isLabelled) continue;
            const Backprojection here = builder.compute(posed.lights[l], p, n, receiver.id);
            if (!here.isLabelled) continue;
            const std::vector<Label> a = labelSet(atSample, adjacency),
                                     b = labelSet(here, adjacency);
            if (a == b) continue;
            found = true;
            std::vector<Label> onlySample, onlyHere;
            std::set_difference(a.begin(), a.end(), b.begin(), b.end(),
                                std::back_inserter(onlySample));
            std::set_difference(b.begin(), b.end(), a.begin(), a.end(),
                                std::back_inserter(onlyHere));
            // Does the sample's labelling still give the right light at the corner point?
            const Rgb expected = reference.irradiance(p, n, receiver.id);
            const Rgb got = builder.irradiance({atSample}, p, n, receiver.id);
            const double scale = std::max(1e-11, expected.maxComponent());
            const bool matters = std::abs(got.r - expected.r) / scale > 1e-9;
            const std::string key = differenceKey(onlySample, onlyHere);
            (matters ? realByKind : aliasByKind)[key]++;
            (matters ? real : alias)++;
            // Three edges only crossing one another: an EEE of three occluder edges. Was it
            // enumerated (then its tracing missed the visible stretch)?
            std::vector<int> crossed;
            bool onlyCrossings = true;
            for (const auto* side : {&onlySample, &onlyHere})
              for (const Label& label : *side) {
                onlyCrossings =
                    onlyCrossings &&
                    label[0] == int(BackprojectionVertexKind::kOccluderEdgeOccluderEdge);
                crossed.push_back(label[2]);
                crossed.push_back(label[3]);
              }
            std::sort(crossed.begin(), crossed.end());
            crossed.erase(std::unique(crossed.begin(), crossed.end()), crossed.end());
            std::string triple;
            if (onlyCrossings && crossed.size() == 3) {
              triple = " (three-edge EEE not enumerated)";
              for (const EeeSurface& e : engine.eeeSurfaces()) {
                std::vector<int> edges{e.first, e.second, e.third};
                std::sort(edges.begin(), edges.end());
                if (e.kind == EeeKind::kOccluderEdges && edges == crossed)
                  triple = " (three-edge EEE enumerated)";
              }
            }
            // A crossing of two edges traded for their crossings with one light edge: the
            // light-edge EEE of those three. Was it enumerated?
            if (onlySample.size() + onlyHere.size() == 3) {
              const std::vector<Label>& one = onlySample.size() == 1 ? onlySample : onlyHere;
              const std::vector<Label>& two = onlySample.size() == 1 ? onlyHere : onlySample;
              const auto lightCrossing = int(BackprojectionVertexKind::kLightEdgeOccluderEdge);
              if (one.size() == 1 &&
                  one[0][0] == int(BackprojectionVertexKind::kOccluderEdgeOccluderEdge) &&
                  two[0][0] == lightCrossing && two[1][0] == lightCrossing &&
                  two[0][1] == two[1][1]) {
                triple = " (light-edge EEE not enumerated)";
                for (const EeeSurface& e : engine.eeeSurfaces())
                  if (e.kind == EeeKind::kLightEdge && e.lightEdge == two[0][1] &&
                      std::min(e.first, e.second) == one[0][2] &&
                      std::max(e.first, e.second) == one[0][3])
                    triple = " (light-edge EEE enumerated)";
                realByKind[key + triple]++;
                realByKind[key]--;
              }
            }
            // One occluder edge named on each side only, the two coplanar: the swap where the
            // point crosses the plane of two coplanar edges of different polygons (their
            // projections line up there), an event the engine builds only for one polygon's plane.
            const auto edgesOf = [](const std::vector<Label>& labels) {
              std::vector<int> out;
              for (const Label& label : labels) {
                const auto kind = BackprojectionVertexKind(label[0]);
                if (kind == BackprojectionVertexKind::kLightEdgeOccluderEdge ||
                    kind == BackprojectionVertexKind::kOccluderEdgeHorizon)
                  out.push_back(label[2]);
                if (kind == BackprojectionVertexKind::kOccluderEdgeOccluderEdge) {
                  out.push_back(label[2]);
                  out.push_back(label[3]);
                }
              }
              std::sort(out.begin(), out.end());
              out.erase(std::unique(out.begin(), out.end()), out.end());
              return out;
            };
            const std::vector<int> inSample = edgesOf(onlySample), inCorner = edgesOf(onlyHere);
            std::vector<int> lost, gained;
            std::set_difference(inSample.begin(), inSample.end(), inCorner.begin(), inCorner.end(),
                                std::back_inserter(lost));
            std::set_difference(inCorner.begin(), inCorner.end(), inSample.begin(), inSample.end(),
                                std::back_inserter(gained));
            if (matters && lost.size() == 1 && gained.size() == 1) {
              const SceneEdge &a = adjacency.edges()[lost[0]], &b = adjacency.edges()[gained[0]];
              const bool sharesVertex = a.a == b.a || a.a == b.b || a.b == b.a || a.b == b.b;
              if (!sharesVertex &&
                  orientation3d(adjacency.position(a.a), adjacency.position(a.b),
                                adjacency.position(b.a), adjacency.position(b.b)) == Sign::kZero) {
                realByKind[key]--;
                realByKind[key + "  [coplanar edges swap]"]++;
                triple = " (coplanar edges swap)";
              }
            }
            if (shown++ < listed)
              std::printf(
                  "receiver %d face %d at (%.6f %.6f %.6f) area %.3g %s: sample only%s; "
                  "corner only%s; sample labels at the corner give %.9g, reference "
                  "%.9g%s\n",
                  receiver.id, face.index, p.x, p.y, p.z, face.area,
                  matters ? "MISSING EVENT" : "alias", describe(onlySample).c_str(),
                  describe(onlyHere).c_str(), got.r, expected.r, triple.c_str());
          }
          if (found) break;
        }
        if (found) break;
      }
    }
  }
  std::printf(
      "\n%d unresolved faces: %d with a missing event (the sample's labels wrong at a "
      "corner), %d false alarms (differing labels, same light)\n",
      unresolved, real, alias);
  std::printf("%d faces verification passed (or slivers aside) are wrong at a corner\n",
              verifiedWrong);
  std::printf(
      "missing events by labels that differ (- at the sample only, + at the corner only):\n");
  for (const auto& [key, count] : realByKind)
    if (count > 0) std::printf("  %5d  %s\n", count, key.c_str());
  std::printf("false alarms by labels that differ:\n");
  for (const auto& [key, count] : aliasByKind) std::printf("  %5d  %s\n", count, key.c_str());
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("dm_gaps", argc, argv, benchMain);
}
