#include "penumbra/dm/receiver_mesh.h"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_observer.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arr_trapezoid_ric_point_location.h>
#include <CGAL/Arr_walk_along_line_point_location.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "penumbra/base/hash_doubles.h"

namespace penumbra {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, SurfaceId>;
// Faces carry their index among the receiver's inside faces (-1 outside).
using Dcel = CGAL::Arr_face_extended_dcel<Traits, int>;
// A vertex's position rounded once from the exact coordinates.
struct VertexData {
  Vec2 local;
  Vec3 world;
};
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;
using Point = Kernel::Point_2;
using FT = Kernel::FT;
// Queries: the trapezoidal map (expected logarithmic; attached lazily, see
// Impl::attachedLocator). Not landmarks: CGAL 5.5's landmark walk never returned at an edge
// midpoint of a triangulated box (test DegeneratePointOnATriangulatedBoxIsLocated), and reads a
// flag it may leave unset (fuzz/README.md).
using PointLocation = CGAL::Arr_trapezoid_ric_point_location<Arrangement>;
// Edits locate with a walk: an attached map would rebuild itself after every edit.
using WalkLocation = CGAL::Arr_walk_along_line_point_location<Arrangement>;

// Where a piece comes from, in the doubles it was computed from: its segment's ends, and the ends
// of the segment (or outline edge) whose line it was snapped onto. Equal sources give the same
// exact piece (snapping is exact arithmetic on them), so an update compares pieces by source
// (and by their exact ends where only the line's doubles differ: ReceiverMesh::update).
struct PieceSource {
  std::array<double, 6> own{};
  std::array<double, 6> line{};  // all zero when not snapped
  bool snapped = false;
  auto operator<=>(const PieceSource&) const = default;
};

struct Piece {
  Point a, b;
  SurfaceId surface;
  bool isOutline;
  bool isJoined = false;  // shares an endpoint exactly with another piece (a polyline's joint)
  PieceSource source;
};

// What snapping did to a piece of segment `own` in a group whose reference is segment (or outline
// edge) `reference`: a function of the two alone, in a mesh's frame and tolerance (both fixed for
// the mesh), so a mesh keeps the outcomes of its last snappings for the next. An update snaps
// all of a receiver's pieces again, nearly all as the frame before did: on the 10,000-polygon
// room's floor (70,000 pieces) snapping took 70-130 ms of an edit, 30-35 ms with the outcomes kept.
struct SnapKey {
  std::array<double, 6> own, reference;
  bool operator==(const SnapKey&) const = default;  // zeros of either sign alike, as the points
};
struct SnapKeyHash {
  size_t operator()(const SnapKey& key) const {
    std::uint64_t hash = 0;
    for (const auto* half : {&key.own, &key.reference})
      for (double x : *half) hash = hashCombine(hash, x);
    return size_t(hash);
  }
};
struct SnapOutcome {
  Point a, b;
  bool moved = false;  // else the piece stays as it was (too far from the line, or degenerate)
};
using SnapMemo = std::unordered_map<SnapKey, SnapOutcome, SnapKeyHash>;

// A surface's pieces, as a run of a list of (surface, piece) sorted by surface and source
// (ReceiverMesh::update).
struct PieceGroup {
  SurfaceId surface;
  size_t from, to;  // its run in the list
  size_t hash;      // of its pieces' own segments, equal for equal groups
};
using PieceMember = std::pair<SurfaceId, const Piece*>;

// What the arrangement's edits changed since the faces were last indexed, as CGAL reports each
// elementary change to its observers: the faces whose boundary an edit touched (split, merged,
// an edge or a hole added or taken away, an edge split or merged on it) and the vertices it made.
// Every other face has exactly the boundary it had, so its index's sample and area stand: indexing
// computes only the touched faces again and passes over the others with one lookup each (it used
// to key every face of an edited mesh by its boundary's vertex serials; measured, the difference
// is within the machine's noise, the touched faces' interior points being most of the cost). The
// sweeps (aggregate insertion into a cleared arrangement) report no elementary changes: their
// callers mark everything.
class EditTracker : public CGAL::Arr_observer<Arrangement> {
 public:
  EditTracker(Arrangement& arrangement, std::unordered_map<const void*, VertexData>& vertexData)
      : CGAL::Arr_observer<Arrangement>(arrangement), vertexData_(vertexData) {}

  bool everything = true;
  std::unordered_set<const void*> faces;
  // The vertices made since, by address (a vertex removed since is dropped again).
  std::unordered_map<const void*, Vertex_handle> madeVertices;

  void reset() {
    everything = false;
    faces.clear();
    madeVertices.clear();
  }
  bool touched(Arrangement::Face_const_handle f) const { return everything || faces.count(&*f); }

  void after_clear() override { everything = true; }
  void after_assign() override { everything = true; }
  void after_create_vertex(Vertex_handle v) override {
    if (!everything) madeVertices[&*v] = v;
  }
  void before_remove_vertex(Vertex_handle v) override {
    if (v->is_isolated()) touch(v->face());
    madeVertices.erase(&*v);
    // Its address may be taken by a vertex made later: that one is indexed afresh.
    vertexData_.erase(&*v);
  }
  void after_modify_vertex(Vertex_handle v) override {
    if (v->is_isolated()) {
      touch(v->face());
      return;
    }
    auto c = v->incident_halfedges();
    const auto first = c;
    do touch(c->face());
    while (++c != first);
  }
  void after_create_edge(Halfedge_handle e) override { touchSides(e); }
  void after_split_edge(Halfedge_handle e1, Halfedge_handle e2) override {
    touchSides(e1);
    touchSides(e2);
  }
  void after_split_face(Face_handle f, Face_handle made, bool) override {
    touch(f);
    touch(made);
  }
  void after_split_outer_ccb(Face_handle f, Ccb_halfedge_circulator,
                             Ccb_halfedge_circulator) override {
    touch(f);
  }
  void after_split_inner_ccb(Face_handle f, Ccb_halfedge_circulator,
                             Ccb_halfedge_circulator) override {
    touch(f);
  }
  void after_add_outer_ccb(Ccb_halfedge_circulator h) override { touch(h->face()); }
  void after_add_inner_ccb(Ccb_halfedge_circulator h) override { touch(h->face()); }
  void before_add_isolated_vertex(Face_handle f, Vertex_handle) override { touch(f); }
  void after_merge_edge(Halfedge_handle e) override { touchSides(e); }
  void after_merge_face(Face_handle f) override { touch(f); }  // the face that stays
  void after_merge_outer_ccb(Face_handle f, Ccb_halfedge_circulator) override { touch(f); }
  void after_merge_inner_ccb(Face_handle f, Ccb_halfedge_circulator) override { touch(f); }
  void before_move_outer_ccb(Face_handle from, Face_handle to, Ccb_halfedge_circulator) override {
    touch(from);
    touch(to);
  }
  void before_move_inner_ccb(Face_handle from, Face_handle to, Ccb_halfedge_circulator) override {
    touch(from);
    touch(to);
  }
  void before_move_isolated_vertex(Face_handle from, Face_handle to, Vertex_handle) override {
    touch(from);
    touch(to);
  }
  void before_remove_edge(Halfedge_handle e) override { touchSides(e); }
  void after_remove_outer_ccb(Face_handle f) override { touch(f); }
  void after_remove_inner_ccb(Face_handle f) override { touch(f); }

