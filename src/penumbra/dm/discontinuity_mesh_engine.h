#pragma once
// The exact soft-shadow engine (Loscos & Drettakis 1997, building on Drettakis & Fiume 1994): for
// every light, its discontinuity surfaces are enumerated, cast through the regular grid and
// clipped by visibility in their own planes; the visible pieces become edges of a planar mesh on
// every receiver polygon (with contact lines of touching polygons and the receiver-plane events of
// receiver_plane_events.h); every face gets a labelled backprojection per light, which gives the
// exact visible light, hence exact irradiance, at any point of the face.
//
// Events built: EV with a light vertex or edge, non-emitter EV (occluder vertex × occluder edge),
// the degenerate EEE of an occluder polygon whose plane cuts the light, EEE with a light edge and
// two occluder edges and EEE of three occluder edges (polylines within kEeeChordTolerance), the
// light plane's line and the horizon events on receivers. Face verification
// (DmOptions::verifyFaces) finds the faces that a missing event crosses; they answer at the point.

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/base/hash_doubles.h"
#include "penumbra/base/rgb.h"
#include "penumbra/base/small_ids.h"
#include "penumbra/dm/backprojection.h"
#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/eee_surfaces.h"
#include "penumbra/dm/receiver_mesh.h"
#include "penumbra/dm/segment_proximity.h"
#include "penumbra/scene/scene.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

struct DmStats {
  int lights = 0;
  // What the last build or update was told: objects moved by the change (0 for a build), and
  // whether it recomputed everything.
  int movedObjects = 0;
  bool recomputedAll = true;
  // Receiver meshes kept (same segments) and built from scratch (new, or moved); faces whose
  // backprojections and verification were kept (same boundary, no moved bounds in their cones)
  // and recomputed: what an update's cost follows.
  long long keptMeshes = 0, rebuiltMeshes = 0, reusedFaces = 0, recomputedFaces = 0;
  // Kept meshes whose inputs were carried over from the frame before (renamed) without being
  // assembled again: no surface's pieces changed on the receiver, nor its own events.
  long long carriedInputs = 0;
  // Receiver meshes an update edited (ReceiverMesh::update), the surfaces whose edges those edits
  // removed and inserted, and the edited meshes built again in one sweep (most pieces changed).
  long long editedMeshes = 0, removedSurfaces = 0, insertedSurfaces = 0, resweptMeshes = 0;
  // Planar surfaces whose cast (cells and stored intersections) was kept: the same fan as before,
  // and no moved object's old or new bounds in any of its cells.
  long long keptCasts = 0;
  // Planar surfaces with the same fan whose cells a moved object touches: only their cuts with
  // the moved objects' polygons computed again (the paper's re-intersection with the mover).
  long long recastMovedCasts = 0;
  // EEE surfaces whose traced segments were kept: the same light and edges as before, and no
  // moved object's old or new bounds in any of the cells their lines cross.
  long long keptTraces = 0;
  // EEE enumeration's candidates per EV surface and cut polygon (and per light-edge crossing):
  // taken over where the surface's generators and the polygon are unchanged, else examined.
  long long keptCandidateCuts = 0, examinedCandidateCuts = 0;
  // Vertices whose non-emitter EV surfaces were taken over (the vertex and the polygons in its
  // region's cells unchanged), and those examined.
  long long keptNonEmitterVertices = 0, examinedNonEmitterVertices = 0;
  // Pairs of coplanar edges whose crossing surfaces were taken over (the pair and the polygons in
  // its region's cells unchanged, moved ones examined again), and those examined.
  long long keptCoplanarPairs = 0, examinedCoplanarPairs = 0;
  // Planes of a light edge and a parallel occluder edge whose crossing surfaces were taken over
  // (their fans' cuts all kept), and those examined.
  long long keptParallelPlanes = 0, examinedParallelPlanes = 0;
  // Polygons whose planes' crossing surfaces (occluder plane × occluder edge) were taken over
  // (the polygon and the polygons in its region's cells unchanged, moved ones examined again),
  // and those examined.
  long long keptOccluderPlanes = 0, examinedOccluderPlanes = 0;
  int surfacesEmitterVertex = 0;      // light vertex × occluder edge
  int surfacesEmitterEdge = 0;        // light edge × occluder vertex
  int surfacesNonEmitter = 0;         // occluder vertex × occluder edge
  int surfacesOccluderPlane = 0;      // light edge × an occluder polygon's plane (degenerate EEE)
  int surfacesOccluderPlaneEdge = 0;  // occluder edge × an occluder polygon's plane
  int surfacesOccluderPlaneVertex = 0;   // an occluder polygon's plane × its own vertex
  int surfacesCoplanarEdges = 0;         // light edge × two coplanar occluder edges
  int surfacesParallelEdgeCrossing = 0;  // light edge × parallel occluder edge × crossing X
  int surfacesCoplanarEdgeCrossing = 0;  // two coplanar occluder edges × crossing X
  int surfacesEee = 0;                   // light edge × two occluder edges (traced as polylines)
  int surfacesEeeOccluder = 0;           // three occluder edges (traced as polylines)
  long long eeeSegments = 0;
  int eeeSurfacesTruncated = 0;  // tracing ended at its line budget (degenerate conics)
  double secondsEee = 0;
  long long storedIntersections = 0;
  long long visibleSegments = 0;
  long long contactSegments = 0;
  long long lightPlaneSegments = 0;  // where a light's plane crosses a receiver
  long long horizonSegments = 0;     // events of receivers whose plane cuts a light
  long long meshVertices = 0, meshEdges = 0, meshFaces = 0;
  long long backprojectionVertices = 0;  // summed over faces and lights
  long long unlabelledBackprojections = 0;
  long long unresolvedFaces = 0;  // faces whose labels differ at a corner (see DmOptions)
  long long sliverFaces = 0;      // faces narrower than kSliverSize, answered at the point
  // Face-light backprojections computed from a neighbour's candidates and kept, and those that
  // verification sent back to a from-scratch computation (DmOptions::propagateBackprojections).
  long long propagatedBackprojections = 0, propagationFallbacks = 0;
  size_t gridBytes = 0, surfaceCellBytes = 0, intersectionBytes = 0, meshBytes = 0,
         backprojectionBytes = 0;
  // What the update keeps from frame to frame beyond the surfaces' casts: the EEE candidates,
  // the non-emitter fans by vertex, the planar surfaces' visible pieces, the EEE traces (their
  // segments and followed lines).
  size_t updateCacheBytes = 0;
  double secondsSurfaces = 0, secondsCasting = 0, secondsVisibility = 0, secondsMeshing = 0,
         secondsBackprojections = 0, secondsVerification = 0;
};

