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
#include <tuple>
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

  using Cycle = std::vector<Arrangement::Halfedge_const_handle>;
  // A boundary cycle of a face as its halfedges, starting where the sequence of its vertices'
  // rounded coordinates is lexicographically least: a function of the cycle's geometry alone, not
  // of the order in which the arrangement was built (an update's edited mesh and one built again
  // from the same segments list the same cycle from the same vertex).
  Cycle canonicalCycle(Arrangement::Ccb_halfedge_const_circulator first) const {
    Cycle cycle;
    auto c = first;
    do cycle.push_back(c);
    while (++c != first);
    const size_t n = cycle.size();
    const auto key = [&](size_t i) {
      const Vec2 q = localOf(cycle[i % n]->source());
      return std::pair{q.x, q.y};
    };
    size_t best = 0;
    for (size_t start = 1; start < n; ++start) {
      if (key(start) > key(best)) continue;
      // Equal first vertices (an antenna's base is visited twice): compare the rotations.
      size_t k = 0;
      while (k < n && key(start + k) == key(best + k)) ++k;
      if (k < n && key(start + k) < key(best + k)) best = start;
    }
    std::rotate(cycle.begin(), cycle.begin() + std::ptrdiff_t(best), cycle.end());
    return cycle;
  }
  // The face's boundary cycles, outer first, then the holes ordered by their canonical vertex
  // sequences.
  std::vector<Cycle> cyclesOf(Arrangement::Face_const_handle f) const {
    std::vector<Cycle> cycles;
    if (f->has_outer_ccb()) cycles.push_back(canonicalCycle(f->outer_ccb()));
    const size_t holesFrom = cycles.size();
    for (auto h = f->holes_begin(); h != f->holes_end(); ++h) cycles.push_back(canonicalCycle(*h));
    std::sort(cycles.begin() + std::ptrdiff_t(holesFrom), cycles.end(),
              [&](const Cycle& a, const Cycle& b) {
                return std::lexicographical_compare(
                    a.begin(), a.end(), b.begin(), b.end(), [&](auto x, auto y) {
                      const Vec2 p = localOf(x->source()), q = localOf(y->source());
                      return std::pair{p.x, p.y} < std::pair{q.x, q.y};
                    });
              });
    return cycles;
  }

  // A point strictly inside face f, as far from its boundary as a cheap search finds: on the
  // vertical line through the middle of every slab between consecutive distinct vertex abscissae,
  // the boundary crossings alternate in and out of the face; take the middle of the inside
  // interval that maximizes min(interval length, slab width), so that the point is away from the
  // boundary both across and along the line. Faces of a discontinuity mesh can be slivers beside
  // long ones (nearly coincident events, slabs a few ulps wide), and a sample near an edge would
  // label the big face with a neighbour's backprojection. Slab and interval are chosen in
  // floating point; the point is constructed exactly.
  std::optional<Point> interiorPoint(Arrangement::Face_const_handle f) const {
    // In canonical order, and every sort below stable or total: the point is a function of the
    // face's geometry alone.
    std::vector<Arrangement::Halfedge_const_handle> boundary;
    for (const Cycle& cycle : cyclesOf(f))
      for (auto h : cycle)
        if (h->twin()->face() != f) boundary.push_back(h);  // antennas bound nothing
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
    std::stable_sort(xs.begin(), xs.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
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
      std::stable_sort(slabs.begin(), slabs.end(),
                       [&](size_t a, size_t b) { return width(a) > width(b); });
      slabs.resize(64);
    }
    std::vector<Candidate> candidates;
    for (size_t k : slabs) {
      const std::vector<double> ys = crossings(xs[k].first + 0.5 * width(k));
      for (size_t i = 0; i + 1 < ys.size(); i += 2)
        candidates.push_back({std::min(ys[i + 1] - ys[i], width(k)), k, i});
    }
    std::stable_sort(candidates.begin(), candidates.end(),
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
      // Summed over the canonical cycles: floating-point sums depend on their order.
      double twiceArea = 0;
      for (const Cycle& cycle : cyclesOf(f)) {
        double sum = 0;
        for (auto h : cycle) {
          const Vec2 a = localOf(h->source()), b = localOf(h->target());
          sum += a.x * b.y - b.x * a.y;
        }
        twiceArea += sum;
      }
      faces.push_back({0, sample, twiceArea / 2});
      faceHandles.push_back(f);
    }
    // Indexed in the order of their sample points: distinct faces have distinct samples (each
    // strictly inside its face), so the order is the geometry's, not the arrangement's history.
    std::vector<size_t> order(faces.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    const auto sampleKey = [&](size_t k) {
      const Vec3& q = faces[k].samplePoint;
      return std::array<double, 3>{q.x, q.y, q.z};
    };
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return sampleKey(a) < sampleKey(b); });
    std::vector<MeshFace> sortedFaces;
    std::vector<Arrangement::Face_const_handle> sortedHandles;
    for (size_t k : order) {
      sortedFaces.push_back({int(sortedFaces.size()), faces[k].samplePoint, faces[k].area});
      sortedHandles.push_back(faceHandles[k]);
      arrangement.non_const_handle(faceHandles[k])->set_data(int(sortedHandles.size()) - 1);
    }
    faces = std::move(sortedFaces);
    faceHandles = std::move(sortedHandles);
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