 private:
  void touch(Face_handle f) {
    if (!everything) faces.insert(&*f);
  }
  void touchSides(Halfedge_handle e) {
    touch(e->face());
    touch(e->twin()->face());
  }
  std::unordered_map<const void*, VertexData>& vertexData_;
};

}  // namespace

struct ReceiverMesh::Impl {
  // The data of a bounded face with no double strictly inside it (inside faces have their index,
  // the others -1).
  static constexpr int kTooThin = -2;
  PolygonId receiver;
  PlaneFrame frame;
  Plane plane;
  Polygon2 outline;
  Arrangement arrangement;
  // Made on the first query after an edit: made, it rebuilds after every change to the
  // arrangement, and an update or a build that nobody queries would pay for that on every
  // receiver it touches. Made anew rather than detached and attached again: CGAL 5.5's
  // trapezoidal map allocates its traits at every attach and frees them only when destroyed (a
  // leak per edited receiver and frame). One query at a time: the map remembers its last answers
  // and exact numbers cache lazily (the engine's queries run on one thread, see final_gather.cpp).
  mutable std::optional<PointLocation> locator;
  void detachLocator() { locator.reset(); }
  const PointLocation& attachedLocator() const {
    if (!locator) locator.emplace(arrangement);
    return *locator;
  }
  std::vector<MeshFace> faces;
  // The receiver's outline, and whether the arrangement still holds nothing else (see insert()).
  std::vector<Traits::Curve_2> boundary;
  std::vector<std::array<double, 6>> boundarySources;  // each outline edge's ends
  // The tiling lines (kTile): in every build, never snapped to nor removed.
  std::vector<Traits::Curve_2> tiles;
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
  // Each vertex's data by its address: entries are added when a vertex is first indexed and
  // erased when an update removes the vertex (whose address a later vertex may take).
  std::unordered_map<const void*, VertexData> vertices;
  // Declared after what it erases from (and destroyed before it).
  EditTracker edits{arrangement, vertices};
  const VertexData& dataOf(Arrangement::Vertex_const_handle v) const { return vertices.at(&*v); }
  Vec3 worldOf(Arrangement::Vertex_const_handle v) const { return dataOf(v).world; }
  Vec2 localOf(Arrangement::Vertex_const_handle v) const { return dataOf(v).local; }
  // The pieces the arrangement holds (snapped, outline left out), for the next update's diff.
  std::vector<Piece> pieces;
  // The pieces grouped by surface, as the last update grouped them (its new pieces, now
  // `pieces`, which the members point into) for the next one, where `groupsCurrent`: anything
  // else that changes the pieces or their surfaces clears it. Grouping sorts every piece: a
  // tenth of the edit of a floor of 70,000 pieces.
  std::vector<PieceGroup> groups;
  std::vector<PieceMember> groupMembers;
  bool groupsCurrent = false;
  // Edges carry slots, each naming one surface here: a surface's id is its position in the
  // frame's list, which shifts from frame to frame, and renaming it rewrites one entry of this
  // table instead of every edge it lies on. The fixed curves have slots of their own, set by
  // clearSlots().
  static constexpr int kOutlineSlot = 0, kTileSlot = 1;
  std::vector<SurfaceId> slotSurface;
  std::unordered_map<SurfaceId, int> slotOf;
  std::vector<int> freeSlots;
  int slotFor(SurfaceId surface) {
    const auto [it, added] = slotOf.try_emplace(surface, 0);
    if (added) {
      if (freeSlots.empty()) {
        it->second = int(slotSurface.size());
        slotSurface.push_back(surface);
      } else {
        it->second = freeSlots.back();
        freeSlots.pop_back();
        slotSurface[size_t(it->second)] = surface;
      }
    }
    return it->second;
  }
  void clearSlots() {
    slotSurface = {kBoundary, kTile};
    slotOf = {{kBoundary, kOutlineSlot}, {kTile, kTileSlot}};
    freeSlots.clear();
  }
  // Renames surfaces (old id to new, one to one; a permutation is fine) and forgets `dropped`,
  // whose slots no edge carries any more.
  void renameSlots(const ReceiverMesh::Renaming& renamed, const std::set<SurfaceId>& dropped) {
    std::vector<std::pair<int, SurfaceId>> moves;
    for (const auto& [from, to] : renamed)
      if (const auto it = slotOf.find(from); it != slotOf.end()) {
        moves.push_back({it->second, to});
        slotOf.erase(it);
      }
    for (SurfaceId id : dropped)
      if (const auto it = slotOf.find(id); it != slotOf.end()) {
        freeSlots.push_back(it->second);
        slotOf.erase(it);
      }
    for (const auto& [slot, to] : moves) {
      slotSurface[size_t(slot)] = to;
      slotOf[to] = slot;
    }
  }
  Traits::Curve_2 curveOf(const Piece& p) {
    return Traits::Curve_2(SegmentTraits::Curve_2(p.a, p.b), slotFor(p.surface));
  }
  // An edge's surfaces, sorted: the order in which the arrangement merged overlapping curves'
  // names is not a function of the segments alone (a mesh an update kept and one built again
  // from the same segments listed them in different orders), nor are the slots.
  std::vector<SurfaceId> sortedSurfaces(const Traits::Data_container& data) const {
    std::vector<SurfaceId> surfaces;
    for (int slot : data) surfaces.push_back(slotSurface[size_t(slot)]);
    std::sort(surfaces.begin(), surfaces.end());
    return surfaces;
  }
  // The segments as pieces in the receiver's frame, nearly collinear ones snapped (see insert()).
  std::vector<Piece> piecesOf(const std::vector<DiscontinuitySegment>& segments,
                              double snapTolerance);
  // The outcomes of the last snappings, and the tolerance they were found with.
  SnapMemo snapped;
  double snappedWith = 0;
  // An inside face's sample, area and index.
  struct IndexedFace {
    Vec3 sample;
    double area;
    int index;
  };
  // The faces an edit may destroy (around the edges it removes or changes), as they were: an
  // edit that takes a piece out and puts the same piece back recreates them with new vertices,
  // and indexFaces recognises them by their geometry (exact boundary points, canonical order).
  struct FormerFace {
    IndexedFace face;
    std::vector<std::vector<Point>> cycles;
  };
  std::vector<FormerFace> former;
  // Remembers the inside faces among `faceList` as former faces (replacing those remembered).
  template <typename Faces>
  void rememberFaces(const Faces& faceList) {
    former.clear();
    for (Arrangement::Face_const_handle f : faceList) {
      if (f->data() < 0) continue;
      const MeshFace& face = faces[size_t(f->data())];
      former.push_back({{face.samplePoint, face.area, face.index}, exactCycles(cyclesOf(f))});
    }
  }
  // The arrangement built from nothing in one sweep: `curves` and the receiver's outline (CGAL's
  // sweep into a non-empty arrangement walks a new face's whole boundary each time an edge closes
  // one, quadratic on a floor crossed by thousands of EEE polyline pieces: 245 s for 55k segments
  // on a 10k-polygon room's floor; the construction sweep is not). Vertex data and cached faces
  // go with the old arrangement.
  void sweep(std::vector<Traits::Curve_2> curves) {
    detachLocator();
    curves.insert(curves.end(), boundary.begin(), boundary.end());
    curves.insert(curves.end(), tiles.begin(), tiles.end());
    arrangement.clear();
    vertices.clear();
    CGAL::insert(arrangement, curves.begin(), curves.end());
    fitCurvesToEdges();
    onlyBoundary = false;
  }
  // CGAL 5.5's sweep can leave an edge carrying a longer curve than its own: measured, where a
  // contact line lying along an outline edge ended inside it, the outline edge was split there but
  // one part kept the whole outline segment as its curve, in some heap layouts and not in others
  // (dm_random_moves, seed 62, move 804). An update that later took the contact line away could
  // not merge the two parts again (their curves no longer meet at the vertex) and left a vertex a
  // fresh build lacks; an insertion's zone walk reads the curves too. Each edge's curve is made the
  // segment between its own vertices (the same line, the same surfaces).
  void fitCurvesToEdges() {
    // Most curve ends share their representation with the vertex: no exact comparison then.
    const auto identical = [](const Point& a, const Point& b) {
      return static_cast<const CGAL::Handle&>(a).identical(b);
    };
    for (auto e = arrangement.edges_begin(); e != arrangement.edges_end(); ++e) {
      const Point &p = e->source()->point(), &q = e->target()->point();
      const auto& curve = e->curve();
      const Point &s = curve.source(), &t = curve.target();
      if ((identical(s, p) && identical(t, q)) || (identical(s, q) && identical(t, p))) continue;
      if ((s == p && t == q) || (s == q && t == p)) continue;
      arrangement.modify_edge(
          e, Traits::X_monotone_curve_2(SegmentTraits::X_monotone_curve_2(p, q), curve.data()));
    }
  }

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
    std::vector<std::pair<double, double>> keys(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec2 q = localOf(cycle[i]->source());
      keys[i] = {q.x, q.y};
    }
    const auto key = [&](size_t i) { return keys[i % n]; };
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

