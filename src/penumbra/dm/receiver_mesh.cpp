#include "penumbra/dm/receiver_mesh.h"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_landmarks_point_location.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>

namespace penumbra {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, SurfaceId>;
// Faces carry their index among the receiver's inside faces (-1 outside).
using Dcel = CGAL::Arr_face_extended_dcel<Traits, int>;
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;
using Point = Kernel::Point_2;
using FT = Kernel::FT;
// Landmarks: fast queries on large meshes; it observes the arrangement, so edits keep it valid.
using PointLocation = CGAL::Arr_landmarks_point_location<Arrangement>;

}  // namespace

struct ReceiverMesh::Impl {
  PolygonId receiver;
  PlaneFrame frame;
  Plane plane;
  Polygon2 outline;
  Arrangement arrangement;
  PointLocation locator{arrangement};
  std::vector<MeshFace> faces;
  // The receiver's outline, and whether the arrangement still holds nothing else (see insert()).
  std::vector<Traits::Curve_2> boundary;
  bool onlyBoundary = true;

  Point toPoint(const Vec3& p) const {
    const Vec2 q = frame.toLocal(p);
    return {q.x, q.y};
  }
  // Rounded from the exact coordinates, never from the lazy interval approximation: an interval
  // is tightened by whatever exact predicate last needed the point, so rounding it would depend on
  // the mesh's history (an update's kept mesh would differ by ulps from one built again).
  static Vec2 rounded(const Point& p) {
    return {CGAL::to_double(p.x().exact()), CGAL::to_double(p.y().exact())};
  }
  Vec3 toWorld(const Point& p) const { return frame.toWorld(rounded(p)); }
  // Each face's handle by index, and each vertex's world position as computed when the faces
  // were indexed. Rounding a lazy exact coordinate to double reads its current interval, which
  // later exact predicates (point location, verification) tighten: read later, the same vertex
  // could round an ulp differently depending on what was asked of the mesh since it was built.
  // Fixed at indexing, positions depend on the mesh's construction alone, so a mesh kept by an
  // update reads exactly as one built again from the same segments.
  std::vector<Arrangement::Face_const_handle> faceHandles;
  std::unordered_map<const void*, Vec2> vertexLocal;
  std::unordered_map<const void*, Vec3> vertexWorld;
  Vec3 worldOf(Arrangement::Vertex_const_handle v) const { return vertexWorld.at(&*v); }
  Vec2 localOf(Arrangement::Vertex_const_handle v) const { return vertexLocal.at(&*v); }

