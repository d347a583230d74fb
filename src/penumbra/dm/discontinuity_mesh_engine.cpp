#include "penumbra/dm/discontinuity_mesh_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "penumbra/dm/fan_visibility.h"
#include "penumbra/dm/receiver_plane_events.h"
#include "penumbra/dm/surface_casting.h"
#include "penumbra/dm/surface_enumeration.h"
#include "penumbra/spatial/receiver_locator.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Surface ids of the segments that no discontinuity surface makes: below the receiver boundary's
// id, contact lines of polygon p, then light planes, then horizons (receiver_plane_events.h).
SurfaceId contactSurface(PolygonId p) {
  return ReceiverMesh::kBoundary - 1 - p;
}
SurfaceId lightPlaneSurface(const PosedScene& scene, PolygonId light) {
  return ReceiverMesh::kBoundary - 1 - SurfaceId(scene.polygons.size()) - light;
}
SurfaceId horizonSurface(const PosedScene& scene, PolygonId light) {
  return ReceiverMesh::kBoundary - 1 - 2 * SurfaceId(scene.polygons.size()) - light;
}

// Edges of other polygons lying in the receiver's plane and touching it: contact lines (D0
// discontinuities), e.g. the footprint of a box resting on the floor.
std::vector<DiscontinuitySegment> contactSegments(const PosedScene& scene, const UniformGrid& grid,
                                                  const WorldPolygon& receiver) {
  std::vector<DiscontinuitySegment> out;
  const double tolerance = 1e-9 * scene.bounds.diagonalLength();
  for (PolygonId id : grid.polygonsInBox(receiver.bounds.expanded(tolerance))) {
    if (id == receiver.id) continue;
    const WorldPolygon& other = scene.polygons[id];
    bool coplanar = true;
    for (const Vec3& v : other.vertices)
      coplanar = coplanar && std::abs(receiver.plane.signedDistance(v)) <= tolerance;
    if (!coplanar) continue;
    for (size_t i = 0; i < other.vertices.size(); ++i)
      out.push_back({contactSurface(id), receiver.id, other.vertices[i],
                     other.vertices[(i + 1) % other.vertices.size()], 0, 0});
  }
  return out;
}

// Segments computed by different surfaces that should meet at one point (where two events cross
// on the receiver) come out of floating-point constructions a few ulps apart, and a gap would merge
// two faces. Extending every segment a little at both ends turns near-misses into crossings: the
// mesh may gain tiny faces (over-refinement, harmless: each gets its own backprojection) but never
// loses one (Drettakis & Fiume's robustness rule).
DiscontinuitySegment extended(DiscontinuitySegment s, double atStart, double atEnd) {
  const Vec3 d = s.p1 - s.p0;
  const double len = length(d);
  if (len == 0) return s;
  s.p0 = s.p0 - d * (atStart / len);
  s.p1 = s.p1 + d * (atEnd / len);
  return s;
}

}  // namespace

DiscontinuityMeshEngine::DiscontinuityMeshEngine(DmOptions options) : options_(options) {}
DiscontinuityMeshEngine::~DiscontinuityMeshEngine() = default;

void DiscontinuityMeshEngine::build(const Scene& scene, int frame) {
  build(poseAt(scene, frame));
}