struct DmOptions {
  // EEE surfaces (light edge × two occluder edges, and three occluder edges). Needed for a
  // complete mesh where the shadows of several occluders overlap. Off: faces may span an EEE event
  // (face verification then catches them and answers at the point).
  bool eeeSurfaces = true;
  // With eeeSurfaces, also the EEE surfaces of three occluder edges (where the crossing of two
  // occluders' projected edges passes over a third's inside the light). Off only to measure what
  // they add (tests, benchmarks).
  bool occluderEeeSurfaces = true;
  // The fans through the points where an obstacle crosses the plane of a light edge and an
  // occluder edge in line with it (SurfaceKind::kLightEdgeParallelEdgeCrossing). Off only to
  // measure what they add (tests, benchmarks).
  bool parallelEdgeCrossings = true;
  // The fans through the points where an occluder edge crosses the plane of two coplanar occluder
  // edges of different polygons (SurfaceKind::kCoplanarEdgesOccluderCrossing). Off only to
  // measure what they add.
  bool coplanarEdgeCrossings = true;
  // Check every face's labels just inside its corners against those at its sample point. A face
  // where they differ is crossed by an event the mesh lacks (a missing event is a defect of the
  // mesh, counted in DmStats::unresolvedFaces); queries there compute the backprojection at the
  // point, so irradiance stays exact. Off: every face answers from its sample's labels.
  bool verifyFaces = true;
  // Compute a face's backprojections from a verified neighbour's cone occluders plus the polygons
  // named by the events between them (crossing_occluders.h) instead of searching the grid. Only
  // with verifyFaces: a propagated face whose corners disagree, or that verification cannot
  // check, is recomputed from scratch. Off by default: measured no cheaper (docs/shadows.md), and
  // exact only where the mesh lacks no event: a shadow that enters and leaves a face through
  // missing events, around its sample but at none of its corners, escapes both the propagated
  // candidates and verification (one face of 11,811 in the generated 1k room).
  bool propagateBackprojections = false;
};