  // The exact points of `cycles` (a face's cyclesOf).
  static std::vector<std::vector<Point>> exactCycles(const std::vector<Cycle>& cycles) {
    std::vector<std::vector<Point>> out;
    for (const Cycle& cycle : cycles) {
      out.emplace_back();
      for (auto h : cycle) out.back().push_back(h->source()->point());
    }
    return out;
  }

  // Does q lie strictly inside face f (not on its boundary), decided by exact predicates on f's
  // boundary alone (crossing parity of a ray to the right, half-open in y)? Point location would
  // answer the same in principle; measured, CGAL's landmarks answered differently for a point
  // within an ulp of a sliver in two identical arrangements built by different histories.
  bool strictlyInside(Arrangement::Face_const_handle f, const Point& q) const {
    // An edge wholly above or wholly below q (certain from the intervals that bound its ends'
    // exact ordinates) neither crosses the ray nor holds q: only the others need exact tests.
    const CGAL::Interval_nt<false> qy = q.approx().y();
    const auto beside = [&](const Point& a, const Point& b) {
      const CGAL::Interval_nt<false> ay = a.approx().y(), by = b.approx().y();
      return (ay.sup() < qy.inf() && by.sup() < qy.inf()) ||
             (ay.inf() > qy.sup() && by.inf() > qy.sup());
    };
    const auto parity = [&](Arrangement::Ccb_halfedge_const_circulator first) -> int {
      bool inside = false;
      auto c = first;
      do {
        const Point& a = c->source()->point();
        const Point& b = c->target()->point();
        if (beside(a, b)) continue;
        const CGAL::Orientation turn = CGAL::orientation(a, b, q);
        if (turn == CGAL::COLLINEAR && CGAL::collinear_are_ordered_along_line(a, q, b)) return 0;
        const bool aBelow = CGAL::compare_y(a, q) != CGAL::LARGER;
        const bool bBelow = CGAL::compare_y(b, q) != CGAL::LARGER;
        if (aBelow && !bBelow && turn == CGAL::LEFT_TURN) inside = !inside;   // upward, q left
        if (!aBelow && bBelow && turn == CGAL::RIGHT_TURN) inside = !inside;  // downward, q right
      } while (++c != first);
      return inside ? 1 : -1;
    };
    if (!f->has_outer_ccb() || parity(f->outer_ccb()) != 1) return false;
    for (auto h = f->holes_begin(); h != f->holes_end(); ++h)
      if (parity(*h) != -1) return false;
    return true;
  }