void DiscontinuityMeshEngine::build(PosedScene posed) {
  stats_ = {};
  receivers_.clear();
  surfaces_.clear();
  posed_ = std::make_unique<PosedScene>(std::move(posed));
  const PosedScene& scene = *posed_;
  grid_ = std::make_unique<UniformGrid>(scene);
  reference_ = std::make_unique<ExactReference>(scene, grid_.get());
  adjacency_ = std::make_unique<EdgeAdjacency>(scene);
  backprojections_ = std::make_unique<BackprojectionBuilder>(scene, *grid_, *reference_);
  stats_.lights = int(scene.lights.size());
  stats_.gridBytes = grid_->memoryBytes();

  auto start = Clock::now();
  for (PolygonId light : scene.lights) {
    std::vector<DiscontinuitySurface> surfaces =
        enumerateEmitterEvSurfaces(scene, *adjacency_, light, SurfaceId(surfaces_.size()));
    for (DiscontinuitySurface& s : surfaces) surfaces_.push_back(std::move(s));
    surfaces = enumerateNonEmitterEvSurfaces(scene, *adjacency_, *grid_, light,
                                             SurfaceId(surfaces_.size()));
    for (DiscontinuitySurface& s : surfaces) surfaces_.push_back(std::move(s));
    surfaces = enumerateOccluderPlaneSurfaces(scene, *adjacency_, *grid_, light,
                                              SurfaceId(surfaces_.size()));
    for (DiscontinuitySurface& s : surfaces) surfaces_.push_back(std::move(s));
  }
  for (const DiscontinuitySurface& s : surfaces_) {
    switch (s.kind) {
      case SurfaceKind::kEmitterVertexOccluderEdge:
        ++stats_.surfacesEmitterVertex;
        break;
      case SurfaceKind::kEmitterEdgeOccluderVertex:
        ++stats_.surfacesEmitterEdge;
        break;
      case SurfaceKind::kNonEmitterVertexEdge:
        ++stats_.surfacesNonEmitter;
        break;
      case SurfaceKind::kLightEdgeOccluderPlane:
        ++stats_.surfacesOccluderPlane;
        break;
      case SurfaceKind::kOccluderPlaneOccluderEdge:
        ++stats_.surfacesOccluderPlaneEdge;
        break;
    }
  }
  stats_.secondsSurfaces = secondsSince(start);

  start = Clock::now();
  for (DiscontinuitySurface& s : surfaces_) {
    castSurface(s, scene, *grid_);
    stats_.storedIntersections += (long long)s.intersections.size();
    stats_.surfaceCellBytes += s.cells.capacity() * sizeof(int);
    stats_.intersectionBytes += s.intersections.capacity() * sizeof(SurfaceIntersection);
  }
  stats_.secondsCasting = secondsSince(start);

  start = Clock::now();
  std::map<PolygonId, std::vector<DiscontinuitySegment>> perReceiver;
  for (const DiscontinuitySurface& s : surfaces_)
    for (DiscontinuitySegment& segment : visibleSegments(s)) {
      ++stats_.visibleSegments;
      perReceiver[segment.receiver].push_back(std::move(segment));
    }
  stats_.secondsVisibility = secondsSince(start);

  start = Clock::now();
  eeeSurfaces_.clear();
  const double chord = kEeeChordTolerance * scene.bounds.diagonalLength();
  std::map<PolygonId, std::vector<std::pair<Vec3, Vec3>>> eeeOnReceiver;
  for (PolygonId light : options_.eeeSurfaces ? scene.lights : std::vector<PolygonId>{}) {
    const SurfaceId firstId = SurfaceId(surfaces_.size() + eeeSurfaces_.size());
    for (EeeSurface& s : enumerateEeeSurfaces(scene, *adjacency_, surfaces_, light, firstId))
      eeeSurfaces_.push_back(std::move(s));
  }
  for (EeeSurface& s : eeeSurfaces_) {
    for (DiscontinuitySegment& segment : traceEeeSurface(s, scene, *adjacency_, *grid_, chord)) {
      ++stats_.eeeSegments;
      eeeOnReceiver[segment.receiver].push_back({segment.p0, segment.p1});
      perReceiver[segment.receiver].push_back(std::move(segment));
    }
    stats_.surfaceCellBytes += s.cells.capacity() * sizeof(int);
    stats_.eeeSurfacesTruncated += s.truncated ? 1 : 0;
  }
  stats_.surfacesEee = int(eeeSurfaces_.size());
  stats_.secondsEee = secondsSince(start);

  start = Clock::now();
  for (const WorldPolygon& receiver : scene.polygons) {
    if (receiver.isLight) continue;
    ReceiverData data{
        ReceiverMesh(receiver), {}, SegmentProximity(std::move(eeeOnReceiver[receiver.id]))};
    std::vector<DiscontinuitySegment> segments;
    // Segments end where events meet, computed apart: extend their ends (see extended()). The
    // joints inside an EEE polyline are shared exactly by consecutive pieces and stay as they are.
    std::map<std::pair<SurfaceId, std::array<double, 3>>, int> ends;
    const auto endKey = [](const DiscontinuitySegment& s, const Vec3& p) {
      return std::pair{s.surface, std::array<double, 3>{p.x, p.y, p.z}};
    };
    for (const DiscontinuitySegment& segment : perReceiver[receiver.id]) {
      ++ends[endKey(segment, segment.p0)];
      ++ends[endKey(segment, segment.p1)];
    }
    const double by = kSegmentExtension * scene.bounds.diagonalLength();
    for (const DiscontinuitySegment& segment : perReceiver[receiver.id]) {
      const bool open0 = ends[endKey(segment, segment.p0)] == 1;
      const bool open1 = ends[endKey(segment, segment.p1)] == 1;
      segments.push_back(extended(segment, open0 ? by : 0, open1 ? by : 0));
    }
    // Segments no surface makes are extended at both ends. Contact lines end exactly at occluder
    // vertices where computed events start (the foot of an edge standing on the receiver): an
    // event passing an ulp beside that end must still cross them.
    const auto addExtended = [&](const std::vector<DiscontinuitySegment>& pieces,
                                 long long& count) {
      for (const DiscontinuitySegment& segment : pieces)
        segments.push_back(extended(segment, by, by));
      count += (long long)pieces.size();
    };
    for (PolygonId light : scene.lights) {
      const WorldPolygon& lightPolygon = scene.polygons[light];
      addExtended(lightPlaneSegments(receiver, lightPolygon, lightPlaneSurface(scene, light)),
                  stats_.lightPlaneSegments);
      addExtended(horizonSegments(*adjacency_, *grid_, receiver, lightPolygon,
                                  horizonSurface(scene, light)),
                  stats_.horizonSegments);
    }
    addExtended(contactSegments(scene, *grid_, receiver), stats_.contactSegments);
    data.mesh.insert(segments);
    stats_.meshVertices += data.mesh.vertexCount();
    stats_.meshEdges += data.mesh.edgeCount();
    stats_.meshFaces += (long long)data.mesh.faces().size();
    stats_.meshBytes += data.mesh.memoryBytes();
    receivers_.emplace(receiver.id, std::move(data));
  }
  stats_.secondsMeshing = secondsSince(start);

  start = Clock::now();
  const double sliver = kSliverSize * scene.bounds.diagonalLength();
  for (auto& [id, data] : receivers_) {
    const WorldPolygon& receiver = scene.polygons[id];
    for (const MeshFace& face : data.mesh.faces()) {
      FaceData faceData;
      for (PolygonId light : scene.lights) {
        Backprojection bp =
            backprojections_->compute(light, face.samplePoint, receiver.plane.normal, id);
        stats_.unlabelledBackprojections += bp.isLabelled ? 0 : 1;
        for (const auto& cycle : bp.cycles) {
          stats_.backprojectionVertices += (long long)cycle.size();
          stats_.backprojectionBytes += cycle.capacity() * sizeof(BackprojectionVertex);
        }
        faceData.perLight.push_back(std::move(bp));
      }
      // Faces of no area (where extended segments overshoot one another) hold no query and
      // their labels are degenerate: not verified.
      if (options_.verifyFaces && face.area > sliver * sliver) {
        const auto verifying = Clock::now();
        faceData.unresolved = !labelsHoldAtCorners(data.mesh, face, faceData, data.eeeSegments);
        stats_.secondsVerification += secondsSince(verifying);
      }
      stats_.unresolvedFaces += faceData.unresolved ? 1 : 0;
      data.faces.push_back(std::move(faceData));
    }
  }
  stats_.secondsBackprojections = secondsSince(start) - stats_.secondsVerification;
}