class DiscontinuityMeshEngine {
 public:
  // Discontinuity segments are lengthened by this fraction of the scene's size at both ends.
  static constexpr double kSegmentExtension = 1e-9;
  // Segments within this fraction of the scene's size of one line are snapped onto one exact line
  // (ReceiverMesh::insert): axis-aligned scenes compute many events twice, by coplanar fans.
  static constexpr double kSegmentSnap = 1e-12;
  // EEE conics are traced as polylines within this fraction of the scene's size; points closer
  // than twice that to such a polyline get their backprojection computed where they are.
  static constexpr double kEeeChordTolerance = 1e-6;
  // Face verification samples the point this fraction of the way from each corner to the face's
  // sample point; where that point lies beside an EEE polyline (whose side of the conic is not
  // known) or outside the face (a concave corner), the points as far along the corner's bisector,
  // then the next fraction, farther in. A face whose corners all lie beside polylines is then
  // still verified, as its labels answer points beside them (facesBySides).
  static constexpr std::array<double, 4> kCornerInsets{1e-3, 1e-2, 1e-1, 0.5};
  // Receivers longer than twice this share of the scene's (frame-invariant) diagonal are tiled by
  // fixed lines at least this far apart (ReceiverMesh's tileSize).
  static constexpr double kTileShare = 0.125;
  // Faces narrower than about this fraction of the scene's size are slivers, left unverified.
  static constexpr double kSliverSize = 1e-7;

  // The mesh is built in the scene's own coordinates, to tolerances of 1e-12 to 1e-9 of the size
  // of its extent (every pose's bounds), so its coordinates must resolve that size more finely:
  // the scene may lie no farther from the origin than this many times its extent's size (where
  // doubles resolve it to 2^-52 x 2^15 = 7e-12 of its size). The dm_geometry fuzzer's scenes
  // 4e-6 to 0.6 across, 1 to 1e6 from the origin (2.4e5 to 1.6e11 times their size) were off
  // by 1e-6 to 3x; nearer, the rounding of the input stays below the engine's tolerances.
  static constexpr double kMaxDistanceToSize = 32768;
  // Whether a scene with this extent lies near enough the origin (kMaxDistanceToSize).
  static bool resolves(const Box3& extent);
  // Throws InputError (located at `where`, the scene's file) naming the figures when it does not.
  static void requireResolves(const Box3& extent, const std::string& where);

  explicit DiscontinuityMeshEngine(DmOptions options = {});
  ~DiscontinuityMeshEngine();

  // Full computation at the current pose of a shared live scene (which must outlive the engine's
  // use of it: the engine reads its posed scene and grid; InputError when it lies too far from
  // the origin, requireResolves).
  void build(const DynamicScene& scene);
  // Brings the solution to the scene's new pose after `change` was applied to it (the scene built
  // from). Every discontinuity surface is enumerated again; a planar surface keeps its cast and
  // an EEE surface its traced lines where no moved bounds (old or new) lie in their grid cells.
  // A receiver whose segments are the same as before keeps its mesh; another (that did not move
  // itself) has its mesh edited locally into exactly the mesh its segments build
  // (ReceiverMesh::update: the surfaces that changed removed and inserted). A face that kept its
  // boundary keeps its backprojections and verification unless a moved object's old or new
  // bounds pass the occluder test of a cone they were computed with (keepsFaceData). What is
  // kept is what a full computation would compute again from the same inputs, and meshes are
  // canonical, so the result is identical to build() (`shadows --mode verify`). A receiver no
  // changed surface piece reaches, whose own events (contacts, light planes, horizons) read no
  // cell a moved object touched, takes its inputs over renamed without assembling them. The
  // fans made after casting (parallel-edge and coplanar-edge crossings) whose inputs are the
  // frame before's take its surfaces over whole, casts included, and the light-edge EEE
  // candidates are reference-counted by the cuts that list them: only the cuts that changed
  // count. Still global: enumerating, matching and filing every surface, and listing the
  // surfaces again from the counts (issue 16's next steps).
  void update(const DynamicScene& scene, const SceneChange& change);
  // Conveniences that own a live scene of their own: keyframe pose `frame`, or a static posed
  // scene (tests, tools).
  void build(const Scene& scene, double frame);
  void build(const PosedScene& posed);