  // A point strictly inside face f, as far from its boundary as a cheap search finds: on the
  // vertical line through the middle of every slab between consecutive distinct vertex abscissae,
  // the boundary crossings alternate in and out of the face; take the middle of the inside
  // interval that maximizes min(interval length, slab width), so that the point is away from the
  // boundary both across and along the line. Faces of a discontinuity mesh can be slivers beside
  // long ones (nearly coincident events, slabs a few ulps wide), and a sample near an edge would
  // label the big face with a neighbour's backprojection. Slab and interval are chosen in
  // floating point; the point too where the exact test finds it strictly inside (else it is
  // constructed exactly). Returned in world coordinates, as samples are used.
  // `cycles` are f's (cyclesOf).
  std::optional<Vec3> interiorPoint(Arrangement::Face_const_handle f,
                                    const std::vector<Cycle>& cycles) const {
    // In canonical order, and every sort below stable or total: the point is a function of the
    // face's geometry alone.
    std::vector<Arrangement::Halfedge_const_handle> boundary;
    for (const Cycle& cycle : cycles)
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
    // First the candidates computed in floating point from the rounded vertices (a face wider
    // than a few ulps holds them, and the exact test says so); an exact construction only where
    // none is strictly inside.
    for (size_t c = 0; c < candidates.size() && c < 8; ++c) {
      const double x = xs[candidates[c].slab].first + 0.5 * width(candidates[c].slab);
      const std::vector<double> ys = crossings(x);
      const size_t i = candidates[c].interval;
      if (ys.size() < i + 2) continue;
      const Vec3 sample = frame.toWorld(Vec2{x, 0.5 * (ys[i] + ys[i + 1])});
      if (strictlyInside(f, toPoint(sample))) return sample;
    }
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
      if (strictlyInside(f, toPoint(toWorld(inside)))) return toWorld(inside);
    }
    if (fallback) return toWorld(*fallback);
    return std::nullopt;
  }

  // Indexes the inside faces, each with its sample and area (kept from the last indexing for a
  // face no edit touched since, see EditTracker); gives each face's index at the last indexing,
  // or -1 for a face that was not there.
  std::vector<int> indexFaces() {
    const auto indexVertex = [&](Arrangement::Vertex_const_handle v) {
      const auto [it, added] = vertices.try_emplace(&*v);
      if (!added) return;
      it->second.local = rounded(v->point());
      it->second.world = frame.toWorld(it->second.local);
    };
    if (edits.everything) {
      for (auto v = arrangement.vertices_begin(); v != arrangement.vertices_end(); ++v)
        indexVertex(v);
    } else {
      for (const auto& [address, v] : edits.madeVertices) indexVertex(v);
    }
    struct Found {
      Arrangement::Face_const_handle handle;
      IndexedFace face;  // index: the previous one
    };
    std::vector<Found> found;  // the touched inside faces
    std::map<std::array<double, 3>, size_t> formerBySample;
    for (size_t k = 0; k < former.size(); ++k) {
      const Vec3& q = former[k].face.sample;
      formerBySample.emplace(std::array<double, 3>{q.x, q.y, q.z}, k);
    }
    // The untouched inside faces by their index at the last indexing (null where none).
    std::vector<Arrangement::Face_const_handle> kept(faces.size());
    for (auto f = arrangement.faces_begin(); f != arrangement.faces_end(); ++f) {
      if (f->is_unbounded()) {
        f->set_data(-1);
        continue;
      }
      if (!edits.touched(f)) {
        if (f->data() >= 0) kept[size_t(f->data())] = f;
        continue;
      }
      f->set_data(-1);
      const std::vector<Cycle> cycles = cyclesOf(f);
      const auto inside = interiorPoint(f, cycles);
      if (!inside) {  // too thin for a sample in doubles: located as its neighbours' boundary
        f->set_data(kTooThin);
        continue;
      }
      const Vec3 sample = *inside;
      if (!containsPoint(outline, frame.toLocal(sample))) continue;
      // Summed over the canonical cycles: floating-point sums depend on their order.
      double twiceArea = 0;
      for (const Cycle& cycle : cycles) {
        double sum = 0;
        for (auto h : cycle) {
          const Vec2 a = localOf(h->source()), b = localOf(h->target());
          sum += a.x * b.y - b.x * a.y;
        }
        twiceArea += sum;
      }
      int previousIndex = -1;
      if (const auto was = formerBySample.find({sample.x, sample.y, sample.z});
          was != formerBySample.end()) {
        const FormerFace& face = former[was->second];
        if (face.face.area == twiceArea / 2 && face.cycles == exactCycles(cycles))
          previousIndex = face.face.index;
      }
      found.push_back({f, {sample, twiceArea / 2, previousIndex}});
    }
    former.clear();
    // Indexed in the order of their sample points: distinct faces have distinct samples (each
    // strictly inside its face), so the order is the geometry's, not the arrangement's history.
    const auto sampleKey = [](const Found& x) {
      return std::array<double, 3>{x.face.sample.x, x.face.sample.y, x.face.sample.z};
    };
    // Slivers a few ulps wide can share a rounded sample: then their boundaries decide.
    const auto boundaryKey = [&](const Found& x) {
      std::vector<double> key;
      for (const Cycle& cycle : cyclesOf(x.handle)) {
        for (auto h : cycle) {
          key.push_back(localOf(h->source()).x);
          key.push_back(localOf(h->source()).y);
        }
        key.push_back(std::numeric_limits<double>::infinity());
      }
      key.push_back(x.face.area);
      return key;
    };
    const auto before = [&](const Found& x, const Found& y) {
      if (sampleKey(x) != sampleKey(y)) return sampleKey(x) < sampleKey(y);
      return boundaryKey(x) < boundaryKey(y);
    };
    std::sort(found.begin(), found.end(), before);
    // The untouched faces are in that order already (it is a function of each face's boundary):
    // merged with the touched ones.
    std::vector<Found> untouched;
    for (size_t index = 0; index < faces.size(); ++index)
      if (kept[index] != Arrangement::Face_const_handle())
        untouched.push_back(
            {kept[index], {faces[index].samplePoint, faces[index].area, int(index)}});
    std::vector<Found> all;
    all.reserve(found.size() + untouched.size());
    std::merge(untouched.begin(), untouched.end(), found.begin(), found.end(),
               std::back_inserter(all), before);
    faces.clear();
    faceHandles.clear();
    std::vector<int> previous;
    previous.reserve(all.size());
    for (const Found& x : all) {
      const int index = int(faces.size());
      faces.push_back({index, x.face.sample, x.face.area});
      faceHandles.push_back(x.handle);
      previous.push_back(x.face.index);
      arrangement.non_const_handle(x.handle)->set_data(index);
    }
    edits.reset();
    return previous;
  }
};

