#include "penumbra/dm/irradiance_mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "penumbra/dm/face_triangulation.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

// The face's irradiance at a triangle corner. At some corners (contact corners, where an
// occluder's edge touches the receiver, and a few corners where events meet) the face's
// backprojection is degenerate: Lambert's formula meets zero-length edge vectors or a visible
// region that collapses, and gives NaN or a negative value. There the exact reference computes the
// visible light at the corner itself; if the corner is degenerate for it too, at the point a
// millionth of the way towards the triangle's centroid (the face's value is continuous up to its
// boundary). Values within rounding of zero below it are set to zero.
Rgb cornerIrradiance(const DiscontinuityMeshEngine& engine, PolygonId receiver, int face,
                     const Vec3& p, const Vec3& inside, long long& fallbacks) {
  using Engine = DiscontinuityMeshEngine;
  const Rgb atCorner = engine.faceIrradianceAt(receiver, face, p);
  if (!engine.isDegenerate(atCorner)) return Engine::withoutRoundingBelowZero(atCorner);
  ++fallbacks;
  const Rgb exact = engine.irradianceAtPoint(receiver, p);
  if (!engine.isDegenerate(exact)) return Engine::withoutRoundingBelowZero(exact);
  return Engine::withoutRoundingBelowZero(
      engine.irradianceAtPoint(receiver, p + (inside - p) * 1e-6));
}

bool isOnSegment(const Vec3& p, const Vec3& a, const Vec3& b, double tolerance) {
  const Vec3 d = b - a;
  const double t = std::clamp(dot(p - a, d) / std::max(dot(d, d), 1e-300), 0.0, 1.0);
  return distance(p, a + d * t) <= tolerance;
}

// Does p lie on the receiver polygon's outline (within `tolerance`)?
bool isOnOutline(const Polygon3& polygon, const Vec3& p, double tolerance) {
  for (size_t i = 0; i < polygon.size(); ++i)
    if (isOnSegment(p, polygon[i], polygon[(i + 1) % polygon.size()], tolerance)) return true;
  return false;
}

// Does the segment ab lie along one edge of the polygon's outline?
bool isAlongOutline(const Polygon3& polygon, const Vec3& a, const Vec3& b, double tolerance) {
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& u = polygon[i];
    const Vec3& v = polygon[(i + 1) % polygon.size()];
    if (isOnSegment(a, u, v, tolerance) && isOnSegment(b, u, v, tolerance)) return true;
  }
  return false;
}

// Mesh vertices on the receivers' outlines, hashed by cell, so that each receiver can take the
// vertices its neighbours put on a shared polygon edge.
class OutlinePoints {
 public:
  explicit OutlinePoints(double cell) : cell_(cell) {}
  void add(const Vec3& p, PolygonId owner) {
    cells_[key(cellOf(p))].push_back(int(points_.size()));
    points_.push_back({p, owner});
  }
  // Points of other receivers within `tolerance` of the open segment ab, as parameters along it.
  std::vector<double> foreignPointsOn(const Vec3& a, const Vec3& b, PolygonId owner,
                                      double tolerance) const {
    std::vector<double> ts;
    const Vec3 d = b - a;
    const double len2 = dot(d, d);
    if (len2 == 0) return ts;
    const auto lo = cellOf(componentMin(a, b) - Vec3{tolerance, tolerance, tolerance});
    const auto hi = cellOf(componentMax(a, b) + Vec3{tolerance, tolerance, tolerance});
    const double margin = tolerance / std::sqrt(len2);
    for (long long x = lo[0]; x <= hi[0]; ++x)
      for (long long y = lo[1]; y <= hi[1]; ++y)
        for (long long z = lo[2]; z <= hi[2]; ++z) {
          const auto it = cells_.find(key({x, y, z}));
          if (it == cells_.end()) continue;
          for (int i : it->second) {
            const auto& [q, from] = points_[i];
            if (from == owner) continue;
            const double t = dot(q - a, d) / len2;
            if (t <= margin || t >= 1 - margin) continue;
            if (distance(q, a + d * t) <= tolerance) ts.push_back(t);
          }
        }
    return ts;
  }