  // A point strictly inside face f, as far from its boundary as a cheap search finds: on the
  // vertical line through the middle of every slab between consecutive distinct vertex abscissae,
  // the boundary crossings alternate in and out of the face; take the middle of the inside
  // interval that maximizes min(interval length, slab width), so that the point is away from the
  // boundary both across and along the line. Faces of a discontinuity mesh can be slivers beside
  // long ones (nearly coincident events, slabs a few ulps wide), and a sample near an edge would
  // label the big face with a neighbour's backprojection. Slab and interval are chosen in
  // floating point; the point is constructed exactly.
  std::optional<Point> interiorPoint(Arrangement::Face_const_handle f) const {
    std::vector<Arrangement::Halfedge_const_handle> boundary;
    const auto collect = [&](Arrangement::Ccb_halfedge_const_circulator first) {
      auto c = first;
      do {
        if (c->twin()->face() != f) boundary.push_back(c);  // antennas bound nothing
      } while (++c != first);
    };
    if (f->has_outer_ccb()) collect(f->outer_ccb());
    for (auto h = f->holes_begin(); h != f->holes_end(); ++h) collect(*h);
    if (boundary.empty()) return std::nullopt;
    // The vertices' rounded coordinates (indexFaces): the search runs on them, only the chosen
    // point is constructed exactly.
    struct Side {
      double ax, ay, bx, by;
    };
    std::vector<Side> sides;
    std::vector<std::pair<double, Arrangement::Vertex_const_handle>> xs;
    for (auto h : boundary) {
      const Vec2 a = localOf(h->source()), b = localOf(h->target());
      sides.push_back({a.x, a.y, b.x, b.y});
      xs.push_back({sides.back().ax, h->source()});
    }
    std::sort(xs.begin(), xs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    xs.erase(std::unique(xs.begin(), xs.end(),
                         [](const auto& a, const auto& b) { return a.first == b.first; }),
             xs.end());
    if (xs.size() < 2) return std::nullopt;
    // Crossings of the vertical line x with the boundary, in floating point.
    const auto crossings = [&](double x) {
      std::vector<double> ys;
      for (const Side& e : sides) {
        if ((e.ax < x) == (e.bx < x)) continue;
        ys.push_back(e.ay + (e.by - e.ay) * (x - e.ax) / (e.bx - e.ax));
      }
      std::sort(ys.begin(), ys.end());
      return ys;
    };
    struct Candidate {
      double score;
      size_t slab, interval;
    };
    // The widest slabs first; a face with many vertices (a traced conic) is searched on 64.
    std::vector<size_t> slabs(xs.size() - 1);
    for (size_t k = 0; k < slabs.size(); ++k) slabs[k] = k;
    const auto width = [&](size_t k) { return xs[k + 1].first - xs[k].first; };
    if (slabs.size() > 64) {
      std::nth_element(slabs.begin(), slabs.begin() + 64, slabs.end(),
                       [&](size_t a, size_t b) { return width(a) > width(b); });
      slabs.resize(64);
    }
    std::vector<Candidate> candidates;
    for (size_t k : slabs) {
      const std::vector<double> ys = crossings(xs[k].first + 0.5 * width(k));
      for (size_t i = 0; i + 1 < ys.size(); i += 2)
        candidates.push_back({std::min(ys[i + 1] - ys[i], width(k)), k, i});
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    // The sample is used as a double 3D point: it must locate, rounded like a query, in f itself.
    std::optional<Point> fallback;
    for (size_t c = 0; c < candidates.size() && c < 8; ++c) {
      const FT x0 = (xs[candidates[c].slab].second->point().x() +
                     xs[candidates[c].slab + 1].second->point().x()) /
                    2;
      std::vector<FT> ys;
      for (auto h : boundary) {
        const Point& a = h->source()->point();
        const Point& b = h->target()->point();
        if ((a.x() < x0) == (b.x() < x0)) continue;
        ys.push_back(a.y() + (b.y() - a.y()) * (x0 - a.x()) / (b.x() - a.x()));
      }
      std::sort(ys.begin(), ys.end());
      const size_t i = candidates[c].interval;
      if (ys.size() < i + 2) continue;
      const Point inside(x0, (ys[i] + ys[i + 1]) / 2);
      if (!fallback) fallback = inside;
      const auto located = locator.locate(toPoint(toWorld(inside)));
      const auto* face = boost::get<Arrangement::Face_const_handle>(&located);
      if (face && *face == f) return inside;
    }
    return fallback;
  }

  void indexFaces() {
    faces.clear();
    faceHandles.clear();
    vertexLocal.clear();
    vertexWorld.clear();
    for (auto v = arrangement.vertices_begin(); v != arrangement.vertices_end(); ++v) {
      vertexLocal.emplace(&*v, rounded(v->point()));
      vertexWorld.emplace(&*v, frame.toWorld(vertexLocal.at(&*v)));
    }
    for (auto f = arrangement.faces_begin(); f != arrangement.faces_end(); ++f) {
      f->set_data(-1);
      if (f->is_unbounded()) continue;
      const auto inside = interiorPoint(f);
      if (!inside) continue;
      const Vec3 sample = toWorld(*inside);
      if (!containsPoint(outline, frame.toLocal(sample))) continue;
      double twiceArea = 0;
      const auto ccbArea = [&](Arrangement::Ccb_halfedge_const_circulator first) {
        double sum = 0;
        auto c = first;
        do {
          const Vec2 a = localOf(c->source()), b = localOf(c->target());
          sum += a.x * b.y - b.x * a.y;
        } while (++c != first);
        return sum;
      };
      twiceArea += ccbArea(f->outer_ccb());
      for (auto h = f->holes_begin(); h != f->holes_end(); ++h) twiceArea += ccbArea(*h);
      f->set_data(int(faces.size()));
      faces.push_back({int(faces.size()), sample, twiceArea / 2});
      faceHandles.push_back(f);
    }
  }
};

ReceiverMesh::ReceiverMesh(const WorldPolygon& receiver) : impl_(std::make_unique<Impl>()) {
  impl_->receiver = receiver.id;
  impl_->plane = receiver.plane;
  impl_->frame = PlaneFrame::fromPlane(receiver.plane, receiver.vertices[0]);
  for (const Vec3& v : receiver.vertices) impl_->outline.push_back(impl_->frame.toLocal(v));
  std::vector<Traits::Curve_2>& boundary = impl_->boundary;
  for (size_t i = 0; i < receiver.vertices.size(); ++i) {
    const Point a = impl_->toPoint(receiver.vertices[i]);
    const Point b = impl_->toPoint(receiver.vertices[(i + 1) % receiver.vertices.size()]);
    if (a != b) boundary.push_back(Traits::Curve_2(SegmentTraits::Curve_2(a, b), kBoundary));
  }
  CGAL::insert(impl_->arrangement, boundary.begin(), boundary.end());
  impl_->indexFaces();
}

ReceiverMesh::~ReceiverMesh() = default;
ReceiverMesh::ReceiverMesh(ReceiverMesh&&) noexcept = default;
ReceiverMesh& ReceiverMesh::operator=(ReceiverMesh&&) noexcept = default;

PolygonId ReceiverMesh::receiver() const {
  return impl_->receiver;
}

namespace {

struct Piece {
  Point a, b;
  SurfaceId surface;
  bool isOutline;
  bool isJoined = false;  // shares an endpoint exactly with another piece (a polyline's joint)
};

// Groups the pieces lying within `tolerance` of one line and moves each exactly onto the line of
// its group's reference (an outline edge if one is in the group, else the longest piece): the
// projection of its endpoints onto that line, in exact arithmetic.
void snapNearlyCollinear(std::vector<Piece>& pieces, double tolerance) {
  struct Line {
    double angle, offset, length;
    size_t index;
  };
  std::vector<Line> lines;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const double ax = CGAL::to_double(pieces[i].a.x()), ay = CGAL::to_double(pieces[i].a.y());
    double dx = CGAL::to_double(pieces[i].b.x()) - ax, dy = CGAL::to_double(pieces[i].b.y()) - ay;
    const double length = std::hypot(dx, dy);
    if (length == 0) continue;
    dx /= length;
    dy /= length;
    // The line's direction modulo pi, measured from a direction no scene is likely to be aligned
    // with, so that no family of parallel lines straddles the wrap; an odd multiple of pi taken
    // off flips the direction, which keeps the offset's sign consistent within a family.
    constexpr double kSkew = 0.3217;
    double angle = std::atan2(dy, dx) - kSkew;
    const long turns = std::lround(std::floor(angle / M_PI));
    angle -= double(turns) * M_PI;
    if (turns % 2 != 0) {
      dx = -dx;
      dy = -dy;
    }
    lines.push_back({angle, dx * ay - dy * ax, length, i});
  }
  std::sort(lines.begin(), lines.end(),
            [](const Line& x, const Line& y) { return x.angle < y.angle; });
  // The group's reference: an outline edge if one is in it (input geometry), else the longest.
  const auto better = [&](const Line& x, const Line& y) {
    if (pieces[x.index].isOutline != pieces[y.index].isOutline) return pieces[x.index].isOutline;
    return x.length > y.length;
  };
  constexpr double kAngle = 1e-9;
  for (size_t begin = 0; begin < lines.size();) {
    size_t end = begin + 1;
    while (end < lines.size() && lines[end].angle - lines[end - 1].angle <= kAngle) ++end;
    std::sort(lines.begin() + begin, lines.begin() + end,
              [](const Line& x, const Line& y) { return x.offset < y.offset; });
    for (size_t first = begin; first < end;) {
      size_t last = first + 1;
      while (last < end && lines[last].offset - lines[last - 1].offset <= tolerance) ++last;
      if (last - first > 1) {
        const size_t reference = size_t(
            std::min_element(lines.begin() + first, lines.begin() + last, better) - lines.begin());
        const Point a = pieces[lines[reference].index].a, b = pieces[lines[reference].index].b;
        const auto ab = b - a;
        const FT squared = ab * ab;
        const double norm = std::sqrt(CGAL::to_double(squared));
        const auto distance = [&](const Point& p) {
          const auto ap = p - a;
          return std::abs(CGAL::to_double(ab.x() * ap.y() - ab.y() * ap.x())) / norm;
        };
        const auto onLine = [&](const Point& p) { return a + ab * (((p - a) * ab) / squared); };
        for (size_t k = first; k < last; ++k) {
          Piece& piece = pieces[lines[k].index];
          // Moving a joined piece would open a gap at its joint (EEE polylines).
          if (k == reference || piece.isOutline || piece.isJoined) continue;
          // Both ends near the reference's line (a chain of offsets may drift).
          if (distance(piece.a) > 2 * tolerance || distance(piece.b) > 2 * tolerance) continue;
          const Point snappedA = onLine(piece.a), snappedB = onLine(piece.b);
          if (snappedA == snappedB) continue;
          piece.a = snappedA;
          piece.b = snappedB;
        }
      }
      first = last;
    }
    begin = end;
  }
}

}  // namespace

void ReceiverMesh::insert(const std::vector<DiscontinuitySegment>& segments, double snapTolerance) {
  std::vector<Piece> pieces;
  std::vector<const DiscontinuitySegment*> sources;  // the segment each piece comes from
  pieces.reserve(segments.size());
  std::map<std::array<double, 3>, int> ends;
  const auto key = [](const Vec3& p) { return std::array<double, 3>{p.x, p.y, p.z}; };
  for (const DiscontinuitySegment& s : segments) {
    const Point a = impl_->toPoint(s.p0), b = impl_->toPoint(s.p1);
    if (a == b) continue;
    pieces.push_back({a, b, s.surface, false});
    sources.push_back(&s);
    if (snapTolerance > 0) {
      ++ends[key(s.p0)];
      ++ends[key(s.p1)];
    }
  }
  if (snapTolerance > 0) {
    for (size_t k = 0; k < pieces.size(); ++k)
      pieces[k].isJoined = ends[key(sources[k]->p0)] > 1 || ends[key(sources[k]->p1)] > 1;
    for (const Traits::Curve_2& edge : impl_->boundary)
      pieces.push_back({edge.source(), edge.target(), kBoundary, true});
    snapNearlyCollinear(pieces, snapTolerance);
    std::erase_if(pieces, [](const Piece& p) { return p.isOutline; });
  }
  std::vector<Traits::Curve_2> curves;
  curves.reserve(pieces.size());
  for (const Piece& p : pieces)
    curves.push_back(Traits::Curve_2(SegmentTraits::Curve_2(p.a, p.b), p.surface));
  if (impl_->onlyBoundary && !curves.empty()) {
    // The first insertion rebuilds the arrangement from nothing, outline and segments in one
    // sweep: CGAL's sweep into a non-empty arrangement walks a new face's whole boundary each
    // time an edge closes one, quadratic on a floor crossed by thousands of EEE polyline pieces
    // (245 s for 55k segments on a 10k-polygon room's floor); the construction sweep is not.
    curves.insert(curves.end(), impl_->boundary.begin(), impl_->boundary.end());
    impl_->arrangement.clear();
    impl_->onlyBoundary = false;
  }
  CGAL::insert(impl_->arrangement, curves.begin(), curves.end());
  impl_->indexFaces();
}

void ReceiverMesh::renumberSurfaces(const std::map<SurfaceId, SurfaceId>& renamed) {
  if (renamed.empty()) return;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    const auto& data = e->curve().data();
    bool touched = false;
    Traits::Data_container names;
    for (SurfaceId id : data) {
      const auto it = renamed.find(id);
      touched = touched || it != renamed.end();
      names.insert(it == renamed.end() ? id : it->second);
    }
    if (touched) impl_->arrangement.modify_edge(e, Traits::X_monotone_curve_2(e->curve(), names));
  }
}