ReceiverMesh::ReceiverMesh(const WorldPolygon& receiver, double tileSize)
    : impl_(std::make_unique<Impl>()) {
  impl_->clearSlots();
  impl_->receiver = receiver.id;
  impl_->plane = receiver.plane;
  impl_->frame = PlaneFrame::fromPlane(receiver.plane, receiver.vertices[0]);
  for (const Vec3& v : receiver.vertices) impl_->outline.push_back(impl_->frame.toLocal(v));
  std::vector<Traits::Curve_2>& boundary = impl_->boundary;
  for (size_t i = 0; i < receiver.vertices.size(); ++i) {
    const Point a = impl_->toPoint(receiver.vertices[i]);
    const Point b = impl_->toPoint(receiver.vertices[(i + 1) % receiver.vertices.size()]);
    if (a == b) continue;
    boundary.push_back(Traits::Curve_2(SegmentTraits::Curve_2(a, b), Impl::kOutlineSlot));
    const Vec3 &p = receiver.vertices[i],
               &q = receiver.vertices[(i + 1) % receiver.vertices.size()];
    impl_->boundarySources.push_back({p.x, p.y, p.z, q.x, q.y, q.z});
  }
  if (tileSize > 0) {
    Vec2 low{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    Vec2 high = low * -1.0;
    for (const Vec2& q : impl_->outline) {
      low = {std::min(low.x, q.x), std::min(low.y, q.y)};
      high = {std::max(high.x, q.x), std::max(high.y, q.y)};
    }
    // Lines across axis `k` of the frame (x = const for k = 0), spanning the other axis.
    for (int k = 0; k < 2; ++k) {
      const double from = k == 0 ? low.x : low.y, to = k == 0 ? high.x : high.y;
      const double acrossFrom = k == 0 ? low.y : low.x, acrossTo = k == 0 ? high.y : high.x;
      const int tilesAlong = int(std::floor((to - from) / tileSize));
      for (int i = 1; i < tilesAlong; ++i) {
        const double at = from + (to - from) * double(i) / double(tilesAlong);
        const Point a = k == 0 ? Point(at, acrossFrom) : Point(acrossFrom, at);
        const Point b = k == 0 ? Point(at, acrossTo) : Point(acrossTo, at);
        impl_->tiles.push_back(Traits::Curve_2(SegmentTraits::Curve_2(a, b), Impl::kTileSlot));
      }
    }
  }
  std::vector<Traits::Curve_2> curves = boundary;
  curves.insert(curves.end(), impl_->tiles.begin(), impl_->tiles.end());
  CGAL::insert(impl_->arrangement, curves.begin(), curves.end());
  impl_->fitCurvesToEdges();
  impl_->indexFaces();
}

ReceiverMesh::~ReceiverMesh() = default;
ReceiverMesh::ReceiverMesh(ReceiverMesh&&) noexcept = default;
ReceiverMesh& ReceiverMesh::operator=(ReceiverMesh&&) noexcept = default;

PolygonId ReceiverMesh::receiver() const {
  return impl_->receiver;
}

namespace {

// A point's coordinates rounded as CGAL::to_double rounds them, without making a lazy number for
// each (Compute_x_2 allocates one: a fifth of snapping a floor's 70,000 pieces) where the point's
// interval is one double already, as for every point made from doubles.
std::array<double, 2> roundedCoordinates(const Point& p) {
  const auto& approx = p.approx();
  std::array<double, 2> r{};
  if (!CGAL::fit_in_double(approx.x(), r[0])) r[0] = CGAL::to_double(p.x());
  if (!CGAL::fit_in_double(approx.y(), r[1])) r[1] = CGAL::to_double(p.y());
  return r;
}

// Groups the pieces lying within `tolerance` of one line and moves each exactly onto the line of
// its group's reference (an outline edge if one is in the group, else the longest piece): the
// projection of its endpoints onto that line, in exact arithmetic.
void snapNearlyCollinear(std::vector<Piece>& pieces, double tolerance, SnapMemo& memo) {
  struct Line {
    double angle, offset, length;
    size_t index;
  };
  std::vector<Line> lines;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const auto [ax, ay] = roundedCoordinates(pieces[i].a);
    const auto [bx, by] = roundedCoordinates(pieces[i].b);
    double dx = bx - ax, dy = by - ay;
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
  // The group's reference: an outline edge if one is in it (input geometry), else the longest,
  // and of equal ones the first by its segment's doubles: never by the order of the inputs
  // (pieces of equal length abound in axis-aligned scenes, and which of two nearly collinear ones
  // is the reference moves the other).
  const auto better = [&](const Line& x, const Line& y) {
    if (pieces[x.index].isOutline != pieces[y.index].isOutline) return pieces[x.index].isOutline;
    if (x.length != y.length) return x.length > y.length;
    return pieces[x.index].source.own < pieces[y.index].source.own;
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
        const Piece& line = pieces[lines[reference].index];
        const Point a = line.a, b = line.b;
        const auto ab = b - a;
        std::optional<FT> squared;  // computed once a piece's outcome is not known
        double norm = 0;
        const auto distance = [&](const Point& p) {
          const auto ap = p - a;
          return std::abs(CGAL::to_double(ab.x() * ap.y() - ab.y() * ap.x())) / norm;
        };
        const auto onLine = [&](const Point& p) { return a + ab * (((p - a) * ab) / *squared); };
        const auto outcomeOf = [&](const Piece& piece) {
          if (!squared) {
            squared = ab * ab;
            norm = std::sqrt(CGAL::to_double(*squared));
          }
          // Both ends near the reference's line (a chain of offsets may drift).
          if (distance(piece.a) > 2 * tolerance || distance(piece.b) > 2 * tolerance)
            return SnapOutcome{};
          const Point snappedA = onLine(piece.a), snappedB = onLine(piece.b);
          if (snappedA == snappedB) return SnapOutcome{};
          return SnapOutcome{snappedA, snappedB, true};
        };
        for (size_t k = first; k < last; ++k) {
          Piece& piece = pieces[lines[k].index];
          // Moving a joined piece would open a gap at its joint (EEE polylines).
          if (k == reference || piece.isOutline || piece.isJoined) continue;
          SnapKey key{piece.source.own, line.source.own};
          const auto known = memo.find(key);
          const SnapOutcome& outcome = known != memo.end()
                                           ? known->second
                                           : memo.emplace(key, outcomeOf(piece)).first->second;
          if (!outcome.moved) continue;
          piece.a = outcome.a;
          piece.b = outcome.b;
          piece.source.line = line.source.own;
          piece.source.snapped = true;
        }
      }
      first = last;
    }
    begin = end;
  }
}

}  // namespace

std::vector<Piece> ReceiverMesh::Impl::piecesOf(const std::vector<DiscontinuitySegment>& segments,
                                                double snapTolerance) {
  std::vector<Piece> pieces;
  pieces.reserve(segments.size());
  // Every piece's ends with the piece, sorted by the end: a piece is joined where another one ends
  // at the same point, in a run of equal ends (a sorted list rather than a map of counts, which
  // allocated a node per end on every update).
  struct End {
    std::array<double, 3> at;
    size_t piece;
  };
  std::vector<End> ends;
  for (const DiscontinuitySegment& s : segments) {
    const Point a = toPoint(s.p0), b = toPoint(s.p1);
    if (a == b) continue;
    if (snapTolerance > 0) {
      ends.push_back({{s.p0.x, s.p0.y, s.p0.z}, pieces.size()});
      ends.push_back({{s.p1.x, s.p1.y, s.p1.z}, pieces.size()});
    }
    pieces.push_back({a, b, s.surface, false, false, {}});
    pieces.back().source.own = {s.p0.x, s.p0.y, s.p0.z, s.p1.x, s.p1.y, s.p1.z};
  }
  if (snapTolerance > 0) {
    std::sort(ends.begin(), ends.end(), [](const End& x, const End& y) { return x.at < y.at; });
    for (size_t first = 0; first < ends.size();) {
      size_t last = first + 1;
      while (last < ends.size() && ends[last].at == ends[first].at) ++last;
      if (last - first > 1)
        for (size_t k = first; k < last; ++k) pieces[ends[k].piece].isJoined = true;
      first = last;
    }
    for (size_t k = 0; k < boundary.size(); ++k) {
      pieces.push_back({boundary[k].source(), boundary[k].target(), kBoundary, true, false, {}});
      pieces.back().source.own = boundarySources[k];
    }
    // Outcomes no piece asks for any more are dropped all at once, when they would outnumber the
    // pieces (dropping each as it went out cost as much as finding it).
    if (snapTolerance != snappedWith || snapped.size() > 2 * pieces.size() + 1024) snapped.clear();
    snapNearlyCollinear(pieces, snapTolerance, snapped);
    snappedWith = snapTolerance;
    std::erase_if(pieces, [](const Piece& p) { return p.isOutline; });
  }
  return pieces;
}