bool DiscontinuityMeshEngine::labelsHoldAtCorners(const ReceiverMesh& mesh, const MeshFace& face,
                                                  const FaceData& data,
                                                  const SegmentProximity& eeeSegments) const {
  const WorldPolygon& receiver = posed_->polygons[mesh.receiver()];
  // Events meeting at one point leave clusters of corners a few ulps apart: one check each.
  const double apart = 1e-7 * posed_->bounds.diagonalLength();
  std::vector<Vec3> checked;
  for (const Polygon3& cycle : mesh.faceBoundary(face.index))
    for (const Vec3& corner : cycle) {
      if (std::any_of(checked.begin(), checked.end(),
                      [&](const Vec3& c) { return distance(c, corner) <= apart; }))
        continue;
      checked.push_back(corner);
      // Just inside the face near the corner; a point that falls outside it (a concave corner,
      // a sliver) proves nothing and is skipped.
      const Vec3 p = corner + (face.samplePoint - corner) * kCornerInset;
      if (mesh.locate(p) != face.index) continue;
      // Beside an EEE polyline the labels may be those of the conic's other side (the polyline
      // stands within its tolerance of the conic); queries there are answered at the point.
      if (eeeSegments.near(p, nearEee())) continue;
      for (size_t l = 0; l < posed_->lights.size(); ++l) {
        const Backprojection& atSample = data.perLight[l];
        if (!atSample.isLabelled) continue;
        const Backprojection here =
            backprojections_->compute(posed_->lights[l], p, receiver.plane.normal, receiver.id);
        if (here.isLabelled && !sameLabels(here, atSample, *adjacency_)) return false;
      }
    }
  return true;
}