void ReceiverMesh::removeSurface(SurfaceId surface) {
  std::vector<Arrangement::Halfedge_handle> doomed;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    const auto& data = e->curve().data();
    if (std::find(data.begin(), data.end(), surface) == data.end()) continue;
    Traits::Data_container remaining = data;
    remaining.erase(surface);
    if (remaining.size() == 0) {
      doomed.push_back(e);
    } else {
      impl_->arrangement.modify_edge(e, Traits::X_monotone_curve_2(e->curve(), remaining));
    }
  }
  for (auto e : doomed) impl_->arrangement.remove_edge(e);
  impl_->indexFaces();
}

int ReceiverMesh::vertexCount() const {
  return int(impl_->arrangement.number_of_vertices());
}
int ReceiverMesh::edgeCount() const {
  return int(impl_->arrangement.number_of_edges());
}
const std::vector<MeshFace>& ReceiverMesh::faces() const {
  return impl_->faces;
}

std::optional<int> ReceiverMesh::locate(const Vec3& p) const {
  const auto result = impl_->locator.locate(impl_->toPoint(p));
  Arrangement::Face_const_handle face;
  if (const auto* f = boost::get<Arrangement::Face_const_handle>(&result)) {
    face = *f;
  } else if (const auto* h = boost::get<Arrangement::Halfedge_const_handle>(&result)) {
    face = (*h)->face()->data() >= 0 ? (*h)->face() : (*h)->twin()->face();
  } else if (const auto* v = boost::get<Arrangement::Vertex_const_handle>(&result)) {
    auto c = (*v)->incident_halfedges();
    const auto first = c;
    face = c->face();
    do {
      if (c->face()->data() >= 0) {
        face = c->face();
        break;
      }
    } while (++c != first);
  } else {
    return std::nullopt;
  }
  if (face->data() < 0) return std::nullopt;
  return face->data();
}