 private:
  std::array<long long, 3> cellOf(const Vec3& p) const {
    // Clamped before the conversion (out of range it is undefined): a point that far out shares
    // its cell with others just as far, and the search stays correct, only slower.
    const auto coordinate = [&](double x) {
      return (long long)std::clamp(std::floor(x / cell_), -4.0e18, 4.0e18);
    };
    return {coordinate(p.x), coordinate(p.y), coordinate(p.z)};
  }
  // Wrapping (unsigned) arithmetic: cells far from the origin overflow a signed product.
  static std::uint64_t key(const std::array<long long, 3>& c) {
    return (std::uint64_t(c[0]) * 73856093u) ^ (std::uint64_t(c[1]) * 19349663u) ^
           (std::uint64_t(c[2]) * 83492791u);
  }
  double cell_;
  std::vector<std::pair<Vec3, PolygonId>> points_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// Is the face's sample point under a polygon in face-to-face contact with the receiver (coplanar,
// facing the other way: a cabinet's back against the wall)? Such a face can be seen from nowhere
// (each side hides the other), receives no light, and drawn it fights for depth with the
// polygon covering it at every pixel along the contact: black specks where it wins.
bool isCoveredByContact(const PosedScene& scene, const UniformGrid& grid,
                        const WorldPolygon& receiver, const Vec3& sample, double tolerance) {
  bool covered = false;
  grid.forEachCellOverlappingBox(Box3{sample, sample}.expanded(tolerance), [&](int cell) {
    for (PolygonId id : grid.polygonsInCell(cell)) {
      if (covered || id == receiver.id) continue;
      const WorldPolygon& q = scene.polygons[id];
      if (dot(q.plane.normal, receiver.plane.normal) > -1 + 1e-9) continue;
      if (std::abs(q.plane.signedDistance(sample)) > tolerance) continue;
      const PlaneFrame frame = PlaneFrame::fromPlane(q.plane, q.vertices[0]);
      Polygon2 local;
      for (const Vec3& v : q.vertices) local.push_back(frame.toLocal(v));
      covered = containsPoint(local, frame.toLocal(sample));
    }
  });
  return covered;
}

}  // namespace