const ReceiverMesh* DiscontinuityMeshEngine::meshOf(PolygonId receiver) const {
  const auto it = receivers_.find(receiver);
  return it == receivers_.end() ? nullptr : &it->second.mesh;
}

Rgb DiscontinuityMeshEngine::faceIrradianceAt(PolygonId receiver, int face, const Vec3& p) const {
  const ReceiverData& data = receivers_.at(receiver);
  const Vec3& n = posed_->polygons[receiver].plane.normal;
  if (data.faces[face].unresolved) return atPoint(p, n, receiver);
  return backprojections_->irradiance(data.faces[face].perLight, p, n, receiver);
}

double DiscontinuityMeshEngine::nearEee() const {
  return 2 * kEeeChordTolerance * posed_->bounds.diagonalLength();
}

Rgb DiscontinuityMeshEngine::atPoint(const Vec3& p, const Vec3& n, PolygonId receiver) const {
  std::vector<Backprojection> here;
  for (PolygonId light : posed_->lights)
    here.push_back(backprojections_->compute(light, p, n, receiver));
  return backprojections_->irradiance(here, p, n, receiver);
}

std::optional<Rgb> DiscontinuityMeshEngine::irradiance(const Vec3& p, const Vec3& n) const {
  const auto match = locateReceiver(*posed_, *grid_, p, n);
  if (!match) return std::nullopt;
  const auto it = receivers_.find(match->polygon);
  if (it == receivers_.end()) return std::nullopt;
  const WorldPolygon& receiver = posed_->polygons[match->polygon];
  const Vec3 onPlane = receiver.plane.project(p);
  const auto face = it->second.mesh.locate(onPlane);
  // The locator accepts points within its tolerance outside the polygon (a point on the diagonal
  // of a triangulated quad may match the triangle it is an ulp outside of): no face holds them.
  if (!face) return atPoint(p, n, match->polygon);
  if (it->second.faces[*face].unresolved) return atPoint(p, n, match->polygon);
  // Within the polyline tolerance of an approximated EEE conic the face may be the neighbour's:
  // the backprojection is computed at the point itself there.
  if (it->second.eeeSegments.near(onPlane, nearEee())) return atPoint(p, n, match->polygon);
  return backprojections_->irradiance(it->second.faces[*face].perLight, p, n, match->polygon);
}

}  // namespace penumbra