bool ReceiverMesh::isInside(const Vec3& p, int face) const {
  const auto result = impl_->locator.locate(impl_->toPoint(p));
  const auto* f = boost::get<Arrangement::Face_const_handle>(&result);
  return f && (*f)->data() == face;
}

std::optional<int> ReceiverMesh::locate(const Vec3& p) const {
  const auto result = impl_->locator.locate(impl_->toPoint(p));
  Arrangement::Face_const_handle face;
  if (const auto* f = boost::get<Arrangement::Face_const_handle>(&result)) {
    face = *f;
  } else if (const auto* h = boost::get<Arrangement::Halfedge_const_handle>(&result)) {
    // On an edge: the inside face of lower index (which halfedge of the pair the locator returns
    // depends on the arrangement's history).
    const int left = (*h)->face()->data(), right = (*h)->twin()->face()->data();
    if (left < 0 && right < 0) return std::nullopt;
    if (left < 0 || right < 0) return std::max(left, right);
    return std::min(left, right);
  } else if (const auto* v = boost::get<Arrangement::Vertex_const_handle>(&result)) {
    // On a vertex: the inside face of lowest index around it.
    std::optional<int> lowest;
    auto c = (*v)->incident_halfedges();
    const auto first = c;
    do {
      const int index = c->face()->data();
      if (index >= 0 && (!lowest || index < *lowest)) lowest = index;
    } while (++c != first);
    return lowest;
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
    Vec3 a = impl_->worldOf(e->source()), b = impl_->worldOf(e->target());
    if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) std::swap(a, b);
    out.push_back({{a, b}, sortedSurfaces(e->curve().data())});
  }
  // Sorted by geometry: the arrangement's edge list is in the order of its history.
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) {
    const auto& [p, q] = x.first;
    const auto& [r, t] = y.first;
    return std::tie(p.x, p.y, p.z, q.x, q.y, q.z, x.second) <
           std::tie(r.x, r.y, r.z, t.x, t.y, t.z, y.second);
  });
  return out;
}

std::vector<Vec3> ReceiverMesh::vertexPositions() const {
  std::vector<Vec3> out;
  for (auto v = impl_->arrangement.vertices_begin(); v != impl_->arrangement.vertices_end(); ++v)
    out.push_back(impl_->worldOf(v));
  std::sort(out.begin(), out.end(), [](const Vec3& a, const Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  });
  return out;
}

std::vector<Polygon3> ReceiverMesh::faceBoundary(int face) const {
  std::vector<Polygon3> cycles;
  for (const Impl::Cycle& cycle : impl_->cyclesOf(impl_->faceHandles.at(face))) {
    Polygon3 out;
    out.reserve(cycle.size());
    for (auto h : cycle) out.push_back(impl_->worldOf(h->source()));
    cycles.push_back(std::move(out));
  }
  return cycles;
}

std::vector<std::pair<Vec3, Vec3>> ReceiverMesh::faceBoundarySegments(int face) const {
  std::vector<std::pair<Vec3, Vec3>> segments;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  for (const Impl::Cycle& cycle : impl_->cyclesOf(f))
    for (auto h : cycle)
      if (h->twin()->face() != f)  // antennas separate the face from itself
        segments.push_back({impl_->worldOf(h->source()), impl_->worldOf(h->target())});
  return segments;
}

std::vector<FaceCrossing> ReceiverMesh::faceCrossings() const {
  std::vector<FaceCrossing> crossings;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    const int left = e->face()->data(), right = e->twin()->face()->data();
    if (left < 0 || right < 0 || left == right) continue;
    crossings.push_back(
        {std::min(left, right), std::max(left, right), sortedSurfaces(e->curve().data())});
  }
  // In the order of the faces (canonical), not of the arrangement's edge list.
  std::sort(crossings.begin(), crossings.end(), [](const FaceCrossing& a, const FaceCrossing& b) {
    return std::tie(a.face, a.other, a.surfaces) < std::tie(b.face, b.other, b.surfaces);
  });
  return crossings;
}

std::vector<FaceCrossing> ReceiverMesh::crossingsNear(int face, const Vec3& p,
                                                      double radius) const {
  std::vector<FaceCrossing> crossings;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  const Vec2 q = impl_->frame.toLocal(p);
  for (const Impl::Cycle& cycle : impl_->cyclesOf(f))
    for (auto h : cycle) {
      const int other = h->twin()->face()->data();
      if (other < 0 || other == face) continue;
      const Vec2 a = impl_->localOf(h->source()), b = impl_->localOf(h->target());
      const Vec2 ab = b - a;
      const double length2 = dot(ab, ab);
      const double t = length2 > 0 ? std::clamp(dot(q - a, ab) / length2, 0.0, 1.0) : 0.0;
      const Vec2 off = q - (a + ab * t);
      if (std::sqrt(dot(off, off)) > radius) continue;
      crossings.push_back({face, other, sortedSurfaces(h->curve().data())});
    }
  std::sort(crossings.begin(), crossings.end(), [](const FaceCrossing& a, const FaceCrossing& b) {
    return std::tie(a.other, a.surfaces) < std::tie(b.other, b.surfaces);
  });
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