IrradianceMesh buildIrradianceMesh(const DiscontinuityMeshEngine& engine, double maxEdgeLength) {
  IrradianceMesh out;
  const PosedScene& scene = engine.posedScene();
  // Each receiver's mesh splits its polygon's edges only where its own events meet them, so two
  // receivers sharing an edge (a cabinet's front and side) split it at different points: a
  // T-junction, and the rasteriser leaves sub-pixel cracks there through which the inside of the
  // object shows as dark specks. Every outline segment is therefore also split where the
  // neighbouring receivers' meshes have vertices on it (projected onto it, so the face's boundary
  // stays straight).
  const double size = scene.extent.diagonalLength();
  const double tolerance = 1e-9 * size;
  OutlinePoints outline(size / 256);
  std::map<std::pair<PolygonId, int>, std::vector<std::pair<Vec3, Vec3>>> boundaries;
  for (const WorldPolygon& receiver : scene.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      auto& segments = boundaries[{receiver.id, face.index}];
      segments = mesh->faceBoundarySegments(face.index);
      for (const auto& [a, b] : segments)
        for (const Vec3& p : {a, b})
          if (isOnOutline(receiver.vertices, p, tolerance)) outline.add(p, receiver.id);
    }
  }
  for (const WorldPolygon& receiver : scene.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      if (isCoveredByContact(scene, engine.grid(), receiver, face.samplePoint, tolerance)) {
        ++out.coveredFaces;
        continue;
      }
      std::vector<std::pair<Vec3, Vec3>> segments;
      for (const auto& [a, b] : boundaries[{receiver.id, face.index}]) {
        std::vector<double> ts;
        if (isAlongOutline(receiver.vertices, a, b, tolerance))
          ts = outline.foreignPointsOn(a, b, receiver.id, tolerance);
        std::sort(ts.begin(), ts.end());
        Vec3 from = a;
        for (double t : ts) {
          const Vec3 at = a + (b - a) * t;
          if (distance(at, from) <= tolerance) continue;
          segments.push_back({from, at});
          from = at;
        }
        segments.push_back({from, b});
      }
      for (const auto& [a, b, c] : triangulateFace(segments, mesh->frame(), maxEdgeLength)) {
        // Counter-clockwise about the frame's normal; the frame's normal is the receiver's.
        const Vec3 inside = (a + b + c) / 3;
        for (const Vec3& p : {a, b, c}) {
          out.indices.push_back(std::uint32_t(out.positions.size()));
          out.positions.push_back(p);
          out.irradiance.push_back(
              cornerIrradiance(engine, receiver.id, face.index, p, inside, out.referenceCorners));
          out.receiverOf.push_back(receiver.id);
        }
      }
    }
    for (const auto& [segment, surfaces] : mesh->edges())
      if (std::any_of(surfaces.begin(), surfaces.end(), [](SurfaceId id) {
            return id != ReceiverMesh::kBoundary && id != ReceiverMesh::kTile;
          }))
        out.edges.push_back(segment);
  }
  return out;
}

namespace {

// Bit for bit: -0 differs from 0, and a NaN equals the same NaN (a NaN is a defect of its own,
// issue 20, but not a difference between two computations).
bool identical(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool identical(const Vec3& a, const Vec3& b) {
  return identical(a.x, b.x) && identical(a.y, b.y) && identical(a.z, b.z);
}
bool identical(const Rgb& a, const Rgb& b) {
  return identical(a.r, b.r) && identical(a.g, b.g) && identical(a.b, b.b);
}

std::string describe(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
  return text;
}

}  // namespace

std::optional<std::string> firstDifference(const IrradianceMesh& a, const IrradianceMesh& b) {
  if (a.positions.size() != b.positions.size())
    return "corner counts differ: " + std::to_string(a.positions.size()) + " vs " +
           std::to_string(b.positions.size());
  if (a.indices.size() != b.indices.size())
    return "triangle counts differ: " + std::to_string(a.indices.size() / 3) + " vs " +
           std::to_string(b.indices.size() / 3);
  if (a.edges.size() != b.edges.size())
    return "edge counts differ: " + std::to_string(a.edges.size()) + " vs " +
           std::to_string(b.edges.size());
  for (size_t i = 0; i < a.positions.size(); ++i) {
    if (!identical(a.positions[i], b.positions[i]) || a.receiverOf[i] != b.receiverOf[i])
      return "corner " + std::to_string(i) + " differs: " + describe(a.positions[i]) + " vs " +
             describe(b.positions[i]);
    if (!identical(a.irradiance[i], b.irradiance[i]))
      return "irradiance at corner " + std::to_string(i) + " " + describe(a.positions[i]) +
             " on polygon " + std::to_string(a.receiverOf[i]) + " differs";
  }
  for (size_t i = 0; i < a.indices.size(); ++i)
    if (a.indices[i] != b.indices[i]) return "triangle " + std::to_string(i / 3) + " differs";
  for (size_t i = 0; i < a.edges.size(); ++i)
    if (!identical(a.edges[i].first, b.edges[i].first) ||
        !identical(a.edges[i].second, b.edges[i].second))
      return "discontinuity edge " + std::to_string(i) + " differs: " + describe(a.edges[i].first) +
             " vs " + describe(b.edges[i].first);
  return std::nullopt;
}

}  // namespace penumbra