  // Exact direct irradiance at p (normal n) on the receiver polygon p lies on, from the
  // backprojections of p's face. Nothing when p lies on no receiver.
  std::optional<Rgb> irradiance(const Vec3& p, const Vec3& n) const;
  // How a query was answered: by its face's backprojections, or at the point by the exact
  // reference, and why (`probe --report` counts them).
  enum class Answer {
    kMesh,              // the face's labelled backprojections evaluated at the point
    kOutsideFaces,      // on the receiver within the locator's tolerance but in no face
    kUnresolvedFace,    // a face a missing event crosses (face verification)
    kSliverFace,        // a face too thin to carry labels
    kNearEeePolyline,   // within the EEE polylines' tolerance of an approximated conic
    kDegenerate,        // the backprojection gave no finite non-negative value (contact points)
    kUnlabelled,        // the face's backprojection could not be labelled at its sample (more or
                        // fewer than two features meet at one of its vertices)
    kOnAnotherPolygon,  // a contact: the point lies on an occluder touching the receiver, where
                        // irradiance jumps and the faces around hold one-sided limits only
  };
  struct Query {
    Rgb irradiance;
    Answer answer = Answer::kMesh;
  };
  // irradiance(), saying how it was answered.
  std::optional<Query> query(const Vec3& p, const Vec3& n) const;
  // Is a value from a backprojection degenerate: not finite, or below zero by more than rounding
  // (1e-12 of its largest channel, or 1e-13 of the brightest light's exitance)? Lambert's formula
  // gives such values at points where an occluder touches the receiver (zero-length edge
  // vectors); they are answered at the point. In an umbra the sum of the light's terms, each of
  // the order of its exitance, rounds to a few 1e-14 of it either side of zero (measured at edge
  // midpoints of desk-145: down to -3e-14 W/m² under a lamp of exitance 110): that is zero, and
  // within what the engine answers to there (1e-9 of 1e-4 of the exitance, bench/dm_exactness).
  bool isDegenerate(const Rgb& e) const;
  // A value that is not degenerate, with what rounding left below zero (Lambert's sum in an
  // umbra: -1e-15 of the brightest value) set to zero: irradiance is never negative.
  static Rgb withoutRoundingBelowZero(const Rgb& e);
  // The last build's or update's figures. The totals over every receiver (mesh and
  // backprojection counts, unresolved faces) and the update's cache memory are summed when first
  // asked for, not by the update itself: a pass over the whole scene that its cost should not
  // follow (4% of a 10,000-polygon room's step).
  const DmStats& stats() const;
  const PosedScene& posedScene() const { return *posed_; }
  const UniformGrid& grid() const { return *grid_; }
  const ReceiverMesh* meshOf(PolygonId receiver) const;
  // The segments a receiver's mesh was built from, in insertion order (extended, with the
  // receiver-plane events and contact lines): what an update compares.
  const std::vector<DiscontinuitySegment>& meshInputs(PolygonId receiver) const {
    return receivers_.at(receiver).inputs;
  }
  const std::vector<DiscontinuitySurface>& surfaces() const { return surfaces_; }
  const std::vector<EeeSurface>& eeeSurfaces() const { return eeeSurfaces_; }
  const EdgeAdjacency& adjacency() const { return *adjacency_; }
  // Irradiance at a face sample point of a receiver, for every face (for images and statistics).
  Rgb faceIrradianceAt(PolygonId receiver, int face, const Vec3& p) const;
  // The exact reference's irradiance at p on `receiver` (the visible light clipped at the point,
  // no mesh): what faces answered at the point give, and the fallback where a face's
  // backprojection is degenerate at a point (irradiance_mesh.cpp's contact corners).
  Rgb irradianceAtPoint(PolygonId receiver, const Vec3& p) const {
    return atPoint(p, posed_->polygons[receiver].plane.normal, receiver);
  }
  // Did face verification find labels differing at one of the face's corners (DmOptions)? (A
  // sliver is not unresolved, but is also answered at the point: isAnsweredAtPoint.)
  bool isUnresolved(PolygonId receiver, int face) const {
    return receivers_.at(receiver).faces[face].unresolved;
  }
  bool isAnsweredAtPoint(PolygonId receiver, int face) const {
    return receivers_.at(receiver).faces[face].answersAtPoint();
  }
  // Does p lie within twice the EEE chord tolerance of an EEE polyline of `receiver` (where a
  // face's labels may be those of the true conic's other side, and queries are answered at the
  // point)?
  bool isNearEeePolyline(PolygonId receiver, const Vec3& p) const {
    return receivers_.at(receiver).eeeSegments.near(p, nearEee());
  }
  // The labelled backprojections of a face (one per light), from its sample point.
  const std::vector<Backprojection>& faceBackprojections(PolygonId receiver, int face) const {
    return receivers_.at(receiver).faces[face].perLight;
  }