void ReceiverMesh::insert(const std::vector<DiscontinuitySegment>& segments, double snapTolerance) {
  std::vector<Piece> pieces = impl_->piecesOf(segments, snapTolerance);
  std::vector<Traits::Curve_2> curves;
  curves.reserve(pieces.size());
  for (const Piece& p : pieces) curves.push_back(impl_->curveOf(p));
  // The first insertion builds the arrangement in one sweep (Impl::sweep).
  impl_->detachLocator();
  if (impl_->onlyBoundary && !curves.empty()) {
    impl_->sweep(std::move(curves));
  } else {
    // An aggregate insertion sweeps: it reports no elementary changes (EditTracker).
    impl_->edits.everything = true;
    CGAL::insert(impl_->arrangement, curves.begin(), curves.end());
    impl_->fitCurvesToEdges();
  }
  impl_->pieces.insert(impl_->pieces.end(), std::make_move_iterator(pieces.begin()),
                       std::make_move_iterator(pieces.end()));
  impl_->groupsCurrent = false;
  impl_->indexFaces();
}

std::vector<int> ReceiverMesh::update(const std::vector<DiscontinuitySegment>& segments,
                                      double snapTolerance, UpdateStats* stats) {
  Impl& m = *impl_;
  if (m.onlyBoundary) {
    insert(segments, snapTolerance);
    return std::vector<int>(m.faces.size(), -1);
  }
  std::vector<Piece> now = m.piecesOf(segments, snapTolerance);
  // Each surface's pieces by source, before and now; a surface now whose pieces are those of one
  // before (a surface's id is its position in the frame's list, which moves) takes its edges.
  // The groups are runs of one flat sorted list, matched by hash (maps of vectors allocated per
  // surface, compared element by element, cost a tenth of an edit on receivers of thousands of
  // pieces).
  using Group = PieceGroup;
  using Member = PieceMember;
  const auto groupsOf = [](const std::vector<Piece>& pieces, std::vector<Member>& members) {
    members.clear();
    members.reserve(pieces.size());
    for (const Piece& p : pieces) members.push_back({p.surface, &p});
    std::sort(members.begin(), members.end(), [](const Member& x, const Member& y) {
      return x.first != y.first ? x.first < y.first : x.second->source < y.second->source;
    });
    // Zeros of either sign compare equal: they hash alike. The line a piece was snapped onto is
    // left out: another member of its snap group on the same exact line (a moving event's
    // segment joining a row of static ones) gives the same piece from other doubles.
    std::vector<Group> groups;
    for (size_t i = 0; i < members.size();) {
      Group g{members[i].first, i, i, 0};
      for (; i < members.size() && members[i].first == g.surface; ++i)
        for (double x : members[i].second->source.own) g.hash = hashCombine(g.hash, x);
      g.to = i;
      groups.push_back(g);
    }
    return groups;
  };
  std::vector<Member> beforeMembers, afterMembers;
  const std::vector<Group> before =
      m.groupsCurrent ? std::move(m.groups) : groupsOf(m.pieces, beforeMembers);
  if (m.groupsCurrent) beforeMembers = std::move(m.groupMembers);
  m.groupsCurrent = false;
  std::vector<Group> after = groupsOf(now, afterMembers);
  // Kept for the next update once `now` is the mesh's pieces (moving the list keeps its items).
  const auto keepGroups = [&] {
    m.groups = std::move(after);
    m.groupMembers = std::move(afterMembers);
    m.groupsCurrent = true;
  };
  // Equal sources give the same piece; equal segments snapped onto lines given by other doubles
  // give it where the exact ends agree (the same exact line), compared exactly only then.
  const auto samePiece = [](const Member& a, const Member& b) {
    const Piece &p = *a.second, &q = *b.second;
    if (p.source == q.source) return true;
    return p.source.own == q.source.own && p.isOutline == q.isOutline && p.a == q.a && p.b == q.b;
  };
  const auto sameGroup = [&](const Group& x, const Group& y) {
    return x.hash == y.hash && x.to - x.from == y.to - y.from &&
           std::equal(beforeMembers.begin() + std::ptrdiff_t(x.from),
                      beforeMembers.begin() + std::ptrdiff_t(x.to),
                      afterMembers.begin() + std::ptrdiff_t(y.from), samePiece);
  };
  // The groups before by hash, then surface: a surface now takes, among the groups before equal
  // to its own and not yet taken, the one of the highest surface id.
  std::vector<size_t> byHash(before.size());
  for (size_t k = 0; k < before.size(); ++k) byHash[k] = k;
  std::sort(byHash.begin(), byHash.end(), [&](size_t x, size_t y) {
    return before[x].hash != before[y].hash ? before[x].hash < before[y].hash
                                            : before[x].surface < before[y].surface;
  });
  std::vector<char> taken(before.size(), 0);
  std::map<SurfaceId, SurfaceId> renamed;  // before → now
  std::set<SurfaceId> removed, added;
  size_t changedPieces = 0;
  for (const Group& g : after) {
    const auto first = std::lower_bound(byHash.begin(), byHash.end(), g.hash,
                                        [&](size_t k, size_t h) { return before[k].hash < h; });
    auto last = first;
    while (last != byHash.end() && before[*last].hash == g.hash) ++last;
    std::optional<size_t> match;
    for (auto it = last; it != first;) {
      --it;
      if (!taken[*it] && sameGroup(before[*it], g)) {
        match = *it;
        break;
      }
    }
    if (!match) {
      added.insert(g.surface);
      changedPieces += g.to - g.from;
      continue;
    }
    taken[*match] = 1;
    if (before[*match].surface != g.surface) renamed.emplace(before[*match].surface, g.surface);
  }
  for (size_t k = 0; k < before.size(); ++k)
    if (!taken[k]) {
      removed.insert(before[k].surface);
      changedPieces += before[k].to - before[k].from;
    }
  if (stats) *stats = {int(removed.size()), int(added.size()), false};

  // When most of the pieces change, one sweep over all of them is cheaper than editing: the mesh
  // is built again, and its faces recognised among the former ones by their exact boundaries.
  if (changedPieces > now.size()) {
    if (stats) stats->rebuilt = true;
    m.rememberFaces(m.faceHandles);
    std::vector<Traits::Curve_2> curves;
    curves.reserve(now.size() + m.boundary.size() + m.tiles.size());
    m.clearSlots();
    for (const Piece& p : now) curves.push_back(m.curveOf(p));
    m.sweep(std::move(curves));
    m.pieces = std::move(now);
    keepGroups();
    return m.indexFaces();
  }

  // Edges lose the removed surfaces and take the new names; those left with none disappear. The
  // vertices at their ends, and at the ends of edges that lost a surface, may be left isolated or
  // between two collinear edges of equal surfaces, which the arrangement of the remaining pieces
  // lacks unless they end a piece there.
  m.detachLocator();
  std::vector<Arrangement::Halfedge_handle> doomed;
  std::vector<Arrangement::Vertex_handle> touched;
  std::vector<char> removedSlot(m.slotSurface.size(), 0);
  for (SurfaceId id : removed)
    if (const auto it = m.slotOf.find(id); it != m.slotOf.end())
      removedSlot[size_t(it->second)] = 1;
  const auto isRemoved = [&](int slot) { return removedSlot[size_t(slot)] != 0; };
  for (auto e = m.arrangement.edges_begin(); e != m.arrangement.edges_end(); ++e) {
    const auto& data = e->curve().data();
    // Most edges keep all their surfaces: their names are not copied (a list, allocated per name).
    if (std::none_of(data.begin(), data.end(), isRemoved)) continue;
    Traits::Data_container names;
    for (int slot : data)
      if (!isRemoved(slot)) names.insert(slot);
    touched.push_back(e->source());
    touched.push_back(e->target());
    if (names.size() == 0) {
      doomed.push_back(e);
    } else {
      m.arrangement.modify_edge(e, Traits::X_monotone_curve_2(e->curve(), names));
    }
  }
  m.renameSlots(ReceiverMesh::Renaming(renamed.begin(), renamed.end()), removed);
  {
    std::vector<Arrangement::Face_const_handle> around;
    for (auto e : doomed) {
      around.push_back(e->face());
      around.push_back(e->twin()->face());
    }
    for (auto v : touched) {
      if (v->is_isolated()) continue;
      auto c = v->incident_halfedges();
      const auto first = c;
      do around.push_back(c->face());
      while (++c != first);
    }
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    m.rememberFaces(around);
  }
  for (auto e : doomed) m.arrangement.remove_edge(e, false, false);
  // A touched vertex left isolated or between two edges goes unless a piece that stays (or the
  // outline) ends there. Removing one such vertex changes no other's degree.
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  struct Lonely {
    Arrangement::Vertex_handle vertex;
    double xLow, xHigh, yLow, yHigh;  // its point's intervals
    bool endsAPiece = false;
  };
  std::vector<Lonely> lonely;
  for (auto v : touched)
    if (v->is_isolated() || v->degree() == 2) {
      const auto& box = v->point().approx();
      lonely.push_back({v, box.x().inf(), box.x().sup(), box.y().inf(), box.y().sup()});
    }
  // Every end of those pieces marks the lonely vertices it is, compared exactly only with those
  // whose intervals overlap its own: a scan of the ends against a few vertices sorted by the lower
  // bound of their abscissa's interval (a floor has 70,000 pieces, an edit a few such vertices).
  std::vector<size_t> byLow(lonely.size());
  for (size_t k = 0; k < byLow.size(); ++k) byLow[k] = k;
  std::sort(byLow.begin(), byLow.end(),
            [&](size_t a, size_t b) { return lonely[a].xLow < lonely[b].xLow; });
  double widest = 0;
  for (const Lonely& v : lonely) widest = std::max(widest, v.xHigh - v.xLow);
  const auto markEnd = [&](const Point& p) {
    const auto& box = p.approx();
    const auto first =
        std::lower_bound(byLow.begin(), byLow.end(), box.x().inf() - widest,
                         [&](size_t k, double value) { return lonely[k].xLow < value; });
    for (auto it = first; it != byLow.end() && lonely[*it].xLow <= box.x().sup(); ++it) {
      Lonely& v = lonely[*it];
      if (!v.endsAPiece && box.x().inf() <= v.xHigh && v.yLow <= box.y().sup() &&
          box.y().inf() <= v.yHigh && v.vertex->point() == p)
        v.endsAPiece = true;
    }
  };
  if (!lonely.empty()) {
    for (const Piece& p : now)
      if (!added.count(p.surface)) {
        markEnd(p.a);
        markEnd(p.b);
      }
    for (const auto* fixed : {&m.boundary, &m.tiles})
      for (const auto& curve : *fixed) {
        markEnd(curve.source());
        markEnd(curve.target());
      }
  }
  for (const Lonely& v : lonely)
    if (!v.endsAPiece)
      CGAL::remove_vertex(m.arrangement, v.vertex);  // its data goes with it (EditTracker)
  {
    WalkLocation walk(m.arrangement);
    for (const Piece& p : now)
      if (added.count(p.surface)) CGAL::insert(m.arrangement, m.curveOf(p), walk);
  }
  m.pieces = std::move(now);
  keepGroups();
  return m.indexFaces();
}

