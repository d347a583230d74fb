#pragma once
// The planar discontinuity mesh of one receiver polygon: a half-edge arrangement (CGAL
// Arrangement_2, exact constructions) in the receiver's plane, whose edges carry the set of
// discontinuity surfaces that made them (or the receiver's boundary), with local insertion and
// removal for the incremental update (Loscos & Drettakis 1997 §4). Faces inside the receiver are
// indexed and given an interior sample point, where their backprojection is computed.
//
// CGAL stays inside receiver_mesh.cpp: this header only uses Penumbra's types.

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "penumbra/dm/discontinuity_surface.h"

namespace penumbra {

struct MeshFace {
  int index = 0;
  Vec3 samplePoint;  // strictly inside the face (rounded to double from an exact construction)
  double area = 0;
};

// An edge between two different inside faces, with the surfaces that made it: walking from one
// face to the other crosses exactly these events.
struct FaceCrossing {
  int face = 0, other = 0;
  std::vector<SurfaceId> surfaces;
};

// An edge of a face near a point, as a crossing from the face, with where it passes the point:
// its point nearest to it and the unit direction across it into the other face (in the plane).
struct NearCrossing {
  FaceCrossing crossing;
  Vec3 nearest, intoOther;
};

// Where a straight walk across a mesh ends, and the surfaces of the edges it crossed (sorted,
// without repeats).
struct MeshWalk {
  int face = 0;
  std::vector<SurfaceId> surfaces;
};

class ReceiverMesh {
 public:
  static constexpr SurfaceId kBoundary = -1;
  // The fixed lines tiling a large receiver (no event: the irradiance is smooth across them).
  static constexpr SurfaceId kTile = std::numeric_limits<SurfaceId>::min();

  // The mesh starts as the receiver polygon alone, crossed where it is longer than 2 tileSize
  // (when positive) by lines at equal spacing of at least tileSize along both axes of its
  // plane's frame, from side to side of its bounds: a face of the mesh then holds a few shadow
  // islands as holes instead of every island of a large floor (hundreds in a 10,000-polygon
  // room), and inserting an edit's pieces, which scans the holes of each face it splits, costs
  // what the change costs. The lines are a function of the polygon alone, so every build of the
  // mesh holds the same ones.
  explicit ReceiverMesh(const WorldPolygon& receiver, double tileSize = 0);
  ~ReceiverMesh();
  ReceiverMesh(ReceiverMesh&&) noexcept;
  ReceiverMesh& operator=(ReceiverMesh&&) noexcept;

  PolygonId receiver() const;
  // Inserts segments lying on the receiver's plane (projected onto it), in one sweep.
  // Overlapping pieces keep the union of their surfaces. Segments that lie within
  // `snapTolerance` of one line (one event computed by several coplanar surfaces, an event along a
  // contact line) are first moved exactly onto the line of the longest of them (also the
  // outline's, where one is near), each keeping its surface: computed apart they would stand a
  // few ulps from one another and leave sliver faces between them.
  void insert(const std::vector<DiscontinuitySegment>& segments, double snapTolerance = 0);
  // What an update changed: surfaces whose pieces were removed, and surfaces inserted.
  struct UpdateStats {
    int removedSurfaces = 0, insertedSurfaces = 0;
    bool rebuilt = false;  // more pieces changed than stayed: built again in one sweep
  };
  // Makes the mesh exactly what insert(segments, snapTolerance) builds on a new mesh of the
  // receiver (the same faces, indices, samples and boundaries, bit for bit), editing it locally:
  // a surface whose pieces (by the doubles they come from, or by their exact ends where only the
  // line they were snapped onto came from other doubles) are those of a surface already here
  // takes over its edges under its new id; the others' edges are removed, the vertices that
  // leaves redundant merged away, and the new pieces inserted one by one (or, when more pieces
  // change than stay, the mesh is built again in one sweep). Gives each face's index before the
  // update where the face has the same boundary as then (same vertices, or the same exact
  // points), else -1.
  std::vector<int> update(const std::vector<DiscontinuitySegment>& segments,
                          double snapTolerance = 0, UpdateStats* stats = nullptr);
  // Renames the surfaces named on the edges (ids not in `renamed` stay): for an update whose
  // segments kept their geometry and order but not their surfaces' positions in the frame's list.
  // Geometry and face indices are unchanged. `renamed`: (old id, new id), sorted by the old.
  using Renaming = std::vector<std::pair<SurfaceId, SurfaceId>>;
  void renumberSurfaces(const Renaming& renamed);

  int vertexCount() const;
  int edgeCount() const;
  // Faces inside the receiver, indexed 0..n-1 in the order of their sample points: the same
  // indices for the same geometry, however the arrangement was built or edited.
  const std::vector<MeshFace>& faces() const;
  // The face containing p (p on the receiver's plane); a point on an edge or vertex gets the
  // inside face of lowest index around it. Nothing when p is outside the receiver.
  std::optional<int> locate(const Vec3& p) const;
  // Does p lie strictly inside the face (not on its boundary)? A function of the face's geometry
  // alone.
  bool isInside(const Vec3& p, int face) const;
  // Every edge as a 3D segment with its surfaces, sorted (for drawing and statistics).
  std::vector<std::pair<std::pair<Vec3, Vec3>, std::vector<SurfaceId>>> edges() const;
  std::vector<Vec3> vertexPositions() const;
  // The boundary cycles of a face (outer first, then holes), vertices in order, antennas
  // included (for drawing, triangulation and diagnostics). Canonical: each cycle starts at its
  // lexicographically least vertex sequence, holes in the order of those sequences.
  std::vector<Polygon3> faceBoundary(int face) const;
  // The vertices of a face's boundary cycles (antennas' bases twice), in the arrangement's order:
  // a function of the face's geometry as a multiset only, for order-free tests.
  std::vector<Vec3> faceCorners(int face) const;
  // The edges that separate a face from other faces (antennas left out), as 3D segments.
  std::vector<std::pair<Vec3, Vec3>> faceBoundarySegments(int face) const;
  // Every edge separating two different inside faces (face adjacency for propagating per-face
  // data; antennas and the outline left out).
  std::vector<FaceCrossing> faceCrossings() const;
  // The edges of `face` within `radius` of p that separate it from another inside face, each as
  // a crossing from `face` (in the order of the other face's index).
  std::vector<NearCrossing> crossingsNear(int face, const Vec3& p, double radius) const;
  // Walks the segment from `from` (in or on the boundary of `face`) to `to`, crossing faces in
  // double precision. Nothing where that cannot tell the faces apart: the segment passes within
  // rounding of a mesh vertex or along an edge, leaves the receiver, or crosses more than
  // `maxCrossings` edges.
  std::optional<MeshWalk> walk(int face, const Vec3& from, const Vec3& to,
                               int maxCrossings = 64) const;
  // The receiver's plane frame, in which the mesh is built.
  const PlaneFrame& frame() const;
  size_t memoryBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