 private:
  struct FaceData {
    std::vector<Backprojection> perLight;
    // The labels at the face's sample differ from those just inside one of its corners: an event
    // the mesh lacks crosses the face, and its irradiance is computed at each query point.
    bool unresolved = false;
    // Of area below kSliverSize squared: made by events a rounding apart (extended segments
    // overshooting one another, collinear events computed twice), it has degenerate labels and
    // no corner to check them at. No labels are computed; its irradiance is computed at each
    // query point. About half the faces of the furnished scenes are slivers.
    bool sliver = false;
    // The box of its corners: a face an update finds again has the same boundary, and its keep
    // test (keepsFaceData) starts from this box instead of walking the boundary again.
    Box3 bounds;
    bool answersAtPoint() const { return unresolved || sliver; }
  };
  struct ReceiverData {
    ReceiverMesh mesh;
    std::vector<FaceData> faces;
    SegmentProximity eeeSegments;  // approximated conics on this receiver
    // What the mesh was built from: the segments inserted (in order) and the EEE polylines.
    std::vector<DiscontinuitySegment> inputs;
    std::vector<std::pair<Vec3, Vec3>> eeeInputs;
    std::vector<SurfaceId> eeeSurfaceIds;  // the EEE surface of each of eeeInputs
  };
  // The face holding p (near an EEE polyline of the receiver) by the exact side of each EEE
  // surface near it: the face of a witness point a little off p, beyond every polyline's
  // tolerance, reached from p across EEE polylines only, and on p's side of every such surface;
  // where p lies on a surface within rounding, the faces of witnesses on both sides of it.
  // Nothing when no witness is certain.
  std::vector<int> facesBySides(const ReceiverData& data, int located, const Vec3& p) const;
  // Do two values agree to 1e-11 of the larger (faces answering together)?
  static bool agree(const Rgb& a, const Rgb& b);
  // The face (not a sliver, not unresolved) within 1e-12 of the scene of p, in a sliver face,
  // whose labels answer for it; nothing when the sliver is wider than that at p.
  std::optional<int> faceBesideSliver(const ReceiverData& data, int sliver, const Vec3& p) const;
  // The points just inside a face's corners where verification compares the labels with the
  // sample's (one per cluster of corners, inside the face, away from EEE polylines).
  std::vector<Vec3> cornerProbes(const ReceiverMesh& mesh, const MeshFace& face,
                                 const SegmentProximity& eeeSegments) const;
  // `compared` (optional, one per light) counts the corners where the labels were compared.
  // Whether p (on `receiver`) lies on another polygon, within the contact lines' tolerance.
  bool liesOnAnotherPolygon(const Vec3& p, PolygonId receiver) const;
  // Whether the sample's labels, different from those computed at p, still give p's own region
  // there (a degenerate alignment at one of the two points, not a missing event between them).
  bool isAlias(const Backprojection& atSample, const Backprojection& here, const Vec3& p,
               const WorldPolygon& receiver) const;
  // The face's labels for `light` computed at another point of it, where the sample's could not
  // be labelled (`atSample`: a degenerate alignment there), taken only where they give the
  // sample's own light; its cone's occluders into `occluders`.
  std::optional<Backprojection> labelledElsewhere(const ReceiverMesh& mesh, const MeshFace& face,
                                                  const Backprojection& atSample,
                                                  const SegmentProximity& eeeSegments,
                                                  std::vector<PolygonId>& occluders) const;
  bool labelsHoldAtCorners(const ReceiverMesh& mesh, const MeshFace& face, const FaceData& data,
                           const SegmentProximity& eeeSegments,
                           std::vector<int>* compared = nullptr) const;
  // Backprojections of every face of one receiver, each from scratch or propagated from a
  // verified neighbour (DmOptions::propagateBackprojections), and face verification; a face for
  // which `reuse` gives data (an update's unchanged face) takes it over (moved out).
  void computeFaceBackprojections(PolygonId receiver, ReceiverData& data, double sliver,
                                  const std::function<FaceData*(int)>& reuse = {});
  Rgb atPoint(const Vec3& p, const Vec3& n, PolygonId receiver) const;
  // Twice the EEE chord tolerance: closer than this to a polyline, answers are computed at the
  // point.
  double nearEee() const;

