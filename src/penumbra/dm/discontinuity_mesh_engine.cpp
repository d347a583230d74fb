#include "penumbra/dm/discontinuity_mesh_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>

#include "penumbra/base/check.h"
#include "penumbra/base/input_error.h"
#include "penumbra/dm/crossing_occluders.h"
#include "penumbra/dm/fan_visibility.h"
#include "penumbra/dm/receiver_plane_events.h"
#include "penumbra/dm/surface_casting.h"
#include "penumbra/dm/surface_enumeration.h"
#include "penumbra/spatial/receiver_locator.h"
#include "penumbra/spatial/shaft.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The frame before's items by a hash of what makes them reusable, each taken at most once: one
// open-addressed array of item numbers, where a multimap made (and freed) a node per item every
// frame (472,000 planar surfaces and 245,000 EEE traces in a 10,000-polygon room), and sorting
// (hash, item) pairs was 3% of that room's update. An update enumerates its items in nearly the
// frame before's order, so the item after the one taken last is tried first: most are found
// there without a search. Which of two matching items is taken makes no difference: items that
// match are equal in all that reusing them reads (castOrKeep, traceFrom).
class TakenOnce {
 public:
  void reserve(std::size_t items) { hashOf_.reserve(items); }
  // The next item (items are numbered 0, 1, 2, ... in the order added).
  void add(std::size_t hash) { hashOf_.push_back(hash); }
  // Items 0, 1, ... with these hashes, in place of any added.
  void assign(std::vector<std::size_t>&& hashes) { hashOf_ = std::move(hashes); }
  std::size_t hashOf(std::size_t item) const { return hashOf_[item]; }
  // The hashes' storage, for a later assign (the object is empty after).
  std::vector<std::size_t> releaseHashes() {
    slots_.clear();
    taken_.clear();
    next_ = 0;
    return std::move(hashOf_);
  }
  void seal() {
    std::size_t capacity = 16;
    while (capacity < 2 * hashOf_.size()) capacity *= 2;
    slots_.assign(capacity, kEmpty);
    // Items of one hash lie along its probe sequence in the order added.
    for (std::size_t item = 0; item < hashOf_.size(); ++item) {
      std::size_t i = slotOf(hashOf_[item]);
      while (slots_[i] != kEmpty) i = (i + 1) & (slots_.size() - 1);
      slots_[i] = std::uint32_t(item);
    }
    taken_.assign(hashOf_.size(), 0);
  }
  // Takes the item if it is not taken yet.
  bool take(size_t item) {
    if (taken_[item]) return false;
    takeItem(item);
    return true;
  }
  // An item of this hash, not taken yet, that `matches` (the one after the item taken last if
  // it does, else the first added); taken now.
  template <class Matches>
  std::optional<size_t> take(std::size_t hash, Matches&& matches) {
    if (next_ < hashOf_.size() && !taken_[next_] && hashOf_[next_] == hash && matches(next_))
      return takeItem(next_);
    if (slots_.empty()) return std::nullopt;
    for (std::size_t i = slotOf(hash); slots_[i] != kEmpty; i = (i + 1) & (slots_.size() - 1)) {
      const std::size_t item = slots_[i];
      if (hashOf_[item] == hash && !taken_[item] && matches(item)) return takeItem(item);
    }
    return std::nullopt;
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  std::size_t slotOf(std::size_t hash) const {
    std::uint64_t z = std::uint64_t(hash) + 0x9e3779b97f4a7c15ull;  // SplitMix64's finalizer
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return std::size_t(z ^ (z >> 31)) & (slots_.size() - 1);
  }
  size_t takeItem(size_t item) {
    taken_[item] = 1;
    next_ = item + 1;
    return item;
  }
  std::vector<std::uint32_t> slots_;  // item numbers, kEmpty where none
  std::vector<std::size_t> hashOf_;   // by item
  std::vector<char> taken_;           // by item
  size_t next_ = 0;
};

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
// Which of those a segment's surface id is, as the count in `stats` that tallies it (null for a
// discontinuity surface's id or the boundary's).
long long* ownEventCount(const PosedScene& scene, SurfaceId surface, DmStats& stats) {
  if (surface >= ReceiverMesh::kBoundary) return nullptr;
  const SurfaceId k = ReceiverMesh::kBoundary - 1 - surface;
  const SurfaceId n = SurfaceId(scene.polygons.size());
  return k < n       ? &stats.contactSegments
         : k < 2 * n ? &stats.lightPlaneSegments
                     : &stats.horizonSegments;
}

// Where other polygons meet the receiver's plane: contact lines (D0 discontinuities), e.g. the
// footprint of a box resting on the floor (its bottom face, lying on the receiver), the foot of a
// card standing on it (one edge of a polygon across the plane), or the trace of a polygon passing
// through it. No event surface makes the last two (the EV fans through the edge meet the
// receiver only at their hinge). An edge given by a polygon lying on the receiver is not repeated
// for the polygons standing on it.
std::vector<DiscontinuitySegment> contactSegments(const PosedScene& scene, const UniformGrid& grid,
                                                  const WorldPolygon& receiver) {
  std::vector<DiscontinuitySegment> out;
  const double tolerance = 1e-9 * scene.extent.diagonalLength();
  const auto onPlane = [&](const Vec3& v) {
    return std::abs(receiver.plane.signedDistance(v)) <= tolerance;
  };
  // By value: std::minmax of temporaries returns references to them.
  const auto key = [](const Vec3& a, const Vec3& b) {
    std::array<double, 3> p{a.x, a.y, a.z}, q{b.x, b.y, b.z};
    if (q < p) std::swap(p, q);
    return std::pair{p, q};
  };
  std::set<std::pair<std::array<double, 3>, std::array<double, 3>>> lying;
  std::vector<DiscontinuitySegment> standing;
  for (PolygonId id : grid.polygonsInBox(receiver.bounds.expanded(tolerance))) {
    if (id == receiver.id) continue;
    const WorldPolygon& other = scene.polygons[id];
    const bool coplanar = std::all_of(other.vertices.begin(), other.vertices.end(), onPlane);
    // A polygon through the receiver (vertices beyond the tolerance on both sides) meets it along
    // its trace, from the first point where its boundary meets the plane to the last (the hull of
    // a non-convex polygon's pieces: an extra line only refines the mesh).
    bool above = false, below = false;
    for (const Vec3& v : other.vertices) {
      const double d = receiver.plane.signedDistance(v);
      above = above || d > tolerance;
      below = below || d < -tolerance;
    }
    if (above && below) {
      const Vec3 along = cross(receiver.plane.normal, other.plane.normal);
      std::optional<Vec3> first, last;
      for (size_t i = 0; i < other.vertices.size(); ++i) {
        const Vec3& a = other.vertices[i];
        const Vec3& b = other.vertices[(i + 1) % other.vertices.size()];
        const double da = receiver.plane.signedDistance(a), db = receiver.plane.signedDistance(b);
        std::optional<Vec3> meet;
        if (std::abs(da) <= tolerance)
          meet = a;
        else if ((da > tolerance && db < -tolerance) || (da < -tolerance && db > tolerance))
          meet = a + (b - a) * (da / (da - db));
        if (!meet) continue;
        if (!first || dot(*meet, along) < dot(*first, along)) first = meet;
        if (!last || dot(*meet, along) > dot(*last, along)) last = meet;
      }
      if (first && last && !(*first == *last))
        out.push_back({contactSurface(id), receiver.id, *first, *last, 0, 0});
      continue;
    }
    for (size_t i = 0; i < other.vertices.size(); ++i) {
      const Vec3& a = other.vertices[i];
      const Vec3& b = other.vertices[(i + 1) % other.vertices.size()];
      if (coplanar) {
        out.push_back({contactSurface(id), receiver.id, a, b, 0, 0});
        lying.insert(key(a, b));
      } else if (onPlane(a) && onPlane(b)) {
        standing.push_back({contactSurface(id), receiver.id, a, b, 0, 0});
      }
    }
  }
  for (const DiscontinuitySegment& s : standing)
    if (!lying.count(key(s.p0, s.p1))) out.push_back(s);
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

namespace {

// The largest magnitude of a coordinate in the box.
double farthestCoordinate(const Box3& box) {
  double farthest = 0;
  for (const Vec3& corner : {box.min, box.max})
    farthest = std::max({farthest, std::abs(corner.x), std::abs(corner.y), std::abs(corner.z)});
  return farthest;
}

}  // namespace

bool DiscontinuityMeshEngine::resolves(const Box3& extent) {
  return farthestCoordinate(extent) <= kMaxDistanceToSize * extent.diagonalLength();
}

void DiscontinuityMeshEngine::requireResolves(const Box3& extent, const std::string& where) {
  if (resolves(extent)) return;
  const double farthest = farthestCoordinate(extent), size = extent.diagonalLength();
  char text[400];
  std::snprintf(text, sizeof text,
                "the scene lies too far from the origin for exact soft shadows: a coordinate of "
                "%g is %.3g times the size of its extent over all frames (%g), so its coordinates "
                "resolve it only to %.2g of its size, where the discontinuity mesh needs 1e-11; "
                "move it within %g times its size of the origin",
                farthest, farthest / size, size,
                farthest * std::numeric_limits<double>::epsilon() / size, kMaxDistanceToSize);
  throw InputError(where, text);
}

DiscontinuityMeshEngine::DiscontinuityMeshEngine(DmOptions options) : options_(options) {}
DiscontinuityMeshEngine::~DiscontinuityMeshEngine() = default;

void DiscontinuityMeshEngine::build(const Scene& scene, double frame) {
  ownedScene_ = std::make_unique<DynamicScene>(scene, frame);
  build(*ownedScene_);
}

void DiscontinuityMeshEngine::build(const PosedScene& posed) {
  ownedScene_ = std::make_unique<DynamicScene>(posed);
  build(*ownedScene_);
}

void DiscontinuityMeshEngine::build(const DynamicScene& scene) {
  requireResolves(scene.posed().extent, scene.scene().sourcePath);
  posed_ = &scene.posed();
  grid_ = &scene.grid();
  compute(nullptr);
}

void DiscontinuityMeshEngine::update(const DynamicScene& scene, const SceneChange& change) {
  CHECK(posed_ == &scene.posed() && grid_ == &scene.grid());
  // A grown extent changes every frame-invariant tolerance; propagation names surfaces by their
  // position in this frame's list: both recompute everything.
  if (change.extentGrows || options_.propagateBackprojections) {
    build(scene);
  } else {
    compute(&change);
  }
  stats_.movedObjects = int(change.moves.size());
}

bool DiscontinuityMeshEngine::isCrossed(const Box3& region, const SceneChange& change) const {
  // A face's backprojections, their verification and its answers at points are computed from the
  // cones from points of the face to each light (ExactReference::visibleLight). A polygon enters
  // such a computation only if its bounds overlap the cone's bounds, which lie in the box around
  // the face and the light, and only if clipping it to the cone leaves a piece, which lies in the
  // shaft from the face to the cones' base (the convex hull of the two boxes). A moved object
  // that misses either, at its old and new pose, changes nothing there.
  const double diagonal = posed_->extent.diagonalLength();
  const double margin = 1e-9 * diagonal;
  for (PolygonId light : posed_->lights) {
    Box3 around = region;
    around.extend(posed_->polygons[light].bounds);
    around = around.expanded(margin);
    // The clipping and the shaft's planes round by a few ulps of the coordinates, magnified where
    // the cone is narrow (down to the light's diameter over the scene's): the shaft is kept that
    // much wider, far below any gap the scenes hold.
    const Box3 base = reference_->coneBaseBounds(light);
    const double wide = margin * diagonal / std::max(base.diagonalLength(), 1e-300);
    std::optional<Shaft> shaft;
    for (const ObjectMove& move : change.moves)
      for (const Box3& bounds : {move.boundsBefore, move.boundsAfter}) {
        if (!around.overlaps(bounds)) continue;
        if (!shaft) shaft.emplace(region.expanded(wide), base.expanded(wide));
        if (shaft->mayIntersect(bounds.expanded(wide))) return true;
      }
  }
  return false;
}

namespace {

// What a planar surface's cast depends on besides the scene: its light and its fan (castSurface).
bool sameFan(const DiscontinuitySurface& a, const DiscontinuitySurface& b) {
  return a.light == b.light && a.fan.source0 == b.fan.source0 && a.fan.source1 == b.fan.source1 &&
         a.fan.hinge0 == b.fan.hinge0 && a.fan.hinge1 == b.fan.hinge1 &&
         a.fan.contacts == b.fan.contacts;
}

std::size_t fanHash(const DiscontinuitySurface& s) {
  std::uint64_t h = std::uint64_t(s.light);
  for (const Vec3& p : {s.fan.source0, s.fan.source1, s.fan.hinge0, s.fan.hinge1})
    for (double c : {p.x, p.y, p.z}) h = hashCombine(h, c);
  return std::size_t(h);
}

// Are two segments the same (geometry and receiver, bit for bit), whatever surface made them?
bool sameGeometry(const DiscontinuitySegment& a, const DiscontinuitySegment& b) {
  return a.receiver == b.receiver && a.p0 == b.p0 && a.p1 == b.p1 && a.u0 == b.u0 && a.u1 == b.u1;
}

// Do two receivers' inputs hold the same segments in the same order (geometry, bit for bit)? The
// surfaces that made them may sit at other positions in this frame's list (surfaces before them
// appeared or vanished): `renamed` gets each old id's new one where they differ, which must be one
// to one. (Sorted pairs, not maps: this runs for every receiver every frame, and a map's node per
// surface was an allocation per segment of the scene.)
bool sameSegmentGeometry(const std::vector<DiscontinuitySegment>& before,
                         const std::vector<DiscontinuitySegment>& now,
                         ReceiverMesh::Renaming& renamed) {
  renamed.clear();
  if (before.size() != now.size()) return false;
  ReceiverMesh::Renaming pairs;  // (old, new) for every segment
  pairs.reserve(now.size());
  for (size_t i = 0; i < now.size(); ++i) {
    const DiscontinuitySegment& a = before[i];
    const DiscontinuitySegment& b = now[i];
    if (!sameGeometry(a, b)) return false;
    pairs.push_back({a.surface, b.surface});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  // One to one: no old id twice (with two new ones), and no new id twice.
  for (size_t i = 1; i < pairs.size(); ++i)
    if (pairs[i].first == pairs[i - 1].first) return false;
  std::vector<SurfaceId> targets;
  targets.reserve(pairs.size());
  for (const auto& [from, to] : pairs) targets.push_back(to);
  std::sort(targets.begin(), targets.end());
  if (std::adjacent_find(targets.begin(), targets.end()) != targets.end()) return false;
  for (const auto& entry : pairs)
    if (entry.first != entry.second) renamed.push_back(entry);
  return true;
}

// Are two lists of a surface's visible pieces the same (geometry and receivers, bit for bit)?
bool samePieces(const std::vector<DiscontinuitySegment>& before,
                const std::vector<DiscontinuitySegment>& now) {
  return std::equal(before.begin(), before.end(), now.begin(), now.end(), sameGeometry);
}

// A receiver's inputs of the frame before under this frame's surface ids (`newIdOf`, by old id,
// -1 for a surface whose pieces were not taken over): where every surface piece on it was taken
// over and the new ids keep the old ones' order (pieces are filed by surface id, so the same
// pieces come in the same order) and the receiver got as many surface pieces now (`pieces`).
// The receiver's own events (negative ids) are kept as they are. `renamed`: (old id, new id)
// where they differ, sorted by the old, for ReceiverMesh::renumberSurfaces.
bool carriedInputs(const std::vector<DiscontinuitySegment>& before,
                   const std::vector<SurfaceId>& newIdOf, size_t pieces,
                   std::vector<DiscontinuitySegment>& inputs, ReceiverMesh::Renaming& renamed) {
  inputs.clear();
  renamed.clear();
  inputs.reserve(before.size());
  size_t surfacePieces = 0;
  SurfaceId last = -1;
  for (DiscontinuitySegment segment : before) {
    if (segment.surface >= 0) {
      const SurfaceId old = segment.surface;
      if (size_t(old) >= newIdOf.size() || newIdOf[size_t(old)] < 0) return false;
      segment.surface = newIdOf[size_t(old)];
      if (segment.surface < last) return false;
      last = segment.surface;
      ++surfacePieces;
      if (segment.surface != old && (renamed.empty() || renamed.back().first != old))
        renamed.push_back({old, segment.surface});
    }
    inputs.push_back(segment);
  }
  return surfacePieces == pieces;
}

// The points a corner's verification probe is chosen from, in order (the first strictly inside
// the face and away from EEE polylines is the probe): at each inset of the way to the face's
// sample, the point towards the sample, then the points along the corner's bisector either
// way, as far from the corner (at a concave corner, or where a polyline bulges into the face,
// the line to the sample leaves the face at once; the bisector stays in it).
std::vector<Vec3> probeCandidates(const Polygon3& cycle, size_t corner, const Vec3& sample) {
  const Vec3& c = cycle[corner];
  const Vec3 toPrevious = cycle[(corner + cycle.size() - 1) % cycle.size()] - c;
  const Vec3 toNext = cycle[(corner + 1) % cycle.size()] - c;
  const double reach = distance(c, sample);
  Vec3 bisector{0, 0, 0};
  if (length(toPrevious) > 0 && length(toNext) > 0)
    bisector = toPrevious / length(toPrevious) + toNext / length(toNext);
  const double spread = length(bisector);
  std::vector<Vec3> out;
  for (const double inset : DiscontinuityMeshEngine::kCornerInsets) {
    out.push_back(c + (sample - c) * inset);
    if (spread > 1e-6) {
      const Vec3 step = bisector * (inset * reach / spread);
      out.push_back(c + step);
      out.push_back(c - step);
    }
  }
  return out;
}

}  // namespace

bool DiscontinuityMeshEngine::keepsFaceData(const ReceiverData& now, const MeshFace& face,
                                            const FaceData& before,
                                            const SegmentProximity& eeeBefore,
                                            const SegmentProximity& eeeChanged, bool sameEee,
                                            const SceneChange& change) const {
  // The face's data is computed from its boundary (here the same vertices), its sample, and its
  // corner probes (labelsHoldAtCorners): a backprojection per light at each, which reads only the
  // polygons its cone admits (ExactReference::mayOcclude). The probes are, per corner, the first
  // of the inset points towards the sample that lies strictly inside the face (a function of its
  // geometry) and away from EEE polylines: the same where the polylines near every inset point
  // are the same. Every test below is on the set of inset points, in any order.
  const Box3& bounds = before.bounds;  // of its corners, the same as the frame before's
  // Where the polylines are the same and nothing moved through that box and the lights (below),
  // the inset points are not needed.
  if (sameEee && !isCrossed(bounds, change)) return true;
  // Whether a point is near a polyline changes only where a polyline that changed (one of
  // `eeeChanged`, the polylines of either frame missing from the other) is near it. Only the
  // points inside the face can be its probes or its sample, and those lie in its box (up to a
  // rounding, far below the padding): where no changed polyline comes near the box, no probe
  // changes.
  const double near = nearEee();
  const bool probesMayChange = !sameEee && eeeChanged.mayBeNear(bounds, 2 * near);
  if (!probesMayChange && !isCrossed(bounds, change)) return true;
  std::vector<Vec3> insets;
  for (const Polygon3& cycle : now.mesh.faceBoundary(face.index))
    for (size_t i = 0; i < cycle.size(); ++i)
      for (const Vec3& p : probeCandidates(cycle, i, face.samplePoint)) insets.push_back(p);
  if (probesMayChange) {
    const auto differs = [&](const Vec3& p) {
      return eeeChanged.near(p, near) && now.eeeSegments.near(p, near) != eeeBefore.near(p, near);
    };
    if (differs(face.samplePoint)) return false;
    for (const Vec3& p : insets)
      if (differs(p)) return false;
  }
  // Nothing moved (old or new bounds) through the box around the face and the lights: no cone
  // can admit a moved polygon. Else the cones themselves, from the sample and every inset point
  // (the probes among them).
  if (!isCrossed(bounds, change)) return true;
  insets.push_back(face.samplePoint);
  std::vector<Box3> moved;
  for (const ObjectMove& move : change.moves) {
    moved.push_back(move.boundsBefore);
    moved.push_back(move.boundsAfter);
  }
  const Vec3& normal = posed_->polygons[now.mesh.receiver()].plane.normal;
  for (const Vec3& p : insets)
    for (PolygonId light : posed_->lights)
      if (reference_->mayOcclude(p, normal, light, moved)) return false;
  return true;
}

void DiscontinuityMeshEngine::compute(const SceneChange* change) {
  stats_ = {};
  statsTallied_ = false;
  stats_.recomputedAll = change == nullptr;
  // The previous frame's receivers, offered for reuse when an update finds their inputs equal.
  std::map<PolygonId, ReceiverData> previous;
  if (change) previous = std::move(receivers_);
  receivers_.clear();
  // The previous frame's planar surfaces, by their fan, and the grid cells a moved object's old
  // or new bounds overlap: a surface with the same fan as before whose cells none of those are
  // cuts the same polygons the same way (the paper's per-cell test), so its cast is kept.
  std::vector<DiscontinuitySurface> previousSurfaces;
  if (change) previousSurfaces = std::move(surfaces_);
  surfaces_ = std::move(spareSurfaces_);
  surfaces_.clear();
  // Sized as the frame before: growing a list of half a million surfaces by doubling moved each
  // one several times and faulted in fresh pages for every copy (10% of a large room's update).
  surfaces_.reserve(previousSurfaces.size());
  // Their fans' hashes as the frame before computed them (each surface's, by index), else
  // computed here; this frame's are recorded as its surfaces are cast or kept.
  TakenOnce previousByFan;
  if (change && fanHashes_.size() == previousSurfaces.size()) {
    previousByFan.assign(std::move(fanHashes_));
  } else {
    previousByFan.reserve(previousSurfaces.size());
    for (size_t i = 0; i < previousSurfaces.size(); ++i)
      previousByFan.add(fanHash(previousSurfaces[i]));
  }
  previousByFan.seal();
  fanHashes_ = std::move(spareFanHashes_);
  fanHashes_.clear();
  const auto recordFanHash = [&](size_t index, std::size_t hash) {
    if (fanHashes_.size() <= index) fanHashes_.resize(index + 1);
    fanHashes_[index] = hash;
  };
  // Likewise their cells' blocks, carried with the casts.
  const auto blockOfCells = [&](const std::vector<int>& cells) {
    CellBlock block;
    for (int cell : cells) block.extend(grid_->cellCoordinates(cell));
    return block;
  };
  std::vector<CellBlock> previousBlocks;
  if (change) previousBlocks = std::move(cellBlocks_);
  const bool blocksKnown = previousBlocks.size() == previousSurfaces.size();
  cellBlocks_ = std::move(spareCellBlocks_);
  cellBlocks_.clear();
  const auto recordBlock = [&](size_t index, const CellBlock& block) {
    if (cellBlocks_.size() <= index) cellBlocks_.resize(index + 1);
    cellBlocks_[index] = block;
  };
  std::vector<char> movedCells;
  // The lowest and highest of them: a surface's cells (sorted) are looked at only in that range,
  // found by bisection (a large room's hundreds of thousands of surfaces lie mostly elsewhere).
  int lowestMovedCell = std::numeric_limits<int>::max(), highestMovedCell = -1;
  CellBlock movedBlock;  // and the block around them
  if (change) {
    movedCells.assign(grid_->resolution().cellCount(), 0);
    for (const ObjectMove& move : change->moves)
      for (const Box3& box : {move.boundsBefore, move.boundsAfter})
        grid_->forEachCellOverlappingBox(box, [&](int cell) {
          movedCells[cell] = 1;
          lowestMovedCell = std::min(lowestMovedCell, cell);
          highestMovedCell = std::max(highestMovedCell, cell);
          movedBlock.extend(grid_->cellCoordinates(cell));
        });
  }
  const auto crossesMovedCells = [&](const std::vector<int>& sortedCells) {
    for (auto it = std::lower_bound(sortedCells.begin(), sortedCells.end(), lowestMovedCell);
         it != sortedCells.end() && *it <= highestMovedCell; ++it)
      if (movedCells[*it] != 0) return true;
    return false;
  };
  // The polygons of the moved objects: a surface with the same fan whose cells they touch has
  // only its cuts with them computed again (recastMoved: the paper's re-intersection with the
  // moving object).
  std::vector<char> movedPolygons;
  if (change) {
    movedPolygons.assign(posed_->polygons.size(), 0);
    for (const ObjectMove& move : change->moves)
      for (PolygonId id = posed_->objectFirstPolygon[move.object];
           id < posed_->objectFirstPolygon[move.object + 1]; ++id)
        movedPolygons[size_t(id)] = 1;
  }
  // Each surface's index in the frame before, where its cast was taken over (else -1).
  std::vector<int> previousIndex;
  std::vector<char> keptCast;  // and whether its cuts are all as they were
  // Surface `index` holds the cast (cells and cuts) of the frame before's surface `then`: kept,
  // or recast with the moved polygons where a moved object's old or new bounds overlap its cells.
  const auto keepCast = [&](DiscontinuitySurface& surface, size_t index, size_t then) {
    if (previousIndex.size() <= index) {
      previousIndex.resize(index + 1, -1);
      keptCast.resize(index + 1, 0);
    }
    previousIndex[index] = int(then);
    const CellBlock block = blocksKnown ? previousBlocks[then] : blockOfCells(surface.cells);
    recordBlock(index, block);
    if (block.meets(movedBlock) && crossesMovedCells(surface.cells)) {
      recastMoved(surface, *posed_, *grid_, movedPolygons, movedCells);
      ++stats_.recastMovedCasts;
    } else {
      ++stats_.keptCasts;
      keptCast[index] = 1;
    }
  };
  const auto castOrKeep = [&](DiscontinuitySurface& surface, size_t index) {
    const std::size_t hash = fanHash(surface);
    recordFanHash(index, hash);
    // Taken: no other surface matches it.
    const std::optional<size_t> then =
        previousByFan.take(hash, [&](size_t i) { return sameFan(previousSurfaces[i], surface); });
    if (!then) {
      castSurface(surface, *posed_, *grid_);
      recordBlock(index, blockOfCells(surface.cells));
      return;
    }
    DiscontinuitySurface& before = previousSurfaces[*then];
    surface.cells = std::move(before.cells);
    surface.intersections = std::move(before.intersections);
    keepCast(surface, index, *then);
  };
  // A surface that is the frame before's surface `then`, taken over whole (by an enumeration's
  // memo) with its cast.
  std::vector<char> takenWhole;  // by index: hinge polygons and fan are the frame before's
  const auto keepWhole = [&](DiscontinuitySurface& surface, size_t index, size_t then) {
    recordFanHash(index, previousByFan.hashOf(then));  // the same fan, moved over
    if (takenWhole.size() <= index) takenWhole.resize(index + 1, 0);
    takenWhole[index] = 1;
    keepCast(surface, index, then);
  };
  const PosedScene& scene = *posed_;
  reference_ = std::make_unique<ExactReference>(scene, grid_, ClosedObjectFaces::kFacingThePoint);
  std::unique_ptr<EdgeAdjacency> previousAdjacency = std::move(adjacency_);
  adjacency_ = std::make_unique<EdgeAdjacency>(scene);
  // What EEE enumeration found in the frame before, read where its inputs are unchanged (not
  // when a light moved: every candidate depends on it).
  EeeCandidateMemo previousCandidates = std::move(eeeCandidates_);
  eeeCandidates_ = {};
  std::optional<UnchangedTopology> unchanged;
  if (change && previousAdjacency && !change->movesLight())
    unchanged = unchangedTopology(*previousAdjacency, *adjacency_);
  const std::optional<EeeCandidateReuse> candidateReuse =
      unchanged ? std::optional<EeeCandidateReuse>(
                      EeeCandidateReuse{previousCandidates, previousIndex, *unchanged})
                : std::nullopt;
  const EeeCandidateReuse* reuseCandidates = candidateReuse ? &*candidateReuse : nullptr;
  // The non-emitter enumeration's vertices, read where every polygon that did not move kept its
  // ids, corners and edges, none shared with a moved one (else a static edge's silhouette test
  // would read moved geometry, and which polygon examines an edge first could change).
  std::map<PolygonId, NonEmitterEvMemo> previousNonEmitter = std::move(nonEmitter_);
  nonEmitter_.clear();
  std::map<PolygonId, CoplanarCrossingMemo> previousCoplanar = std::move(coplanarCrossings_);
  coplanarCrossings_.clear();
  std::map<PolygonId, OccluderPlaneMemo> previousOccluderPlanes = std::move(occluderPlanes_);
  occluderPlanes_.clear();
  bool staticUnchanged = unchanged.has_value();
  for (size_t p = 0; staticUnchanged && p < scene.polygons.size(); ++p) {
    if (movedPolygons[p]) continue;
    staticUnchanged = unchanged->polygons[p] != 0;
    adjacency_->forEachEdgeOf(PolygonId(p), [&](EdgeId e) {
      for (PolygonId q : adjacency_->edges()[e].polygons)
        staticUnchanged = staticUnchanged && !movedPolygons[size_t(q)];
    });
  }
  std::vector<PolygonId> movedIds;
  for (size_t p = 0; p < movedPolygons.size(); ++p)
    if (movedPolygons[p]) movedIds.push_back(PolygonId(p));
  backprojections_ = std::make_unique<BackprojectionBuilder>(scene, *reference_);
  stats_.lights = int(scene.lights.size());
  stats_.gridBytes = grid_->memoryBytes();

  // A memo of the frame before offered to an enumeration by item (FoundByItemReuse): where
  // every polygon that did not move kept its ids and shares no edge with a moved one.
  const auto reuseOf = [&](std::map<PolygonId, FoundByItem>& before, PolygonId light,
                           std::vector<char> UnchangedTopology::*items) {
    const auto it = before.find(light);
    return staticUnchanged && it != before.end() ? std::optional<FoundByItemReuse>(FoundByItemReuse{
                                                       it->second, (*unchanged).*items, movedIds})
                                                 : std::nullopt;
  };
  auto start = Clock::now();
  for (PolygonId light : scene.lights) {
    enumerateEmitterEvSurfaces(scene, *adjacency_, light, surfaces_);
    NonEmitterEvMemo& memo = nonEmitter_[light];
    const std::optional<NonEmitterEvReuse> nonEmitterReuse =
        reuseOf(previousNonEmitter, light, &UnchangedTopology::vertices);
    enumerateNonEmitterEvSurfaces(scene, *adjacency_, *grid_, light, 0, surfaces_, &memo,
                                  nonEmitterReuse ? &*nonEmitterReuse : nullptr);
    stats_.keptNonEmitterVertices += memo.kept;
    stats_.examinedNonEmitterVertices += memo.examined;
    OccluderPlaneMemo& planes = occluderPlanes_[light];
    const std::optional<OccluderPlaneReuse> planeReuse =
        reuseOf(previousOccluderPlanes, light, &UnchangedTopology::polygons);
    enumerateOccluderPlaneSurfaces(scene, *adjacency_, *grid_, light, 0, surfaces_, &planes,
                                   planeReuse ? &*planeReuse : nullptr);
    stats_.keptOccluderPlanes += planes.kept;
    stats_.examinedOccluderPlanes += planes.examined;
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
      case SurfaceKind::kOccluderPlaneOccluderVertex:
        ++stats_.surfacesOccluderPlaneVertex;
        break;
      case SurfaceKind::kLightEdgeCoplanarEdges:  // made after casting, counted there
      case SurfaceKind::kLightEdgeParallelEdgeCrossing:
      case SurfaceKind::kCoplanarEdgesOccluderCrossing:
        break;
    }
  }
  stats_.secondsSurfaces = secondsSince(start);

  start = Clock::now();
  for (size_t k = 0; k < surfaces_.size(); ++k) {
    DiscontinuitySurface& s = surfaces_[k];
    castOrKeep(s, k);
    stats_.storedIntersections += (long long)s.intersections.size();
    stats_.surfaceCellBytes += s.cells.capacity() * sizeof(int);
    stats_.intersectionBytes += s.intersections.capacity() * sizeof(SurfaceIntersection);
  }
  stats_.secondsCasting = secondsSince(start);

  start = Clock::now();
  // A surface's visible pieces are a function of its fan, hinge polygons and cuts: a kept cast
  // with the same hinge polygons has those of the frame before (under its new id).
  std::vector<std::vector<DiscontinuitySegment>> previousVisible = std::move(visible_);
  visible_ = std::move(spareVisible_);
  visible_.clear();
  visible_.reserve(previousVisible.size());
  // By receiver id (lists indexed by polygon, not maps: every visible segment of the scene is
  // filed here every frame).
  std::vector<std::vector<DiscontinuitySegment>> perReceiver(posed_->polygons.size());
  // An update follows which receivers any surface's pieces changed on: a surface's pieces that
  // are those of the frame before (kept, or found again the same) map its old id to its new one
  // (`newIdOf`, planar surfaces then EEE ones by their old ids); a surface whose pieces are new
  // or differ, and one of the frame before no surface took, marks their receivers. A receiver
  // no mark reaches gets the same pieces from the same surfaces, in the same order where the
  // new ids keep the old ones' order: its inputs are those of the frame before, renamed (the
  // receivers' loop, carriedInputs).
  std::vector<char> piecesChanged(change ? scene.polygons.size() : 0, 0);
  std::vector<SurfaceId> newIdOf(change ? previousSurfaces.size() : 0, -1);
  const auto markReceivers = [&](const std::vector<DiscontinuitySegment>& pieces) {
    for (const DiscontinuitySegment& piece : pieces) piecesChanged[size_t(piece.receiver)] = 1;
  };
  const auto addVisible = [&](const DiscontinuitySurface& s, size_t index) {
    std::vector<DiscontinuitySegment> pieces;
    const int then = index < previousIndex.size() ? previousIndex[index] : -1;
    const bool hadPieces = then >= 0 && size_t(then) < previousVisible.size();
    if (hadPieces && keptCast[index] &&
        ((index < takenWhole.size() && takenWhole[index]) ||
         previousSurfaces[size_t(then)].hingePolygons == s.hingePolygons)) {
      pieces = std::move(previousVisible[size_t(then)]);
      for (DiscontinuitySegment& segment : pieces) segment.surface = s.id;
      if (change) newIdOf[size_t(then)] = s.id;
    } else {
      pieces = visibleSegments(s, posed_->polygons);
      if (change && hadPieces && samePieces(previousVisible[size_t(then)], pieces))
        newIdOf[size_t(then)] = s.id;
      else if (change)
        markReceivers(pieces);
    }
    for (const DiscontinuitySegment& segment : pieces) {
      ++stats_.visibleSegments;
      perReceiver[segment.receiver].push_back(segment);
    }
    if (visible_.size() <= index) visible_.resize(index + 1);
    visible_[index] = std::move(pieces);
  };
  for (size_t k = 0; k < surfaces_.size(); ++k) addVisible(surfaces_[k], k);
  stats_.secondsVisibility = secondsSince(start);

  start = Clock::now();
  // The frame before's EEE surfaces, in its traces' order: a kept trace takes its surface's cells
  // over.
  std::vector<EeeSurface> previousEee;
  if (change) previousEee = std::move(eeeSurfaces_);
  eeeSurfaces_ = std::move(spareEee_);
  eeeSurfaces_.clear();
  const double chord = kEeeChordTolerance * scene.extent.diagonalLength();
  std::vector<std::vector<std::pair<Vec3, Vec3>>> eeeOnReceiver(scene.polygons.size());
  std::vector<std::vector<SurfaceId>> eeeSurfacesOnReceiver(scene.polygons.size());  // of those
  std::vector<PolygonId> crossed;
  const auto eeeKeyOf = [&](const EeeSurface& surface) {
    EeeKey key;
    key.light = surface.light;
    key.kind = int(surface.kind);
    key.lightEdge = surface.lightEdge;
    size_t end = 0;
    for (EdgeId e : surface.occluderEdges()) {
      const SceneEdge& edge = adjacency_->edges()[e];
      key.ends[end++] = adjacency_->position(edge.a);
      key.ends[end++] = adjacency_->position(edge.b);
      for (PolygonId polygon : edge.polygons) key.incident.push_back(polygon);
      key.incident.push_back(-1);
    }
    return key;
  };
  // The previous frame's traced EEE surfaces, by what their tracing reads: a surface with the same
  // light, edges (ends and incident polygons, bit for bit) and none of whose cells a moved
  // object's bounds overlap traces the same lines through the same polygons, so its result is
  // kept (not when a light moved: the lines start on it).
  std::vector<EeeTrace> previousTraces;
  if (change) previousTraces = std::move(eeeTraces_);
  eeeTraces_ = std::move(spareTraces_);
  eeeTraces_.clear();
  eeeTraces_.reserve(previousTraces.size());
  TakenOnce previousByKey;
  previousByKey.reserve(previousTraces.size());
  for (size_t i = 0; i < previousTraces.size(); ++i)
    previousByKey.add(previousTraces[i].key.hash());
  previousByKey.seal();
  const bool mayKeepTraces = change && !change->movesLight();
  // The frame before's EEE surfaces were numbered after its planar ones, in trace order.
  const size_t previousPlanar = newIdOf.size();
  if (change) newIdOf.resize(previousPlanar + previousTraces.size(), -1);
  // A trace reads only the polygons its lines cross (traceEeeSurface): none of them moved where
  // no moved object's old or new bounds (with a margin for the crossing's rounding) meet a line.
  std::vector<Box3> movedBounds;
  if (change)
    for (const ObjectMove& move : change->moves)
      for (const Box3& box : {move.boundsBefore, move.boundsAfter})
        movedBounds.push_back(box.expanded(1e-9 * scene.extent.diagonalLength()));
  const auto traceFrom = [&](size_t first, std::map<PolygonId, std::vector<EeeCrossing>>* to) {
    for (size_t k = first; k < eeeSurfaces_.size(); ++k) {
      EeeSurface& s = eeeSurfaces_[k];
      EeeTrace trace;
      trace.key = eeeKeyOf(s);
      // Taken over, not copied: each trace of the frame before is read once at most.
      EeeTrace* kept = nullptr;
      if (mayKeepTraces) {
        const std::optional<size_t> then = previousByKey.take(trace.key.hash(), [&](size_t i) {
          const EeeTrace& before = previousTraces[i];
          const auto meetsMoved = [&](const std::pair<Vec3, Vec3>& line) {
            return std::any_of(movedBounds.begin(), movedBounds.end(), [&](const Box3& b) {
              return b.meetsSegment(line.first, line.second);
            });
          };
          return before.key == trace.key &&
                 (!crossesMovedCells(previousEee[i].cells) ||
                  std::none_of(before.lines.begin(), before.lines.end(), meetsMoved));
        });
        if (then) {
          kept = &previousTraces[*then];
          newIdOf[previousPlanar + *then] = s.id;
        }
        if (kept) {
          s.cells = std::move(previousEee[*then].cells);
          s.truncated = previousEee[*then].truncated;
        }
      }
      if (kept) {
        crossed = std::move(kept->crossed);
        trace.segments = std::move(kept->segments);
        trace.lines = std::move(kept->lines);
        for (DiscontinuitySegment& segment : trace.segments) segment.surface = s.id;
        ++stats_.keptTraces;
      } else {
        trace.segments = traceEeeSurface(s, scene, *adjacency_, *grid_, chord,
                                         to ? &crossed : nullptr, &trace.lines);
        if (!to) crossed.clear();
        if (change) markReceivers(trace.segments);
      }
      for (DiscontinuitySegment segment : trace.segments) {
        ++stats_.eeeSegments;
        eeeOnReceiver[segment.receiver].push_back({segment.p0, segment.p1});
        eeeSurfacesOnReceiver[segment.receiver].push_back(segment.surface);
        perReceiver[segment.receiver].push_back(std::move(segment));
      }
      stats_.surfaceCellBytes += s.cells.capacity() * sizeof(int);
      stats_.eeeSurfacesTruncated += s.truncated ? 1 : 0;
      if (to)
        for (PolygonId p : crossed) (*to)[s.light].push_back({s.first, s.second, p});
      trace.crossed = std::move(crossed);
      crossed.clear();
      eeeTraces_.push_back(std::move(trace));
    }
  };
  const std::vector<PolygonId> eeeLights =
      options_.eeeSurfaces ? scene.lights : std::vector<PolygonId>{};
  // Planar surfaces made from what casting found: parallel-edge crossings and coplanar edges,
  // numbered after surfaces_ (afterCasting[k] is surface surfaces_.size() + k). (In storage kept
  // from frame to frame, as the surfaces' own list.)
  std::vector<DiscontinuitySurface>& afterCasting = afterCastingStorage_;
  afterCasting.clear();
  // Their planes' surfaces are read from the frame before's where the planes' fans kept their
  // casts (not when a light moved: every plane depends on it).
  std::map<PolygonId, ParallelCrossingMemo> previousParallel = std::move(parallelCrossings_);
  parallelCrossings_.clear();
  std::vector<int> sameCutsAs;
  // Per surface of afterCasting: the index of the frame before's surface it is, taken over whole
  // (cast included), else -1.
  std::vector<int> takenFrom;
  std::vector<char> keptWhole;  // and whether its cast was not taken before
  // Marks the surfaces of afterCasting taken over whole since the last call (takenFrom holds
  // them, or nothing past the last call) as taken, before anything looks for casts by fan: one
  // moved out whole matches nothing. Where another surface took its cast first, its cells and
  // cuts were moved out: cast as any other.
  const auto markTakenWhole = [&] {
    takenFrom.resize(afterCasting.size(), -1);
    for (size_t k = keptWhole.size(); k < afterCasting.size(); ++k) {
      keptWhole.push_back(takenFrom[k] >= 0 && previousByFan.take(size_t(takenFrom[k])));
      if (takenFrom[k] >= 0 && !keptWhole[k]) {
        afterCasting[k].cells.clear();
        afterCasting[k].intersections.clear();
      }
    }
  };
  if (change && !change->movesLight()) {
    sameCutsAs.assign(surfaces_.size(), -1);
    for (size_t k = 0; k < surfaces_.size() && k < keptCast.size(); ++k)
      if (keptCast[k]) sameCutsAs[k] = previousIndex[k];
  }
  for (PolygonId light : options_.parallelEdgeCrossings ? scene.lights : std::vector<PolygonId>{}) {
    const auto before = previousParallel.find(light);
    const std::optional<ParallelCrossingReuse> parallelReuse =
        change && !change->movesLight() && before != previousParallel.end()
            ? std::optional<ParallelCrossingReuse>(
                  ParallelCrossingReuse{before->second, sameCutsAs, previousSurfaces, takenFrom})
            : std::nullopt;
    ParallelCrossingMemo& memo = parallelCrossings_[light];
    parallelEdgeCrossingSurfaces(scene, *adjacency_, surfaces_, light, SurfaceId(surfaces_.size()),
                                 afterCasting, &memo, parallelReuse ? &*parallelReuse : nullptr);
    markTakenWhole();
    stats_.keptParallelPlanes += memo.keptPlanes;
    stats_.examinedParallelPlanes += memo.examinedPlanes;
  }
  stats_.surfacesParallelEdgeCrossing = int(afterCasting.size());
  for (PolygonId light : eeeLights) {
    std::vector<CoplanarEdgePair> pairs;
    for (EeeSurface& s : enumerateEeeSurfaces(scene, *adjacency_, surfaces_, light, 0, &pairs,
                                              &eeeCandidates_, reuseCandidates))
      eeeSurfaces_.push_back(std::move(s));
    coplanarEdgeSurfaces(scene, *adjacency_, pairs, light, SurfaceId(surfaces_.size()),
                         afterCasting);
    if (!options_.coplanarEdgeCrossings) continue;
    // Offered on the non-emitter enumeration's terms: the same polygons, edges and light.
    const auto before = previousCoplanar.find(light);
    takenFrom.resize(afterCasting.size(), -1);
    const std::optional<CoplanarCrossingReuse> coplanarReuse =
        staticUnchanged && before != previousCoplanar.end()
            ? std::optional<CoplanarCrossingReuse>(CoplanarCrossingReuse{
                  before->second, unchanged->edges, movedIds, previousSurfaces, takenFrom})
            : std::nullopt;
    CoplanarCrossingMemo& memo = coplanarCrossings_[light];
    const size_t crossingsBefore = afterCasting.size();
    coplanarEdgeCrossingSurfaces(scene, *adjacency_, *grid_, pairs, light,
                                 SurfaceId(surfaces_.size()), afterCasting, &memo,
                                 coplanarReuse ? &*coplanarReuse : nullptr);
    stats_.surfacesCoplanarEdgeCrossing += int(afterCasting.size() - crossingsBefore);
    markTakenWhole();
    stats_.keptCoplanarPairs += memo.keptPairs;
    stats_.examinedCoplanarPairs += memo.examinedPairs;
  }
  // The parallel-edge and coplanar-edge fans are planar surfaces like the EV ones (made from the
  // EV fans' stored intersections and the EEE pairs): cast, clipped by visibility,
  // numbered after them; the EEE surfaces are numbered after all planar ones.
  keptWhole.resize(afterCasting.size(), 0);
  for (size_t k = 0; k < afterCasting.size(); ++k) {
    DiscontinuitySurface& s = afterCasting[k];
    if (keptWhole[k])
      keepWhole(s, surfaces_.size(), size_t(takenFrom[k]));
    else
      castOrKeep(s, surfaces_.size());
    stats_.storedIntersections += (long long)s.intersections.size();
    stats_.surfaceCellBytes += s.cells.capacity() * sizeof(int);
    stats_.intersectionBytes += s.intersections.capacity() * sizeof(SurfaceIntersection);
    addVisible(s, surfaces_.size());
    surfaces_.push_back(std::move(s));
  }
  stats_.surfacesCoplanarEdges = int(afterCasting.size()) - stats_.surfacesParallelEdgeCrossing -
                                 stats_.surfacesCoplanarEdgeCrossing;
  afterCasting.clear();  // all moved into surfaces_
  // The frame before's surfaces whose pieces no surface took over (visible_ holds a surface's
  // pieces at its index).
  for (size_t i = 0; change && i < std::min(previousPlanar, previousVisible.size()); ++i)
    if (newIdOf[i] < 0) markReceivers(previousVisible[i]);
  for (size_t k = 0; k < eeeSurfaces_.size(); ++k)
    eeeSurfaces_[k].id = SurfaceId(surfaces_.size() + k);
  // The polygons the light-edge surfaces' lines cross hold the third edges of the
  // three-occluder-edge surfaces whose lines leave the light through its edges.
  // (Their lists' storage is kept from frame to frame: a large room's run to millions.)
  std::map<PolygonId, std::vector<EeeCrossing>>& crossings = eeeCrossings_;
  for (auto& [light, list] : crossings) list.clear();
  traceFrom(0, &crossings);
  stats_.surfacesEee = int(eeeSurfaces_.size());
  const size_t lightEdgeSurfaces = eeeSurfaces_.size();
  for (PolygonId light : options_.occluderEeeSurfaces ? eeeLights : std::vector<PolygonId>{}) {
    const SurfaceId firstId = SurfaceId(surfaces_.size() + eeeSurfaces_.size());
    for (EeeSurface& s :
         enumerateOccluderEeeSurfaces(scene, *adjacency_, surfaces_, crossings[light], light,
                                      firstId, &eeeCandidates_, reuseCandidates))
      eeeSurfaces_.push_back(std::move(s));
  }
  stats_.surfacesEeeOccluder = int(eeeSurfaces_.size() - lightEdgeSurfaces);
  stats_.keptCandidateCuts = eeeCandidates_.keptCuts;
  stats_.examinedCandidateCuts = eeeCandidates_.foundCuts;
  traceFrom(lightEdgeSurfaces, nullptr);
  for (size_t i = 0; change && i < previousTraces.size(); ++i)
    if (newIdOf[previousPlanar + i] < 0) markReceivers(previousTraces[i].segments);
  stats_.secondsEee = secondsSince(start);

  start = Clock::now();
  const double sliver = kSliverSize * scene.extent.diagonalLength();
  double backprojectionSeconds = 0;
  const double diagonal = scene.extent.diagonalLength();
  // Whether a receiver's own events (contact lines, light planes, horizons) may differ from the
  // frame before: they read the polygons the grid lists in the receiver's box (with the lights
  // its plane cuts, for the horizons), so they are the same where no cell of that box is one a
  // moved object's old or new bounds overlap (a moved light changes them all: not carried).
  const auto planeEventsMayChange = [&](const WorldPolygon& receiver) {
    Box3 region = receiver.bounds.expanded(2e-9 * diagonal);
    for (PolygonId light : scene.lights) {
      const WorldPolygon& lightPolygon = scene.polygons[light];
      bool above = false, notAbove = false;
      for (const Vec3& v : lightPolygon.vertices)
        (receiver.plane.signedDistance(v) > 0 ? above : notAbove) = true;
      if (above && notAbove) region.extend(lightPolygon.bounds);
    }
    bool touched = false;
    grid_->forEachCellOverlappingBox(region,
                                     [&](int cell) { touched = touched || movedCells[cell] != 0; });
    return touched;
  };
  for (const WorldPolygon& receiver : scene.polygons) {
    if (receiver.isLight) continue;
    const auto beforeIt = change ? previous.find(receiver.id) : previous.end();
    ReceiverData* before = beforeIt != previous.end() ? &beforeIt->second : nullptr;
    const bool moved = change && change->moveOf(receiver.objectIndex) != nullptr;
    std::vector<std::pair<Vec3, Vec3>>& eee = eeeOnReceiver[receiver.id];
    const bool sameEee = before && before->eeeInputs == eee;
    std::vector<DiscontinuitySegment> segments;
    ReceiverMesh::Renaming renamed;
    // A receiver no changed piece reaches, whose own events are the same, takes its inputs of
    // the frame before (renamed) instead of assembling them: the same segments, so its mesh is
    // kept (below) as a comparison of assembled inputs would keep it.
    const bool carried =
        sameEee && !moved && !change->movesLight() && !piecesChanged[size_t(receiver.id)] &&
        !planeEventsMayChange(receiver) &&
        carriedInputs(before->inputs, newIdOf, perReceiver[receiver.id].size(), segments, renamed);
    if (carried) {
      ++stats_.carriedInputs;
      // Its own events counted as assembling them counts them.
      for (const DiscontinuitySegment& segment : segments)
        if (long long* count = ownEventCount(scene, segment.surface, stats_)) ++*count;
    } else {
      // Segments end where events meet, computed apart: extend their ends (see extended()). The
      // joints inside an EEE polyline are shared exactly by consecutive pieces and stay as they
      // are. An end is open when no other segment of its surface ends there: counted in one sorted
      // list (a map of counts allocated a node per end, thousands on a floor, every frame).
      using EndKey = std::pair<SurfaceId, std::array<double, 3>>;
      const auto endKey = [](const DiscontinuitySegment& s, const Vec3& p) {
        return EndKey{s.surface, std::array<double, 3>{p.x, p.y, p.z}};
      };
      const std::vector<DiscontinuitySegment>& onReceiver = perReceiver[receiver.id];
      std::vector<EndKey> ends;
      ends.reserve(2 * onReceiver.size());
      for (const DiscontinuitySegment& segment : onReceiver) {
        ends.push_back(endKey(segment, segment.p0));
        ends.push_back(endKey(segment, segment.p1));
      }
      std::sort(ends.begin(), ends.end());
      const auto isOpen = [&](const EndKey& key) {
        const auto [from, to] = std::equal_range(ends.begin(), ends.end(), key);
        return to - from == 1;
      };
      const double by = kSegmentExtension * diagonal;
      segments.reserve(onReceiver.size());
      for (const DiscontinuitySegment& segment : onReceiver) {
        const bool open0 = isOpen(endKey(segment, segment.p0));
        const bool open1 = isOpen(endKey(segment, segment.p1));
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
    }

    // An update keeps what a full computation would compute again: a receiver's mesh where it
    // would be built from the same segments in the same order (and the same EEE polylines), or
    // else edits it locally into exactly the mesh those segments build (ReceiverMesh::update);
    // and a face's backprojections and verification where the face kept its boundary and
    // nothing moved into the cones they read (keepsFaceData).
    const bool keepMesh =
        carried || (sameEee && !moved && sameSegmentGeometry(before->inputs, segments, renamed));
    const bool editMesh = before && !moved && !keepMesh;
    const double snap = kSegmentSnap * diagonal;
    ReceiverData data = keepMesh
                            ? std::move(*before)
                            : ReceiverData{editMesh ? std::move(before->mesh)
                                                    : ReceiverMesh(receiver, kTileShare * diagonal),
                                           {},
                                           SegmentProximity(eee),
                                           {},
                                           eee,
                                           {}};
    SegmentProximity eeeBefore;
    std::vector<FaceData> oldFaceData;
    std::vector<int> previousFace;  // each face's index in the frame before, or -1
    if (keepMesh) {
      data.mesh.renumberSurfaces(renamed);
      oldFaceData = std::move(data.faces);
      for (const MeshFace& face : data.mesh.faces()) previousFace.push_back(face.index);
      ++stats_.keptMeshes;
    } else if (editMesh) {
      eeeBefore = std::move(before->eeeSegments);
      oldFaceData = std::move(before->faces);
      ReceiverMesh::UpdateStats edit;
      previousFace = data.mesh.update(segments, snap, &edit);
      stats_.removedSurfaces += edit.removedSurfaces;
      stats_.insertedSurfaces += edit.insertedSurfaces;
      stats_.resweptMeshes += edit.rebuilt ? 1 : 0;
      ++stats_.editedMeshes;
    } else {
      data.mesh.insert(segments, snap);
      previousFace.assign(data.mesh.faces().size(), -1);
      ++stats_.rebuiltMeshes;
    }
    // The polylines' surfaces by this computation's numbering (a kept mesh has the same
    // polylines, maybe under other ids).
    data.eeeSurfaceIds = eeeSurfacesOnReceiver[receiver.id];
    data.inputs = std::move(segments);
    // Faces whose data can be taken from the frame before, by their index there.
    // A kept mesh with its polylines (so its faces' probes) unchanged, whose receiver's box with
    // the lights no moved object crosses: no face's cone can admit a moved polygon (each face's
    // box lies in the receiver's), so every face keeps its data (same indices) untouched.
    if (keepMesh && sameEee && !change->movesLight() && !isCrossed(receiver.bounds, *change)) {
      data.faces = std::move(oldFaceData);
      stats_.reusedFaces += (long long)data.faces.size();
      stats_.recomputedFaces += (long long)data.faces.size();
      receivers_.emplace(receiver.id, std::move(data));
      continue;
    }
    std::vector<int> reusable(data.mesh.faces().size(), -1);
    if ((keepMesh || editMesh) && !change->movesLight()) {
      // The polylines of either frame that the other lacks.
      SegmentProximity eeeChanged;
      if (!sameEee) {
        const auto less = [](const std::pair<Vec3, Vec3>& a, const std::pair<Vec3, Vec3>& b) {
          return std::tie(a.first.x, a.first.y, a.first.z, a.second.x, a.second.y, a.second.z) <
                 std::tie(b.first.x, b.first.y, b.first.z, b.second.x, b.second.y, b.second.z);
        };
        std::vector<std::pair<Vec3, Vec3>> then = before->eeeInputs, nowEee = data.eeeInputs,
                                           changed;
        std::sort(then.begin(), then.end(), less);
        std::sort(nowEee.begin(), nowEee.end(), less);
        std::set_symmetric_difference(then.begin(), then.end(), nowEee.begin(), nowEee.end(),
                                      std::back_inserter(changed), less);
        eeeChanged = SegmentProximity(std::move(changed));
      }
      for (const MeshFace& face : data.mesh.faces()) {
        const int g = previousFace[face.index];
        if (g >= 0 &&
            keepsFaceData(data, face, oldFaceData[size_t(g)],
                          keepMesh ? data.eeeSegments : eeeBefore, eeeChanged, sameEee, *change))
          reusable[face.index] = g;
      }
    }
    const auto backprojecting = Clock::now();
    computeFaceBackprojections(receiver.id, data, sliver, [&](int face) -> FaceData* {
      return reusable[face] >= 0 ? &oldFaceData[reusable[face]] : nullptr;
    });
    backprojectionSeconds += secondsSince(backprojecting);
    for (int r : reusable) stats_.reusedFaces += r >= 0 ? 1 : 0;
    stats_.recomputedFaces += (long long)data.mesh.faces().size();
    receivers_.emplace(receiver.id, std::move(data));
  }
  stats_.recomputedFaces -= stats_.reusedFaces;
  const double receiverSeconds = secondsSince(start);
  stats_.secondsBackprojections = backprojectionSeconds - stats_.secondsVerification;
  stats_.secondsMeshing = receiverSeconds - backprojectionSeconds;
  // Their storage kept for the next update (see spareSurfaces_); a build keeps none. (The
  // computation's peak is the same either way: both frames' lists exist while it runs.)
  if (change) {
    previousSurfaces.clear();
    spareSurfaces_ = std::move(previousSurfaces);
    previousTraces.clear();
    spareTraces_ = std::move(previousTraces);
    previousVisible.clear();
    spareVisible_ = std::move(previousVisible);
    previousEee.clear();
    spareEee_ = std::move(previousEee);
    spareFanHashes_ = previousByFan.releaseHashes();
    previousBlocks.clear();
    spareCellBlocks_ = std::move(previousBlocks);
  }
  CHECK(fanHashes_.size() == surfaces_.size() && cellBlocks_.size() == surfaces_.size());
}

const DmStats& DiscontinuityMeshEngine::stats() const {
  if (!statsTallied_) {
    tallyReceivers();
    stats_.updateCacheBytes = updateCacheBytes();
    statsTallied_ = true;
  }
  return stats_;
}

size_t DiscontinuityMeshEngine::updateCacheBytes() const {
  size_t bytes = 0;
  for (const SurfaceCandidates& surface : eeeCandidates_.bySurface) {
    bytes += sizeof(surface) + surface.cuts.capacity() * sizeof(CutCandidates);
    for (const CutCandidates& cut : surface.cuts)
      bytes += cut.found.capacity() * sizeof(EeeCandidate);
  }
  for (const auto& [light, counted] : eeeCandidates_.byLight)
    bytes += counted.counts.memoryBytes() + counted.keys.capacity() * sizeof(std::uint64_t);
  bytes += eeeCandidates_.crossingIds.memoryBytes() +
           eeeCandidates_.crossingRanges.capacity() * sizeof(eeeCandidates_.crossingRanges[0]) +
           eeeCandidates_.crossingCandidates.capacity() * sizeof(EeeCandidate);
  for (const auto* memos : {&nonEmitter_, &occluderPlanes_})
    for (const auto& [light, memo] : *memos)
      for (const auto& entries : memo.byItem) {
        bytes += sizeof(entries) + entries.capacity() * sizeof(entries[0]);
        for (const auto& [polygon, surfaces] : entries)
          bytes += surfaces.capacity() * sizeof(DiscontinuitySurface);
      }
  for (const auto& [light, memo] : coplanarCrossings_)
    for (const CoplanarCrossingMemo::Pair& pair : memo.pairs)
      bytes += sizeof(pair) + pair.entries.capacity() * sizeof(pair.entries[0]);
  for (const auto& [light, memo] : parallelCrossings_) {
    bytes += memo.byFirstFan.capacity() * sizeof(memo.byFirstFan[0]);
    for (const ParallelCrossingMemo::Plane& plane : memo.planes)
      bytes += sizeof(plane) + plane.polygons.capacity() * sizeof(PolygonId) +
               plane.fans.capacity() * sizeof(size_t);
  }
  bytes += afterCastingStorage_.capacity() * sizeof(DiscontinuitySurface);
  bytes += (fanHashes_.capacity() + spareFanHashes_.capacity()) * sizeof(std::size_t) +
           (cellBlocks_.capacity() + spareCellBlocks_.capacity()) * sizeof(CellBlock);
  for (const auto& [light, crossings] : eeeCrossings_)
    bytes += crossings.capacity() * sizeof(EeeCrossing);
  for (const auto& pieces : visible_)
    bytes += sizeof(pieces) + pieces.capacity() * sizeof(DiscontinuitySegment);
  bytes += spareSurfaces_.capacity() * sizeof(DiscontinuitySurface) +
           spareTraces_.capacity() * sizeof(EeeTrace) +
           spareVisible_.capacity() * sizeof(spareVisible_[0]) +
           spareEee_.capacity() * sizeof(EeeSurface);
  for (const EeeTrace& trace : eeeTraces_)
    bytes += sizeof(trace) + trace.segments.capacity() * sizeof(DiscontinuitySegment) +
             trace.lines.capacity() * sizeof(trace.lines[0]) +
             trace.crossed.capacity() * sizeof(PolygonId) + trace.key.incident.heapBytes();
  return bytes;
}

void DiscontinuityMeshEngine::tallyReceivers() const {
  for (const auto& [id, data] : receivers_) {
    stats_.meshVertices += data.mesh.vertexCount();
    stats_.meshEdges += data.mesh.edgeCount();
    stats_.meshFaces += (long long)data.mesh.faces().size();
    stats_.meshBytes += data.mesh.memoryBytes();
    for (const FaceData& faceData : data.faces) {
      for (const Backprojection& bp : faceData.perLight) {
        if (faceData.sliver) break;  // no labels computed
        stats_.unlabelledBackprojections += bp.isLabelled ? 0 : 1;
        for (const auto& cycle : bp.cycles) {
          stats_.backprojectionVertices += (long long)cycle.size();
          stats_.backprojectionBytes += cycle.capacity() * sizeof(BackprojectionVertex);
        }
      }
      stats_.unresolvedFaces += faceData.unresolved ? 1 : 0;
      stats_.sliverFaces += faceData.sliver ? 1 : 0;
    }
  }
}

void DiscontinuityMeshEngine::computeFaceBackprojections(
    PolygonId receiverId, ReceiverData& data, double sliver,
    const std::function<FaceData*(int)>& reuse) {
  const PosedScene& scene = *posed_;
  const Vec3& normal = scene.polygons[receiverId].plane.normal;
  const std::vector<MeshFace>& faces = data.mesh.faces();
  const size_t lights = scene.lights.size();
  // Propagation rests on verification: without it a wrong candidate set would go unnoticed.
  const bool propagate = options_.propagateBackprojections && options_.verifyFaces;

  // Face adjacency, and for each crossing the polygons its events name (or none: from scratch).
  std::vector<std::vector<std::pair<int, int>>> neighbours(faces.size());  // (face, crossing)
  std::vector<std::optional<std::vector<PolygonId>>> named;
  if (propagate) {
    const CrossingOccluders crossingOccluders(scene, *adjacency_, surfaces_, eeeSurfaces_);
    for (const FaceCrossing& c : data.mesh.faceCrossings()) {
      std::vector<PolygonId> polygons;
      named.push_back(crossingOccluders.addNamedPolygons(c.surfaces, polygons)
                          ? std::optional(std::move(polygons))
                          : std::nullopt);
      neighbours[c.face].push_back({c.other, int(named.size()) - 1});
      neighbours[c.other].push_back({c.face, int(named.size()) - 1});
    }
  }
  // Per face and light the cone's polygons, and whether the face may lend them: its labels were
  // verified at its corners (an event crossing it would make them wrong at its neighbours).
  std::vector<std::vector<std::vector<PolygonId>>> occluders(faces.size());
  std::vector<char> isSource(faces.size(), 0);
  data.faces.assign(faces.size(), {});

  const auto verify = [&](const MeshFace& face, FaceData& faceData, std::vector<int>& compared) {
    compared.assign(lights, 0);
    if (!options_.verifyFaces) return false;
    const auto verifying = Clock::now();
    faceData.unresolved =
        !labelsHoldAtCorners(data.mesh, face, faceData, data.eeeSegments, &compared);
    stats_.secondsVerification += secondsSince(verifying);
    return true;
  };

  const auto computeFace = [&](int f) {
    const MeshFace& face = faces[f];
    FaceData& faceData = data.faces[f];
    for (const Vec3& corner : data.mesh.faceCorners(f)) faceData.bounds.extend(corner);
    faceData.sliver = face.area <= sliver * sliver;
    occluders[f].assign(lights, {});
    if (faceData.sliver) {  // answered at the point: its labels would not be used
      for (PolygonId light : scene.lights) faceData.perLight.push_back({light, false, {}});
      return;
    }
    // Beside an EEE polyline the sample may lie across the true conic from the mesh's edge.
    const bool mayPropagate = propagate && !data.eeeSegments.near(face.samplePoint, nearEee());
    std::vector<char> propagated(lights, 0);
    for (size_t l = 0; l < lights; ++l) {
      const PolygonId light = scene.lights[l];
      // The verified neighbour offering the fewest candidates.
      std::optional<std::vector<PolygonId>> candidates;
      for (const auto& [g, c] : neighbours[f]) {
        if (!mayPropagate) break;
        if (!isSource[g] || !named[c]) continue;
        // A neighbour that sees nothing of the light for want of a cone (behind the light's
        // plane) has no occluders to lend.
        if (data.faces[g].perLight[l].cycles.empty() && occluders[g][l].empty()) continue;
        if (candidates && candidates->size() <= occluders[g][l].size() + named[c]->size()) continue;
        candidates = occluders[g][l];
        candidates->insert(candidates->end(), named[c]->begin(), named[c]->end());
      }
      if (candidates) {
        std::sort(candidates->begin(), candidates->end());
        candidates->erase(std::unique(candidates->begin(), candidates->end()), candidates->end());
        faceData.perLight.push_back(backprojections_->computeAmong(
            light, face.samplePoint, normal, receiverId, *candidates, occluders[f][l]));
        propagated[l] = 1;
      } else {
        faceData.perLight.push_back(backprojections_->compute(light, face.samplePoint, normal,
                                                              receiverId, occluders[f][l]));
        if (!faceData.perLight.back().isLabelled)
          if (auto labelled = labelledElsewhere(data.mesh, face, faceData.perLight.back(),
                                                data.eeeSegments, occluders[f][l]))
            faceData.perLight.back() = std::move(*labelled);
      }
    }
    std::vector<int> compared;
    bool verified = verify(face, faceData, compared);
    // A propagated backprojection is kept only where verification vouches for it: labelled,
    // compared at a corner at least, and the face resolved. Otherwise from scratch, re-verified.
    bool redo = false;
    for (size_t l = 0; l < lights; ++l)
      redo = redo || (propagated[l] && (!verified || faceData.unresolved ||
                                        !faceData.perLight[l].isLabelled || compared[l] == 0));
    if (redo) {
      // Verification compares label sets, so labels from scratch equal to the propagated ones
      // (the face is truly unresolved) get the same verdict: only changed labels are re-verified.
      bool changed = false;
      for (size_t l = 0; l < lights; ++l) {
        if (!propagated[l]) continue;
        Backprojection fresh = backprojections_->compute(scene.lights[l], face.samplePoint, normal,
                                                         receiverId, occluders[f][l]);
        const Backprojection& old = faceData.perLight[l];
        changed = changed || fresh.isLabelled != old.isLabelled ||
                  (fresh.isLabelled && !sameLabels(fresh, old, *adjacency_));
        faceData.perLight[l] = std::move(fresh);
        propagated[l] = 0;
        ++stats_.propagationFallbacks;
      }
      if (changed) {
        faceData.unresolved = false;
        verified = verify(face, faceData, compared);
      }
    }
    for (size_t l = 0; l < lights; ++l) stats_.propagatedBackprojections += propagated[l];
    bool lends = verified && !faceData.unresolved && mayPropagate;
    for (size_t l = 0; l < lights; ++l)
      lends = lends && faceData.perLight[l].isLabelled && compared[l] > 0;
    isSource[f] = lends ? 1 : 0;
  };

  // Breadth first through face adjacency, so that most faces have a computed neighbour.
  std::vector<char> queued(faces.size(), 0);
  std::vector<int> queue;
  for (size_t seed = 0; seed < faces.size(); ++seed) {
    if (queued[seed]) continue;
    queued[seed] = 1;
    queue.assign(1, int(seed));
    for (size_t next = 0; next < queue.size(); ++next) {
      const int f = queue[next];
      if (FaceData* kept = reuse ? reuse(f) : nullptr) {
        data.faces[f] = std::move(*kept);  // each face of the frame before is taken once
      } else {
        computeFace(f);
      }
      for (const auto& [g, c] : neighbours[f])
        if (!queued[g]) {
          queued[g] = 1;
          queue.push_back(g);
        }
    }
  }
}

std::vector<Vec3> DiscontinuityMeshEngine::cornerProbes(const ReceiverMesh& mesh,
                                                        const MeshFace& face,
                                                        const SegmentProximity& eeeSegments) const {
  // Events meeting at one point leave clusters of corners a few ulps apart: one check each.
  const double apart = 1e-7 * posed_->extent.diagonalLength();
  std::vector<Vec3> checked, probes;
  for (const Polygon3& cycle : mesh.faceBoundary(face.index))
    for (size_t i = 0; i < cycle.size(); ++i) {
      const Vec3& corner = cycle[i];
      if (std::any_of(checked.begin(), checked.end(),
                      [&](const Vec3& c) { return distance(c, corner) <= apart; }))
        continue;
      checked.push_back(corner);
      // Just inside the face near the corner, else farther in: a point that falls outside it (a
      // concave corner, a sliver) proves nothing, and beside an EEE polyline the labels may be
      // those of the conic's other side (the polyline stands within its tolerance of the conic).
      for (const Vec3& p : probeCandidates(cycle, i, face.samplePoint)) {
        if (!mesh.isInside(p, face.index) || eeeSegments.near(p, nearEee())) continue;
        probes.push_back(p);
        break;
      }
    }
  return probes;
}

bool DiscontinuityMeshEngine::isAlias(const Backprojection& atSample, const Backprojection& here,
                                      const Vec3& p, const WorldPolygon& receiver) const {
  // Labels that differ only where the region is degenerate at one of the two points (an occluder
  // vertex whose shadow lies on a light edge is a vertex of the region there, and a crossing of
  // two lines a little further on) describe the same region: the sample's labels evaluated at p
  // give p's own region. A missing event between the sample and p would not: evaluated beyond
  // it the labels give another region, off by the distance to the event or its square, far more
  // than rounding except within rounding of the event itself.
  const Vec3& n = receiver.plane.normal;
  const Rgb fromSample = backprojections_->irradiance({atSample}, p, n, receiver.id);
  const Rgb own = backprojections_->irradiance({here}, p, n, receiver.id);
  const double exitance = posed_->materialOf(posed_->polygons[here.light]).emission.maxComponent();
  const double slack = 1e-12 * std::max(own.maxComponent(), 1e-3 * exitance);
  return fromSample.isFinite() && own.isFinite() && std::abs(fromSample.r - own.r) <= slack &&
         std::abs(fromSample.g - own.g) <= slack && std::abs(fromSample.b - own.b) <= slack;
}

std::optional<Backprojection> DiscontinuityMeshEngine::labelledElsewhere(
    const ReceiverMesh& mesh, const MeshFace& face, const Backprojection& atSample,
    const SegmentProximity& eeeSegments, std::vector<PolygonId>& occluders) const {
  // More or fewer than two features meet at a vertex of the visible region seen from the sample
  // (an occluder edge's shadow through a light corner, say): a point of the face off that
  // alignment has the face's labels, which hold over the whole face. Tried halfway from the
  // sample to each corner, in the boundary's canonical order; beside an EEE polyline a point may
  // see the other side of the conic, so those are not tried. The labels found must give the
  // sample's own light there: the sample may see a part of the light the other point does not (a
  // missing event between them) while every corner agrees with the other point, and nothing else
  // would notice. (Added while diagnosing a box's side whose face answered 0.47% off this way; the
  // light its sample saw there turned out to be the reference's own fault, see
  // ExactReference::coneOf, but the check costs an evaluation only where a sample is unlabelled.)
  const PolygonId light = atSample.light;
  const WorldPolygon& receiver = posed_->polygons[mesh.receiver()];
  for (const Polygon3& cycle : mesh.faceBoundary(face.index))
    for (const Vec3& corner : cycle) {
      const Vec3 q = (corner + face.samplePoint) * 0.5;
      if (!mesh.isInside(q, face.index) || eeeSegments.near(q, nearEee())) continue;
      std::vector<PolygonId> cone;
      Backprojection there =
          backprojections_->compute(light, q, receiver.plane.normal, receiver.id, cone);
      if (!there.isLabelled || !isAlias(there, atSample, face.samplePoint, receiver)) continue;
      occluders = std::move(cone);
      return there;
    }
  return std::nullopt;
}

bool DiscontinuityMeshEngine::labelsHoldAtCorners(const ReceiverMesh& mesh, const MeshFace& face,
                                                  const FaceData& data,
                                                  const SegmentProximity& eeeSegments,
                                                  std::vector<int>* compared) const {
  const WorldPolygon& receiver = posed_->polygons[mesh.receiver()];
  for (const Vec3& p : cornerProbes(mesh, face, eeeSegments))
    for (size_t l = 0; l < posed_->lights.size(); ++l) {
      const Backprojection& atSample = data.perLight[l];
      if (!atSample.isLabelled) continue;
      const Backprojection here =
          backprojections_->compute(posed_->lights[l], p, receiver.plane.normal, receiver.id);
      // Unlabelled here (more or fewer than two features meet at a vertex of the region: an
      // occluder's corner lying on a light edge makes one wherever the occluder hides part of the
      // light): no labels to compare, but the sample's labels must still give p's own light, the
      // region computed at p. A card standing on the light's edge hid a sliver of it at one corner
      // of a face whose sample saw none of it, and every other corner agreed.
      if (!here.isLabelled) {
        if (!isAlias(atSample, here, p, receiver)) return false;
        continue;
      }
      if (compared) ++(*compared)[l];
      if (!sameLabels(here, atSample, *adjacency_) && !isAlias(atSample, here, p, receiver))
        return false;
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
  if (data.faces[face].answersAtPoint()) return atPoint(p, n, receiver);
  return backprojections_->irradiance(data.faces[face].perLight, p, n, receiver);
}

double DiscontinuityMeshEngine::nearEee() const {
  return 2 * kEeeChordTolerance * posed_->extent.diagonalLength();
}

Rgb DiscontinuityMeshEngine::atPoint(const Vec3& p, const Vec3& n, PolygonId receiver) const {
  // The visible region computed where the point is, used as it is: labelling it and evaluating
  // the labels again (the backprojection's round trip) loses digits where the point is
  // degenerate (a corner of a sliver where events meet: 2% at one such point).
  return reference_->irradiance(p, n, receiver);
}

std::optional<Rgb> DiscontinuityMeshEngine::irradiance(const Vec3& p, const Vec3& n) const {
  const auto answered = query(p, n);
  return answered ? std::optional(answered->irradiance) : std::nullopt;
}

std::optional<DiscontinuityMeshEngine::Query> DiscontinuityMeshEngine::query(const Vec3& p,
                                                                             const Vec3& n) const {
  // A point on the edge shared by coplanar receivers (a triangulated quad's diagonal) lies on
  // each within rounding, and in the faces of one only: the first whose mesh holds it answers.
  // Only those coplanar with the nearest: another plane through the point within the locator's
  // tolerance is another receiver, whose value is not the point's (a needle of a polygon dipping
  // 7e-13 below the floor answered with the floor's light: the dm_geometry fuzzer).
  std::vector<ReceiverMatch> matches = locateReceivers(*posed_, *grid_, p, n);
  // Lights have no mesh: a point on a card that crosses the light's plane beside the light's edge
  // matched the light (within the locator's tolerance, at distance 0) before the card, and the
  // query answered nothing for a point of a receiver.
  std::erase_if(matches, [&](const ReceiverMatch& m) { return !receivers_.count(m.polygon); });
  if (matches.empty()) return std::nullopt;
  const ReceiverMatch* match = &matches.front();
  const Vec3& nearestNormal = posed_->polygons[match->polygon].plane.normal;
  std::optional<int> face;
  for (const ReceiverMatch& m : matches) {
    if (dot(posed_->polygons[m.polygon].plane.normal, nearestNormal) < 1 - 1e-9) continue;
    face = receivers_.at(m.polygon).mesh.locate(posed_->polygons[m.polygon].plane.project(p));
    if (face) {
      match = &m;
      break;
    }
  }
  const auto it = receivers_.find(match->polygon);  // every match has a mesh (above)
  const WorldPolygon& receiver = posed_->polygons[match->polygon];
  const Vec3 onPlane = receiver.plane.project(p);
  const auto atPointFor = [&](Answer why) {
    return Query{withoutRoundingBelowZero(atPoint(p, n, match->polygon)), why};
  };
  // At a contact (a box's edge or corner on the floor, a card lying on it) the point lies on
  // another polygon: irradiance jumps there, each face around holds its own one-sided limit, and
  // DESIGN.md §5's value is the point's own (a polygon through it hides nothing, the occluder's
  // other faces hide what they hide), which only the point-wise computation follows.
  if (liesOnAnotherPolygon(onPlane, match->polygon)) return atPointFor(Answer::kOnAnotherPolygon);
  // The locator accepts points within its tolerance outside the polygon (a point on the diagonal
  // of a triangulated quad may match the triangle it is an ulp outside of): no face holds them.
  if (!face) return atPointFor(Answer::kOutsideFaces);
  if (it->second.faces[*face].sliver) {
    // A sliver is made by events a rounding apart: p is then as close to a neighbour, whose
    // labels give its value to within that distance (irradiance is continuous where no polygon
    // touches the receiver, and contacts were answered above).
    face = faceBesideSliver(it->second, *face, onPlane);
    if (!face) return atPointFor(Answer::kSliverFace);
  }
  if (it->second.faces[*face].unresolved) return atPointFor(Answer::kUnresolvedFace);
  std::vector<int> answering{*face};
  if (it->second.eeeSegments.near(onPlane, nearEee())) {
    // Within the polylines' tolerance of an approximated conic the face may be the neighbour's:
    // the face is one on the point's side of every EEE surface near it (the exact side test).
    answering = facesBySides(it->second, *face, onPlane);
    if (answering.empty()) return atPointFor(Answer::kNearEeePolyline);
  }
  // The faces' labels evaluated at p; several faces (p on an EEE surface within rounding, its
  // side unknown) answer only where they agree, the true value being one of theirs.
  std::optional<Rgb> value;
  for (const int f : answering) {
    const FaceData& data = it->second.faces[size_t(f)];
    // An unlabelled backprojection has nothing to evaluate at p: it would be computed at p.
    for (const Backprojection& bp : data.perLight)
      if (!bp.isLabelled) return atPointFor(Answer::kUnlabelled);
    const Rgb e = backprojections_->irradiance(data.perLight, p, n, match->polygon);
    if (isDegenerate(e)) return atPointFor(Answer::kDegenerate);
    if (value && !agree(*value, e)) return atPointFor(Answer::kNearEeePolyline);
    if (!value) value = e;
  }
  return Query{withoutRoundingBelowZero(*value), Answer::kMesh};
}

bool DiscontinuityMeshEngine::agree(const Rgb& a, const Rgb& b) {
  // A hundred times below what the engine answers to (1e-9 relative), so that either value is
  // within that of the true one when the true one is among them.
  const double scale = std::max(a.maxComponent(), b.maxComponent());
  const double bound = 1e-11 * scale;
  return std::abs(a.r - b.r) <= bound && std::abs(a.g - b.g) <= bound &&
         std::abs(a.b - b.b) <= bound;
}

std::optional<int> DiscontinuityMeshEngine::faceBesideSliver(const ReceiverData& data, int sliver,
                                                             const Vec3& p) const {
  // Within this fraction of the scene of a face, its labels give p's value to about that
  // relative precision: a thousand times below what the engine answers to (1e-9).
  const double beside = 1e-12 * posed_->extent.diagonalLength();
  for (const NearCrossing& c : data.mesh.crossingsNear(sliver, p, beside)) {
    const FaceData& other = data.faces[size_t(c.crossing.other)];
    if (!other.sliver && !other.unresolved) return c.crossing.other;
  }
  return std::nullopt;
}

std::vector<int> DiscontinuityMeshEngine::facesBySides(const ReceiverData& data, int located,
                                                       const Vec3& p) const {
  // A true conic lies within its polyline's chord tolerance (half of nearEee) of it. A witness is
  // a point near p farther than nearEee from every polyline, so in no sliver between a polyline
  // and its conic: there the labels of the face holding it are exact.
  //
  // eeeSide rounds at about 1e-12 (its scaling), so the sign of a relative side value ten times
  // larger is certain; below that it is computed exactly. None on the quadric itself.
  constexpr double kCertainSide = 1e-11;
  const auto sideOf = [&](const EeeSurface& s, const Vec3& x) -> std::optional<bool> {
    const double side = eeeSide(s, *posed_, *adjacency_, x);
    if (std::abs(side) > kCertainSide) return side > 0;
    const std::optional<int> sign = exactEeeSideSign(s, *posed_, *adjacency_, x);
    if (!sign || *sign == 0) return std::nullopt;
    return *sign > 0;
  };
  // Tiling lines are no events: walks and searches cross them as they cross EEE polylines.
  const auto crossable = [&](SurfaceId id) {
    return id >= SurfaceId(surfaces_.size()) || id == ReceiverMesh::kTile;
  };
  // The face of witness w holds p when the walk from p to w crosses no event but EEE polylines,
  // and p lies on w's side of every conic that may pass between them (within the walk's length
  // and the chord tolerance of p). Sides are compared near p only: a quadric's zero set reaches
  // beyond its event (where its transversals miss an edge's segment), so a face's far sample may
  // lie on either side. Where p lies on a surface within rounding, its side is unknown: faces are
  // gathered until witnesses on both sides of each such surface are found, and the caller answers
  // only when their labels agree at p (the value is one of theirs).
  // How far off p a walk starts where it cannot start at p. Irradiance is continuous there
  // (contacts were answered before), so the labels that hold there give p's value to within its
  // gradient times this distance, which must stay below what the engine answers to: 1e-9 of
  // values down to 1e-4 of the exitance. Beside a lamp (desk-475: 200 W/m^3 under exitance 110)
  // 1e-12 of the scene moved a value by 7e-10 W/m^2, 6e-8 of that floor; 1e-14 of the scene is a
  // few dozen ulps of its coordinates, where the walk still tells faces apart.
  const double offStart = 1e-14 * posed_->extent.diagonalLength();
  std::vector<const EeeSurface*> near;
  std::vector<std::optional<bool>> sides;  // p's, none where p lies on the surface
  double gathered = 0;                     // the radius `near` was gathered in
  std::vector<int> faces;                  // those witnesses found, in the order found
  std::map<const EeeSurface*, int> seen;   // sides (1: negative, 2: positive) of p's undecided
  const auto complete = [&] {
    if (faces.empty()) return false;
    for (size_t k = 0; k < near.size(); ++k)
      if (!sides[k] && seen[near[k]] != 3) return false;
    return true;
  };
  const auto witnessed = [&](const Vec3& w) {
    if (data.eeeSegments.near(w, nearEee())) return false;
    // From p; where p lies within rounding of a vertex (where events meet, often several a few
    // ulps apart) the walk cannot start there, or leaves it across the events meeting there, and
    // starts a little off p towards w instead.
    std::optional<MeshWalk> walk = data.mesh.walk(located, p, w);
    const auto onlyEeeCrossed = [&] {
      return std::all_of(walk->surfaces.begin(), walk->surfaces.end(), crossable);
    };
    if (!walk || !onlyEeeCrossed()) {
      const Vec3 start = p + (w - p) * (offStart / distance(p, w));
      const std::optional<int> startFace = data.mesh.locate(start);
      if (!startFace) return false;
      walk = data.mesh.walk(*startFace, start, w);
    }
    if (!walk || !onlyEeeCrossed()) return false;
    const FaceData& face = data.faces[size_t(walk->face)];
    if (face.unresolved || face.sliver) return false;
    const double reach = distance(p, w) + 2 * nearEee();
    if (reach > gathered) {
      gathered = 2 * reach;
      near.clear();
      data.eeeSegments.forEachNear(p, gathered, [&](size_t index) {
        const SurfaceId id = data.eeeSurfaceIds[index];
        const EeeSurface* s = &eeeSurfaces_[size_t(id) - surfaces_.size()];
        if (std::find(near.begin(), near.end(), s) == near.end()) near.push_back(s);
        return true;
      });
      sides.clear();
      for (const EeeSurface* s : near) sides.push_back(sideOf(*s, p));
    }
    std::vector<std::optional<bool>> atW;
    for (size_t k = 0; k < near.size(); ++k) {
      atW.push_back(sideOf(*near[k], w));
      if (!atW[k] || (sides[k] && *sides[k] != *atW[k])) return false;
    }
    // Equal sides at p and w do not say that the segment between them stays on one side: where
    // an event ends near p (a polyline's end at a contact, where an occluder's edge meets the
    // receiver and every quadric through that edge passes), the segment can cross the event and
    // come back across the quadric's zero set beyond the event's end, into a face whose labels
    // are not p's (desk-475's last pose: 33 edge midpoints, with its triangulated copy, 28% off).
    // Past p's rounding, the segment crosses none of the quadrics. (A crossing within p's rounding
    // is p's side, which the test above compared exactly.)
    for (const EeeSurface* s : near)
      if (eeeQuadricCrossings(*s, *posed_, *adjacency_, p, w) != 0) return false;
    for (size_t k = 0; k < near.size(); ++k)
      if (!sides[k]) seen[near[k]] |= *atW[k] ? 2 : 1;
    if (std::find(faces.begin(), faces.end(), walk->face) == faces.end())
      faces.push_back(walk->face);
    return complete();
  };
  // Witnesses first across the edges near p of the faces reached from the located one across EEE
  // polylines passing near p (breadth first, by face index), just beyond the polylines'
  // tolerance; then, where p lies in a narrow corner between events (a polyline ending on a
  // straight event), on rings around p of growing radius.
  const double offset = 2 * nearEee();
  const auto onlyEee = [&](const std::vector<SurfaceId>& ids) {
    return !ids.empty() && std::all_of(ids.begin(), ids.end(), crossable);
  };
  std::vector<int> queue{located};
  for (size_t next = 0; next < queue.size(); ++next)
    for (const NearCrossing& c : data.mesh.crossingsNear(queue[next], p, nearEee())) {
      for (const double across : {-offset, offset})
        if (witnessed(c.nearest + c.intoOther * across)) return faces;
      const int other = c.crossing.other;
      if (onlyEee(c.crossing.surfaces) &&
          std::find(queue.begin(), queue.end(), other) == queue.end())
        queue.push_back(other);
    }
  // Witnesses stay this close to p: the farther, the likelier a quadric's zero set beyond its
  // event passes between them and makes its side a poor guide.
  const double farthest = 256 * offset;
  // Toward each of those faces' samples, at growing distances: into the opening of a narrow
  // corner that holds p.
  for (const int face : queue) {
    const Vec3& sample = data.mesh.faces()[size_t(face)].samplePoint;
    const double toSample = distance(p, sample);
    for (double radius = offset; radius < std::min(toSample, farthest); radius *= 2)
      if (witnessed(p + (sample - p) * (radius / toSample))) return faces;
  }
  const PlaneFrame& frame = data.mesh.frame();
  constexpr int kDirections = 32;
  for (double radius = offset; radius <= farthest; radius *= 2)
    for (int k = 0; k < kDirections; ++k) {
      const double angle = 2 * std::numbers::pi * k / kDirections;
      const Vec3 w =
          p + frame.u * (radius * std::cos(angle)) + frame.v * (radius * std::sin(angle));
      if (witnessed(w)) return faces;
    }
  // No witness: p lies in a corner narrower than the polylines' tolerance (a polyline ending on
  // a straight event). Its true face is one of those reached from the located one across the
  // polylines passing near p (the conic stands within their tolerance): the caller answers when
  // all their labels agree at p to 1e-11 (the value is then one of theirs). They often do:
  // across an EEE event irradiance and its gradient are continuous, and p is within the
  // polylines' tolerance of the conic.
  for (const int face : queue)
    if (data.faces[size_t(face)].unresolved || data.faces[size_t(face)].sliver) return {};
  return queue;
}

bool DiscontinuityMeshEngine::liesOnAnotherPolygon(const Vec3& p, PolygonId receiver) const {
  // The tolerance of the contact lines (contactSegments), so that a point on one is on the
  // polygon that made it.
  const double tolerance = 1e-9 * posed_->extent.diagonalLength();
  const Box3 around = Box3{p, p}.expanded(tolerance);
  for (PolygonId id : grid_->polygonsInBox(around)) {
    const WorldPolygon& q = posed_->polygons[id];
    if (id == receiver || !q.bounds.expanded(tolerance).contains(p)) continue;
    if (!(std::abs(q.plane.signedDistance(p)) <= tolerance)) continue;
    // Inside a polygon lying on the receiver (a box's bottom under it) the faces agree with the
    // point's value; only its outline is a contact line.
    const bool lyingOn =
        std::abs(dot(q.plane.normal, posed_->polygons[receiver].plane.normal)) >= 1 - 1e-12;
    const PlaneFrame frame = PlaneFrame::fromPlane(q.plane, q.vertices[0]);
    Polygon2 loop;
    loop.reserve(q.vertices.size());
    for (const Vec3& v : q.vertices) loop.push_back(frame.toLocal(v));
    const Vec2 x = frame.toLocal(p);
    if ((!lyingOn && containsPoint(loop, x)) || isNearBoundary(loop, x, tolerance)) return true;
  }
  return false;
}

bool DiscontinuityMeshEngine::isDegenerate(const Rgb& e) const {
  if (!e.isFinite()) return true;
  double brightest = 0;
  for (const PolygonId light : posed_->lights)
    brightest =
        std::max(brightest, posed_->materialOf(posed_->polygons[light]).emission.maxComponent());
  const double slack = std::max({1e-15, 1e-13 * brightest, 1e-12 * e.maxComponent()});
  return e.r < -slack || e.g < -slack || e.b < -slack;
}

Rgb DiscontinuityMeshEngine::withoutRoundingBelowZero(const Rgb& e) {
  return {std::max(e.r, 0.0), std::max(e.g, 0.0), std::max(e.b, 0.0)};
}

}  // namespace penumbra