namespace {

// An edge's surfaces, sorted: the order in which the arrangement merged overlapping curves' names
// is not a function of the segments alone (a mesh an update kept and one built again from the
// same segments listed them in different orders).
std::vector<SurfaceId> sortedSurfaces(const Traits::Data_container& data) {
  std::vector<SurfaceId> surfaces(data.begin(), data.end());
  std::sort(surfaces.begin(), surfaces.end());
  return surfaces;
}

}  // namespace

std::vector<std::pair<std::pair<Vec3, Vec3>, std::vector<SurfaceId>>> ReceiverMesh::edges() const {
  std::vector<std::pair<std::pair<Vec3, Vec3>, std::vector<SurfaceId>>> out;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    out.push_back({{impl_->worldOf(e->source()), impl_->worldOf(e->target())},
                   sortedSurfaces(e->curve().data())});
  }
  return out;
}

std::vector<Vec3> ReceiverMesh::vertexPositions() const {
  std::vector<Vec3> out;
  for (auto v = impl_->arrangement.vertices_begin(); v != impl_->arrangement.vertices_end(); ++v)
    out.push_back(impl_->worldOf(v));
  return out;
}

std::vector<Polygon3> ReceiverMesh::faceBoundary(int face) const {
  std::vector<Polygon3> cycles;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  const auto cycle = [&](Arrangement::Ccb_halfedge_const_circulator first) {
    Polygon3 out;
    auto c = first;
    do out.push_back(impl_->worldOf(c->source()));
    while (++c != first);
    cycles.push_back(std::move(out));
  };
  if (f->has_outer_ccb()) cycle(f->outer_ccb());
  for (auto h = f->holes_begin(); h != f->holes_end(); ++h) cycle(*h);
  return cycles;
}