void ReceiverMesh::renumberSurfaces(const Renaming& renamed) {
  if (renamed.empty()) return;
  impl_->renameSlots(renamed, {});
  impl_->groupsCurrent = false;
  for (Piece& p : impl_->pieces) {
    const auto it =
        std::lower_bound(renamed.begin(), renamed.end(), p.surface,
                         [](const auto& entry, SurfaceId id) { return entry.first < id; });
    if (it != renamed.end() && it->first == p.surface) p.surface = it->second;
  }
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
  return impl_->strictlyInside(impl_->faceHandles.at(size_t(face)), impl_->toPoint(p));
}

std::optional<int> ReceiverMesh::locate(const Vec3& p) const {
  const auto result = impl_->attachedLocator().locate(impl_->toPoint(p));
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
  if (face->data() == Impl::kTooThin) {
    // No double lies strictly inside it, so p is within rounding of its boundary: the inside face
    // of lowest index around it, as for a point on an edge.
    std::optional<int> lowest;
    for (const Impl::Cycle& cycle : impl_->cyclesOf(face))
      for (auto h : cycle) {
        const int index = h->twin()->face()->data();
        if (index >= 0 && (!lowest || index < *lowest)) lowest = index;
      }
    return lowest;
  }
  if (face->data() < 0) return std::nullopt;
  return face->data();
}

std::vector<std::pair<std::pair<Vec3, Vec3>, std::vector<SurfaceId>>> ReceiverMesh::edges() const {
  std::vector<std::pair<std::pair<Vec3, Vec3>, std::vector<SurfaceId>>> out;
  for (auto e = impl_->arrangement.edges_begin(); e != impl_->arrangement.edges_end(); ++e) {
    Vec3 a = impl_->worldOf(e->source()), b = impl_->worldOf(e->target());
    if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) std::swap(a, b);
    out.push_back({{a, b}, impl_->sortedSurfaces(e->curve().data())});
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

std::vector<Vec3> ReceiverMesh::faceCorners(int face) const {
  std::vector<Vec3> corners;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  const auto walk = [&](Arrangement::Ccb_halfedge_const_circulator first) {
    auto c = first;
    do corners.push_back(impl_->worldOf(c->source()));
    while (++c != first);
  };
  if (f->has_outer_ccb()) walk(f->outer_ccb());
  for (auto h = f->holes_begin(); h != f->holes_end(); ++h) walk(*h);
  return corners;
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
        {std::min(left, right), std::max(left, right), impl_->sortedSurfaces(e->curve().data())});
  }
  // In the order of the faces (canonical), not of the arrangement's edge list.
  std::sort(crossings.begin(), crossings.end(), [](const FaceCrossing& a, const FaceCrossing& b) {
    return std::tie(a.face, a.other, a.surfaces) < std::tie(b.face, b.other, b.surfaces);
  });
  return crossings;
}