  // What tracing an EEE surface reads besides the polygons in its cells, and what it gave.
  struct EeeKey {
    PolygonId light = 0;
    int kind = 0, lightEdge = -1;
    // Each occluder edge's two ends (two or three edges; the rest zero), and its polygons, each
    // edge's list ended by -1: in the key itself, where they fit (there is one key per EEE
    // surface, made again every frame: 245,000 in a 10,000-polygon room).
    std::array<Vec3, 6> ends{};
    SmallIds<12> incident;
    bool operator==(const EeeKey&) const = default;
    std::size_t hash() const {
      std::uint64_t h =
          std::uint64_t(light) * 31 + std::uint64_t(kind) * 7 + std::uint64_t(lightEdge + 1);
      for (const Vec3& p : ends)
        for (double c : {p.x, p.y, p.z}) h = hashCombine(h, c);
      return std::size_t(h);
    }
  };
  // (Its surface's cells are the surface's, at the same index of eeeSurfaces_.)
  struct EeeTrace {
    EeeKey key;
    std::vector<DiscontinuitySegment> segments;
    std::vector<PolygonId> crossed;
    std::vector<std::pair<Vec3, Vec3>> lines;  // the critical lines it followed (traceEeeSurface)
  };

  // The computation over posed_ and grid_: everything (change null), or an update after `change`
  // that keeps the receivers whose inputs are unchanged (see update()).
  void compute(const SceneChange* change);
  // Does the change move anything (old or new bounds) into the box around `region` and a light
  // and into the shaft from `region` to that light's cones (where a point of `region` may see it)?
  bool isCrossed(const Box3& region, const SceneChange& change) const;
  // May an update keep the data of `face` (of the receiver's new data `now`), computed in the
  // frame before for a face with the same boundary vertices (whose receiver had the EEE
  // polylines `eeeBefore`: `sameEee` when they are now's; `eeeChanged` holds the polylines of
  // either frame that the other lacks)? Yes when it would be computed again
  // from the same inputs: the same corner probes, and no moved object's old or new bounds
  // admitted by the cone from the sample or a probe to any light.
  bool keepsFaceData(const ReceiverData& now, const MeshFace& face, const FaceData& before,
                     const SegmentProximity& eeeBefore, const SegmentProximity& eeeChanged,
                     bool sameEee, const SceneChange& change) const;
  // The mesh and face statistics summed over the receivers (into stats_, lazily: stats()).
  void tallyReceivers() const;
  // Memory of what the update keeps from frame to frame (DmStats::updateCacheBytes).
  size_t updateCacheBytes() const;