std::vector<std::pair<Vec3, Vec3>> ReceiverMesh::faceBoundarySegments(int face) const {
  std::vector<std::pair<Vec3, Vec3>> segments;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  const auto cycle = [&](Arrangement::Ccb_halfedge_const_circulator first) {
    auto c = first;
    do
      if (c->twin()->face() != f)  // antennas separate the face from itself
        segments.push_back({impl_->worldOf(c->source()), impl_->worldOf(c->target())});
    while (++c != first);
  };
  if (f->has_outer_ccb()) cycle(f->outer_ccb());
  for (auto h = f->holes_begin(); h != f->holes_end(); ++h) cycle(*h);
  return segments;
}

std::vector<FaceCrossing> ReceiverMesh::faceCrossings() const {
  std::vector<FaceCrossing> crossings;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    const int left = e->face()->data(), right = e->twin()->face()->data();
    if (left < 0 || right < 0 || left == right) continue;
    crossings.push_back({left, right, sortedSurfaces(e->curve().data())});
  }
  return crossings;
}

const PlaneFrame& ReceiverMesh::frame() const {
  return impl_->frame;
}

size_t ReceiverMesh::memoryBytes() const {
  // DCEL records plus the exact coordinates' lazy representations, estimated per record.
  const auto& a = impl_->arrangement;
  return sizeof(Impl) + a.number_of_vertices() * 96 + a.number_of_halfedges() * 120 +
         a.number_of_faces() * 64 + impl_->faces.capacity() * sizeof(MeshFace);
}

}  // namespace penumbra