std::vector<NearCrossing> ReceiverMesh::crossingsNear(int face, const Vec3& p,
                                                      double radius) const {
  std::vector<NearCrossing> crossings;
  const Arrangement::Face_const_handle f = impl_->faceHandles.at(face);
  const Vec2 q = impl_->frame.toLocal(p);
  for (const Impl::Cycle& cycle : impl_->cyclesOf(f))
    for (auto h : cycle) {
      const int other = h->twin()->face()->data();
      if (other < 0 || other == face) continue;
      const Vec2 a = impl_->localOf(h->source()), b = impl_->localOf(h->target());
      const Vec2 ab = b - a;
      const double length2 = dot(ab, ab);
      if (!(length2 > 0)) continue;
      const double t = std::clamp(dot(q - a, ab) / length2, 0.0, 1.0);
      const Vec2 nearest = a + ab * t, off = q - nearest;
      if (std::sqrt(dot(off, off)) > radius) continue;
      // The face lies left of its half-edges (outer boundaries counter-clockwise, holes
      // clockwise), so the other face is on the right.
      const double length = std::sqrt(length2);
      const Vec2 right{ab.y / length, -ab.x / length};
      const PlaneFrame& frame = impl_->frame;
      crossings.push_back({{face, other, impl_->sortedSurfaces(h->curve().data())},
                           frame.toWorld(nearest),
                           frame.u * right.x + frame.v * right.y});
    }
  std::sort(crossings.begin(), crossings.end(), [](const NearCrossing& a, const NearCrossing& b) {
    return std::tie(a.crossing.other, a.crossing.surfaces) <
           std::tie(b.crossing.other, b.crossing.surfaces);
  });
  return crossings;
}

std::optional<MeshWalk> ReceiverMesh::walk(int face, const Vec3& from, const Vec3& to,
                                           int maxCrossings) const {
  const Vec2 a = impl_->frame.toLocal(from), b = impl_->frame.toLocal(to);
  const Vec2 ab = b - a;
  const double walkLength2 = dot(ab, ab), walkLength = std::sqrt(walkLength2);
  if (!(walkLength > 0)) return MeshWalk{face, {}};
  const auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
  };
  MeshWalk result{face, {}};
  double entered = 0;  // the walk's parameter where it entered the current face
  Arrangement::Halfedge_const_handle cameThrough;  // the current face's side of that edge
  for (int step = 0; step <= maxCrossings; ++step) {
    const Arrangement::Face_const_handle f = impl_->faceHandles.at(size_t(result.face));
    std::optional<double> exit;
    Arrangement::Halfedge_const_handle through;
    for (const Impl::Cycle& cycle : impl_->cyclesOf(f))
      for (auto h : cycle) {
        // Not back across the edge just crossed (either side of it: an antenna has the same face
        // on both).
        if (step > 0 && (h == cameThrough || h == cameThrough->twin())) continue;
        const Vec2 s = impl_->localOf(h->source()), t = impl_->localOf(h->target());
        const Vec2 st = t - s;
        // Orientations are products of two lengths; this is their rounding, with a margin.
        const double slack = 1e-12 * (walkLength + std::sqrt(dot(st, st))) * walkLength;
        // Where the edge's ends lie across the walk's line, and the walk's ends across the edge's.
        const double sideS = orient(a, b, s), sideT = orient(a, b, t);
        const double atFrom = orient(s, t, a), atTo = orient(s, t, b);
        const bool sOn = std::abs(sideS) <= slack, tOn = std::abs(sideT) <= slack;
        // Ends on the same side of the walk's line: the edge is not crossed.
        if (!sOn && !tOn && (sideS > 0) == (sideT > 0)) continue;
        // The parameters along the walk of the edge's ends (for an edge on the walk's line) or of
        // the crossing; an edge wholly behind where the walk entered the face does not matter.
        const double ps = dot(s - a, ab) / walkLength2, pt = dot(t - a, ab) / walkLength2;
        if (sOn || tOn) {
          // The walk passes within rounding of a vertex, or runs along an edge, where the
          // rounded coordinates cannot tell which faces it crosses.
          const double low = std::min(sOn ? ps : pt, tOn ? pt : ps),
                       high = std::max(sOn ? ps : pt, tOn ? pt : ps);
          if (high >= entered - 1e-9 && low <= 1 + 1e-9) return std::nullopt;
          if (sOn && tOn) continue;
        }
        // The walk ends on the edge: on which side is rounding's choice.
        if (std::abs(atTo) <= slack) return std::nullopt;
        // The face lies left of its half-edges: the walk leaves it where it passes to the right.
        if (!(atTo < 0) || !(atFrom >= atTo)) continue;
        const double param = atFrom / (atFrom - atTo);
        // Onward only (from the start, which may lie on an edge, within rounding).
        if (param < (step == 0 ? -1e-9 : entered) || param > 1) continue;
        if (!exit || param < *exit) exit = param, through = h;
      }
    if (!exit) {
      std::sort(result.surfaces.begin(), result.surfaces.end());
      result.surfaces.erase(std::unique(result.surfaces.begin(), result.surfaces.end()),
                            result.surfaces.end());
      return result;  // `to` lies in this face
    }
    const int other = through->twin()->face()->data();
    if (other < 0) return std::nullopt;
    for (SurfaceId id : impl_->sortedSurfaces(through->curve().data()))
      result.surfaces.push_back(id);
    result.face = other;
    entered = *exit;
    cameThrough = through->twin();
  }
  return std::nullopt;
}

const PlaneFrame& ReceiverMesh::frame() const {
  return impl_->frame;
}

size_t ReceiverMesh::memoryBytes() const {
  // DCEL records plus the exact coordinates' lazy representations, estimated per record.
  const auto& a = impl_->arrangement;
  // What an update reads besides: the pieces, each vertex's data and the snapping outcomes (a
  // hash node of a key, an outcome and a link each, and a bucket).
  const size_t updateData =
      impl_->pieces.capacity() * sizeof(Piece) +
      impl_->vertices.size() * (sizeof(VertexData) + 32) +
      impl_->snapped.size() * (sizeof(SnapKey) + sizeof(SnapOutcome) + 2 * sizeof(void*)) +
      impl_->snapped.bucket_count() * sizeof(void*) +
      impl_->groups.capacity() * sizeof(PieceGroup) +
      impl_->groupMembers.capacity() * sizeof(PieceMember);
  return sizeof(Impl) + a.number_of_vertices() * 96 + a.number_of_halfedges() * 120 +
         a.number_of_faces() * 64 + impl_->faces.capacity() * sizeof(MeshFace) + updateData;
}

}  // namespace penumbra