  DmOptions options_;
  std::unique_ptr<DynamicScene> ownedScene_;  // only for the convenience builds
  const PosedScene* posed_ = nullptr;
  const UniformGrid* grid_ = nullptr;
  // Leaves out the polygons of closed surfaces that face away from the point
  // (ClosedObjectFaces::kFacingThePoint): the same visible light with about half the polygons of
  // a box; the tests' oracle keeps them all.
  std::unique_ptr<ExactReference> reference_;
  std::unique_ptr<EdgeAdjacency> adjacency_;
  std::unique_ptr<BackprojectionBuilder> backprojections_;
  std::vector<DiscontinuitySurface> surfaces_;
  // Each surface's fan hash (the update's key for taking a cast over), read by the next update
  // instead of hashing every surface of the frame before again (2.6% of a large room's step).
  std::vector<std::size_t> fanHashes_, spareFanHashes_;
  // The block of grid cells (inclusive coordinate ranges) around a surface's cells: a surface
  // whose block misses the block of the cells a move touched has none of them, which the update
  // finds without reading the surface's cells (a list on the heap per surface: reading it was 4%
  // of a large room's step, most of it waiting for memory). Coordinates fit 16 bits
  // (UniformGrid::kMaxCellsPerAxis).
  struct CellBlock {
    std::array<std::int16_t, 3> low{32767, 32767, 32767}, high{-1, -1, -1};  // empty
    void extend(const std::array<int, 3>& c) {
      for (int k = 0; k < 3; ++k) {
        low[k] = std::min(low[k], std::int16_t(c[k]));
        high[k] = std::max(high[k], std::int16_t(c[k]));
      }
    }
    bool meets(const CellBlock& other) const {
      for (int k = 0; k < 3; ++k)
        if (high[k] < other.low[k] || other.high[k] < low[k]) return false;
      return true;
    }
  };
  static_assert(UniformGrid::kMaxCellsPerAxis <= 32767);
  std::vector<CellBlock> cellBlocks_, spareCellBlocks_;  // each surface's, by index
  std::vector<EeeSurface> eeeSurfaces_;
  std::vector<EeeTrace> eeeTraces_;  // one per EEE surface, for the next update
  EeeCandidateMemo eeeCandidates_;   // what EEE enumeration found, for the next update
  std::vector<std::vector<DiscontinuitySegment>> visible_;       // each planar surface's, ditto
  std::map<PolygonId, NonEmitterEvMemo> nonEmitter_;             // by light, ditto
  std::map<PolygonId, OccluderPlaneMemo> occluderPlanes_;        // by light, ditto
  std::map<PolygonId, CoplanarCrossingMemo> coplanarCrossings_;  // by light, ditto
  std::map<PolygonId, ParallelCrossingMemo> parallelCrossings_;  // by light, ditto
  std::map<PolygonId, ReceiverData> receivers_;
  // The storage of the frame before the last's lists, emptied, which the next update fills
  // again: a large room's lists (472,000 surfaces of 248 bytes, 245,000 traces) are larger than
  // what the allocator keeps for reuse, so a fresh list every frame was mapped from the system
  // and faulted in page by page (9% of a 10,000-polygon room's step, measured side by side;
  // it holds about 170 MB there between frames, and leaves the peak, while both frames' lists
  // exist, as it was).
  std::vector<DiscontinuitySurface> spareSurfaces_;
  std::vector<EeeTrace> spareTraces_;
  std::vector<std::vector<DiscontinuitySegment>> spareVisible_;
  std::vector<EeeSurface> spareEee_;
  // The fans made after casting, in storage kept from frame to frame (emptied after each
  // computation: they are moved into surfaces_).
  std::vector<DiscontinuitySurface> afterCastingStorage_;
  // Per light, the polygons its light-edge EEE surfaces' lines cross (for the three-edge ones),
  // made again every frame in this storage.
  std::map<PolygonId, std::vector<EeeCrossing>> eeeCrossings_;
  mutable DmStats stats_;
  mutable bool statsTallied_ = true;  // the receivers' totals and cache bytes are in stats_
};

}  // namespace penumbra
