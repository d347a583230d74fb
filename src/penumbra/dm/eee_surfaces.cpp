#include "penumbra/dm/eee_surfaces.h"

#include <gmpxx.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "penumbra/base/flat_set.h"
#include "penumbra/base/sort_unique.h"
#include "penumbra/dm/parameter_ranges.h"
#include "penumbra/geometry/predicates.h"
#include "penumbra/geometry/segment_distance.h"

namespace penumbra {

namespace {

struct Edge3 {
  Vec3 a, b;
};

// The line of the surface through light point L: it meets e1 at R = L + s (Q − L) and e2 at Q.
struct CriticalLine {
  Vec3 source;            // L on the light edge
  Vec3 direction;         // Q − L
  double farContact = 1;  // max(1, s): where the event begins along the line
};

// The line through e1(t) meeting the lines of e2 and e3 within both segments: it passes e1 at
// p (u = 0), e3 at p + direction (u = 1), e2 at u = atSecond.
struct ThreeEdgeLine {
  Vec3 p, direction;
  double atSecond = 0;
};

std::optional<ThreeEdgeLine> lineThroughThree(const Edge3& e1, const Edge3& e2, const Edge3& e3,
                                              double t) {
  const Vec3 p = e1.a + (e1.b - e1.a) * t;
  const Vec3 e = e2.b - e2.a;
  const Vec3 m = cross(e, p - e2.a);  // plane through p and e2
  const double denominator = dot(m, e3.b - e3.a);
  if (denominator == 0) return std::nullopt;
  const double w = dot(m, e2.a - e3.a) / denominator;
  if (w < 0 || w > 1) return std::nullopt;
  const Vec3 d = e3.a + (e3.b - e3.a) * w - p;
  const double cross2 = dot(m, cross(d, e));
  if (cross2 == 0) return std::nullopt;
  const double u = dot(m, cross(e2.a - p, e)) / cross2;
  const double r = dot(m, cross(e2.a - p, d)) / cross2;
  if (r < 0 || r > 1) return std::nullopt;
  return ThreeEdgeLine{p, d, u};
}

// The critical line through L(t) on the light edge, if it meets both occluder segments in front
// of the light.
std::optional<CriticalLine> criticalLine(const Edge3& light, const Edge3& e1, const Edge3& e2,
                                         double t) {
  const auto line = lineThroughThree(light, e1, e2, t);
  if (!line || line->atSecond <= 0) return std::nullopt;
  return CriticalLine{line->p, line->direction, std::max(1.0, line->atSecond)};
}

// Where the plane through v and edge `other` crosses segment `along`, strictly inside it: a line
// meeting `along` and `other` passes through v there.
std::optional<double> throughPoint(const Edge3& along, const Vec3& v, const Edge3& other) {
  const Vec3 m = cross(other.b - other.a, v - other.a);
  const double denominator = dot(m, along.b - along.a);
  if (denominator == 0) return std::nullopt;
  const double t = dot(m, other.a - along.a) / denominator;
  if (t > 0 && t < 1) return t;
  return std::nullopt;
}

// The t-ranges of the light edge where critical lines exist. Existence only changes where a line
// passes through an endpoint of e1 or e2 (the plane through that endpoint and the other edge
// crosses the light edge there), so it is decided at the middle of each range between them.
std::vector<std::array<double, 2>> validRanges(const Edge3& light, const Edge3& e1,
                                               const Edge3& e2) {
  std::vector<double> breaks{0, 1};
  for (const auto& [v, other] : {std::pair{e1.a, e2}, {e1.b, e2}, {e2.a, e1}, {e2.b, e1}})
    if (const auto t = throughPoint(light, v, other)) breaks.push_back(*t);
  return rangesBetween(std::move(breaks),
                       [&](double t) { return criticalLine(light, e1, e2, t).has_value(); });
}

// Where the line x(u) = source + u·direction crosses polygon q, if it does (u of the crossing).
// Called for every polygon of every cell along every traced line (the EEE tracing is a tenth of
// a full build): the even-odd test of containsPoint (geometry/polygon.h) runs on the vertices in
// place, with the same arithmetic in the same order, instead of on a projected copy allocated
// per call.
std::optional<double> crossing(const WorldPolygon& q, const Vec3& source, const Vec3& direction) {
  const double along = dot(q.plane.normal, direction);
  if (along == 0) return std::nullopt;
  const double u = -q.plane.signedDistance(source) / along;
  const Vec3 x = source + direction * u;
  // Containment in the projection that drops the normal's largest axis: (v[a], v[b]).
  const Vec3& n = q.plane.normal;
  const int drop = std::abs(n.x) > std::abs(n.y) ? (std::abs(n.x) > std::abs(n.z) ? 0 : 2)
                                                 : (std::abs(n.y) > std::abs(n.z) ? 1 : 2);
  const int a = drop == 0 ? 1 : drop == 1 ? 2 : 0, b = drop == 0 ? 2 : drop == 1 ? 0 : 1;
  const double px = x[a], py = x[b];
  // No edge spans py when it lies at or above every vertex or below every one: the even-odd
  // test below would count no crossing (its comparisons are exact), so the answer is the same.
  if (py >= q.bounds.max[b] || py < q.bounds.min[b]) return std::nullopt;
  bool inside = false;
  const Polygon3& loop = q.vertices;
  for (size_t i = 0, count = loop.size(), j = count - 1; i < count; j = i++) {
    const double ax = loop[i][a], ay = loop[i][b], bx = loop[j][a], by = loop[j][b];
    if ((ay > py) != (by > py) && px < (bx - ax) * (py - ay) / (by - ay) + ax) inside = !inside;
  }
  if (!inside) return std::nullopt;
  return u;
}

// The critical line of three occluder edges through e1(t), from the point where it leaves the
// light's interior (its front side) through the three contacts.
std::optional<CriticalLine> occluderCriticalLine(const WorldPolygon& light, const Edge3& e1,
                                                 const Edge3& e2, const Edge3& e3, double t) {
  const auto line = lineThroughThree(e1, e2, e3, t);
  if (!line) return std::nullopt;
  if (light.plane.signedDistance(line->p) <= 0) return std::nullopt;
  const auto k = crossing(light, line->p, line->direction);
  if (!k || *k == 0) return std::nullopt;
  // From the light point L = p + k·direction towards p: x = L + s (p − L), s = 1 − u / k, and
  // the contacts lie in front of the light where s > 0.
  const Vec3 source = line->p + line->direction * *k;
  const double atThird = 1 - 1 / *k, atSecond = 1 - line->atSecond / *k;
  if (atThird <= 0 || atSecond <= 0) return std::nullopt;
  return CriticalLine{source, line->p - source, std::max({1.0, atThird, atSecond})};
}

// Where f changes sign on [lo, hi]: sampled, then bisected (f is NaN where it is undefined). The
// ends are sampled just inside: lo and hi are breaks where the lines pass through an endpoint, and
// rounding may reject the line there.
template <class F>
void addSignChanges(double lo, double hi, F&& f, std::vector<double>& out) {
  constexpr int kSamples = 32;
  const double inset = 1e-9 * (hi - lo);
  const auto sampleAt = [&](int j) {
    return j == 0 ? lo + inset : j == kSamples ? hi - inset : lo + (hi - lo) * j / kSamples;
  };
  double previousT = sampleAt(0), previous = f(previousT);
  for (int j = 1; j <= kSamples; ++j) {
    const double tj = sampleAt(j), value = f(tj);
    if ((previous < 0 && value > 0) || (previous > 0 && value < 0)) {
      double a = previousT, b = tj;
      const bool aNegative = previous < 0;
      for (int step = 0; step < 60; ++step) {
        const double mid = 0.5 * (a + b), fm = f(mid);
        if (std::isnan(fm) || fm == 0) {
          a = b = mid;
          break;
        }
        ((fm < 0) == aNegative ? a : b) = mid;
      }
      out.push_back(0.5 * (a + b));
    }
    previousT = tj;
    previous = value;
  }
}

// The t-ranges of e1 where critical lines of three occluder edges exist and meet the light. The
// lines meet the three segments between the breaks where one passes through an endpoint. Within
// such a stretch the point where a line pierces the light's plane moves continuously but where the
// line turns parallel to that plane (it jumps from one far side to the other), and it enters or
// leaves the light where it crosses the line of a light edge: both found by sampled sign changes,
// bisected.
std::vector<std::array<double, 2>> occluderValidRanges(const WorldPolygon& light, const Edge3& e1,
                                                       const Edge3& e2, const Edge3& e3) {
  std::vector<double> breaks{0, 1};
  for (const auto& [v, other] : {std::pair{e2.a, e3}, {e2.b, e3}, {e3.a, e2}, {e3.b, e2}})
    if (const auto t = throughPoint(e1, v, other)) breaks.push_back(*t);
  std::sort(breaks.begin(), breaks.end());
  const Polygon3& lv = light.vertices;
  const Vec3& n = light.plane.normal;
  constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();
  const auto along = [&](double t) {  // n · direction: zero where the line is parallel
    const auto line = lineThroughThree(e1, e2, e3, t);
    return line ? dot(n, line->direction) : kUndefined;
  };
  std::vector<double> all = breaks;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double t0 = breaks[k], t1 = breaks[k + 1];
    if (t1 <= t0 || !lineThroughThree(e1, e2, e3, 0.5 * (t0 + t1))) continue;
    std::vector<double> pieces{t0, t1};
    addSignChanges(t0, t1, along, pieces);
    std::sort(pieces.begin(), pieces.end());
    all.insert(all.end(), pieces.begin(), pieces.end());
    for (size_t q = 0; q + 1 < pieces.size(); ++q)
      for (size_t i = 0; i < lv.size(); ++i) {
        const Vec3 &a = lv[i], &b = lv[(i + 1) % lv.size()];
        // Which side of the light edge's line the piercing point lies on.
        const auto side = [&](double t) {
          const auto line = lineThroughThree(e1, e2, e3, t);
          if (!line) return kUndefined;
          const double d = dot(n, line->direction);
          if (d == 0) return kUndefined;
          const Vec3 x = line->p - line->direction * (light.plane.signedDistance(line->p) / d);
          return dot(cross(b - a, x - a), n);
        };
        addSignChanges(pieces[q], pieces[q + 1], side, all);
      }
  }
  return rangesBetween(std::move(all), [&](double t) {
    return occluderCriticalLine(light, e1, e2, e3, t).has_value();
  });
}

// The critical lines of a surface by one parameter t in [0, 1]: along the light edge
// (kLightEdge) or along the first occluder edge (kOccluderEdges).
class LineFamily {
 public:
  LineFamily(const EeeSurface& surface, const PosedScene& scene, const EdgeAdjacency& adjacency)
      : kind_(surface.kind), light_(scene.polygons[surface.light]) {
    const auto edgeOf = [&](EdgeId id) {
      const SceneEdge& e = adjacency.edges()[id];
      return Edge3{adjacency.position(e.a), adjacency.position(e.b)};
    };
    e1_ = edgeOf(surface.first);
    e2_ = edgeOf(surface.second);
    if (kind_ == EeeKind::kOccluderEdges) {
      e3_ = edgeOf(surface.third);
    } else {
      const Polygon3& lv = light_.vertices;
      lightEdge_ = {lv[surface.lightEdge], lv[(surface.lightEdge + 1) % lv.size()]};
    }
  }

  std::optional<CriticalLine> at(double t) const {
    return kind_ == EeeKind::kLightEdge ? criticalLine(lightEdge_, e1_, e2_, t)
                                        : occluderCriticalLine(light_, e1_, e2_, e3_, t);
  }
  std::vector<std::array<double, 2>> ranges() const {
    return kind_ == EeeKind::kLightEdge ? validRanges(lightEdge_, e1_, e2_)
                                        : occluderValidRanges(light_, e1_, e2_, e3_);
  }

 private:
  EeeKind kind_;
  const WorldPolygon& light_;
  Edge3 lightEdge_, e1_, e2_, e3_;
};

struct LineHit {
  bool valid = false;    // the line meets the light and every occluder edge
  bool visible = false;  // nothing blocks it before its far contact, and it reaches a polygon
  PolygonId receiver = -1;
  PolygonId blocker = -1;  // invisible: the polygon found blocking it before its far contact
  Vec3 point;
};

// Per-line marks so that a polygon listed in several cells is tested once. Kept per thread across
// surfaces: a scene-sized array per traced surface would cost more than short surfaces' tracing.
struct PolygonMarks {
  std::vector<unsigned> tested;
  unsigned stamp = 0;

  unsigned nextLine() {
    if (++stamp == 0) {  // wrapped around: old marks could equal the new stamp
      std::fill(tested.begin(), tested.end(), 0u);
      stamp = 1;
    }
    return stamp;
  }
  static PolygonMarks& forScene(size_t polygons) {
    thread_local PolygonMarks marks;
    if (marks.tested.size() < polygons) marks.tested.resize(polygons, 0);
    return marks;
  }
};

class Tracer {
 public:
  Tracer(EeeSurface& surface, const PosedScene& scene, const EdgeAdjacency& adjacency,
         const UniformGrid& grid, double chordTolerance, std::vector<PolygonId>* crossed,
         std::vector<std::pair<Vec3, Vec3>>* lines)
      : followed_(lines),
        surface_(surface),
        scene_(scene),
        adjacency_(adjacency),
        grid_(grid),
        tolerance_(chordTolerance),
        family_(surface, scene, adjacency),
        edges_(surface.occluderEdges()),
        crossed_(surface.kind == EeeKind::kLightEdge ? crossed : nullptr) {
    for (EdgeId e : edges_)
      for (PolygonId p : adjacency.edges()[e].polygons) contactPolygons_.push_back(p);
  }

  std::vector<DiscontinuitySegment> trace() {
    constexpr int kSamples = 12;
    for (auto [ta, tb] : family_.ranges()) {
      // A three-occluder-edge range often ends where its lines leave the light, and the line
      // there grazes the light's boundary, which containment may reject: a visible stretch
      // ending at the light's edge would then be bracketed by two invisible samples and lost.
      // Its ends are sampled just inside.
      if (surface_.kind == EeeKind::kOccluderEdges) {
        const double inset = 1e-9 * (tb - ta);
        ta += inset;
        tb -= inset;
      }
      std::vector<LineHit> hits;
      std::vector<double> ts;
      for (int i = 0; i <= kSamples; ++i) {
        ts.push_back(ta + (tb - ta) * double(i) / kSamples);
        hits.push_back(hit(ts.back()));
      }
      for (int i = 0; i < kSamples; ++i) refine(ts[i], hits[i], ts[i + 1], hits[i + 1], 0);
    }
    std::sort(cells_.begin(), cells_.end());
    cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
    surface_.cells = cells_;
    if (crossed_) {
      std::sort(crossed_->begin(), crossed_->end());
      crossed_->erase(std::unique(crossed_->begin(), crossed_->end()), crossed_->end());
    }
    // A surface that ran out of lines is a degenerate conic whose visibility flickers by rounding:
    // its isolated pieces of rounding-noise length would put thousands of tiny edges at one point
    // (they made a 1k-polygon room's meshing take minutes).
    if (surface_.truncated)
      std::erase_if(segments_, [&](const DiscontinuitySegment& s) {
        return distance(s.p0, s.p1) < 1e-3 * tolerance_;
      });
    return segments_;
  }

 private:
  bool isContact(PolygonId id) const {
    return std::find(contactPolygons_.begin(), contactPolygons_.end(), id) !=
           contactPolygons_.end();
  }

  // Where the line enters a box (slab method), in units of its direction; -inf if it starts in it.
  static double entryParameter(const Box3& box, const CriticalLine& line) {
    double enter = -INFINITY;
    const double origin[3] = {line.source.x, line.source.y, line.source.z};
    const double direction[3] = {line.direction.x, line.direction.y, line.direction.z};
    const double lo[3] = {box.min.x, box.min.y, box.min.z},
                 hi[3] = {box.max.x, box.max.y, box.max.z};
    for (int k = 0; k < 3; ++k) {
      if (direction[k] == 0) continue;
      const double a = (lo[k] - origin[k]) / direction[k], b = (hi[k] - origin[k]) / direction[k];
      enter = std::max(enter, std::min(a, b));
    }
    return enter;
  }

  LineHit hit(double t) {
    LineHit result;
    const auto line = family_.at(t);
    if (!line) return result;
    result.valid = true;
    // Every occluder edge must be a silhouette seen along the line.
    for (EdgeId e : edges_)
      if (!adjacency_.isSilhouetteFrom(e, line->source)) return result;
    const double reach = 2 * scene_.extent.diagonalLength() / length(line->direction);
    const Vec3 end = line->source + line->direction * (line->farContact + reach);
    if (followed_) followed_->push_back({line->source, end});
    // Cells in order from the light: stop once the nearest receiver found lies before the next
    // cell's entry (nothing farther can be nearer, and every blocker lies before the contact).
    double nearest = INFINITY;
    const unsigned stamp = marks_.nextLine();
    for (int cell : grid_.cellsAlongSegment(line->source, end)) {
      cells_.push_back(cell);
      if (cells_.size() > cellsLimit_) {
        std::sort(cells_.begin(), cells_.end());
        cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
        cellsLimit_ = std::max<size_t>(4096, 2 * cells_.size());
      }
      if (nearest < INFINITY && entryParameter(grid_.cellBounds(cell), *line) > nearest) break;
      for (PolygonId id : grid_.polygonsInCell(cell)) {
        if (marks_.tested[id] == stamp) continue;
        marks_.tested[id] = stamp;
        if (id == surface_.light || isContact(id)) continue;
        const auto u = crossing(scene_.polygons[id], line->source, line->direction);
        if (!u || *u <= 0) continue;
        if (crossed_) crossed_->push_back(id);
        if (*u < line->farContact * (1 - 1e-9)) {  // blocked before the event
          result.blocker = id;
          return result;
        }
        if (*u > line->farContact * (1 + 1e-9) && *u < nearest) {
          nearest = *u;
          result.receiver = id;
        }
      }
    }
    if (result.receiver < 0) return result;
    result.visible = true;
    result.point = line->source + line->direction * nearest;
    return result;
  }

  // Are two invisible lines blocked by different polygons sharing no vertex (or one not blocked
  // at all: it misses the light or an edge, or an edge is no silhouette along it)?
  bool separateBlockers(const LineHit& a, const LineHit& b) const {
    if (a.blocker == b.blocker) return false;
    if (a.blocker < 0 || b.blocker < 0) return a.valid && b.valid;
    const std::vector<VertexId>& va = adjacency_.polygonVertices(a.blocker);
    const std::vector<VertexId>& vb = adjacency_.polygonVertices(b.blocker);
    return std::none_of(va.begin(), va.end(),
                        [&](VertexId v) { return std::find(vb.begin(), vb.end(), v) != vb.end(); });
  }

  // Pieces come in the order of t. One much shorter than the tolerance (where a change of
  // receiver or visibility is bracketed, or where the conic degenerates to a point and visibility
  // flickers by rounding) joins the previous piece when they meet: the polyline stays connected
  // and within its tolerance. Tiny pieces standing alone are kept (a visible stretch bracketed to
  // the last bit), except on a surface that ran out of lines (see trace()).
  void emit(const LineHit& h0, const LineHit& h1, double t0, double t1) {
    const double tiny = 1e-3 * tolerance_;
    if (!segments_.empty() && distance(h0.point, h1.point) < tiny) {
      DiscontinuitySegment& previous = segments_.back();
      if (previous.receiver == h0.receiver && previous.p1 == h0.point) {
        previous.p1 = h1.point;
        previous.u1 = t1;
        return;
      }
    }
    segments_.push_back({surface_.id, h0.receiver, h0.point, h1.point, t0, t1});
  }

  void refine(double t0, const LineHit& h0, double t1, const LineHit& h1, int depth) {
    const bool same = h0.visible && h1.visible && h0.receiver == h1.receiver;
    const bool bothInvisible = !h0.visible && !h1.visible;
    if (depth >= 36) return;  // bracketed to 2^-36 of a sample interval: end the piece here
    // Where the conic degenerates (every critical line through one receiver point, e.g. two
    // occluder edges whose lines meet on the floor) visibility flickers by rounding on every
    // interval and the bisection would branch at every level: end such a surface and count it.
    if (++lines_ > kMaxLines) {
      surface_.truncated = true;
      return;
    }
    const double tm = 0.5 * (t0 + t1);
    const LineHit hm = hit(tm);
    if (same && hm.visible && hm.receiver == h0.receiver &&
        distanceToSegment(hm.point, h0.point, h1.point) <= tolerance_) {
      emit(h0, h1, t0, t1);
      return;
    }
    // Invisible at both ends and in the middle, behind one blocker or behind polygons joined at
    // a vertex: nothing here. Behind two separate blockers the lines may pass between them: a
    // visible stretch narrower than half a sample interval (the first samples are 1/12 of the
    // valid range) is then bracketed too (a chair's back post and its seat, the floor seen
    // between them: missing there, the face beside it was answered 0.4% off).
    if (bothInvisible && !hm.visible && !separateBlockers(h0, hm) && !separateBlockers(hm, h1))
      return;
    refine(t0, h0, tm, hm, depth + 1);
    refine(tm, hm, t1, h1, depth + 1);
  }

  std::vector<std::pair<Vec3, Vec3>>* followed_;  // every line followed, when asked
  EeeSurface& surface_;
  const PosedScene& scene_;
  const EdgeAdjacency& adjacency_;
  const UniformGrid& grid_;
  double tolerance_;
  LineFamily family_;
  std::vector<EdgeId> edges_;
  std::vector<PolygonId>* crossed_;  // polygons the lines cross in front of the light
  std::vector<PolygonId> contactPolygons_;
  std::vector<DiscontinuitySegment> segments_;
  std::vector<int> cells_;  // every cell a traced line crossed (sorted at the end)
  size_t cellsLimit_ = 4096;
  static constexpr int kMaxLines = 1 << 14;
  int lines_ = 0;
  PolygonMarks& marks_ = PolygonMarks::forScene(scene_.polygons.size());
};

bool sharesVertex(const SceneEdge& a, const SceneEdge& b) {
  return a.a == b.a || a.a == b.b || a.b == b.a || a.b == b.b;
}

// Do two occluder edges lie in one plane, exactly or within `tolerance`: the second's ends within
// it of the plane through the first and the second's end farther from the first's line? Edges of
// a rotated object that are parallel in its model are so only within rounding once posed; their
// EEE quadric is then that plane within rounding, and its ranges of valid lines, a rounding wide,
// are found on some light edges and lost on others (desk-475's turned stool: the top's edge and
// a panel's above it, 1e-16 out of one plane). Within the tolerance (1e-10 of the scene's size,
// far below the EEE polylines' 1e-6) they are the coplanar pair's planar events instead.
bool inOnePlane(const Edge3& first, const Edge3& second, double tolerance) {
  if (orientation3d(first.a, first.b, second.a, second.b) == Sign::kZero) return true;
  const Vec3 along = first.b - first.a;
  const bool aFarther = squaredLength(cross(along, second.a - first.a)) >
                        squaredLength(cross(along, second.b - first.a));
  const Vec3 m = cross(along, (aFarther ? second.a : second.b) - first.a);
  const double norm = length(m);
  if (norm == 0) return true;
  const Vec3& other = aFarther ? second.b : second.a;
  return std::abs(dot(m, other - first.a)) <= tolerance * norm;
}

bool touchesLight(const std::vector<PolygonId>& polygons, PolygonId light) {
  return std::find(polygons.begin(), polygons.end(), light) != polygons.end();
}

// The surface a candidate names (a third edge makes it a three-occluder-edge surface).
EeeSurface surfaceOf(const EeeCandidate& c, PolygonId light, SurfaceId id) {
  EeeSurface surface;
  surface.id = id;
  surface.light = light;
  surface.kind = c.c >= 0 ? EeeKind::kOccluderEdges : EeeKind::kLightEdge;
  surface.lightEdge = c.lightEdge;
  surface.first = c.a;
  surface.second = c.b;
  surface.third = c.c;
  return surface;
}

// Are a surface's generator features (its occluder edge, vertex or second edge) what they were?
bool generatorsUnchanged(const DiscontinuitySurface& s, const SurfaceCandidates& before,
                         const UnchangedTopology& unchanged) {
  if (before.kind != s.kind || before.lightFeature != s.lightFeature ||
      before.occluderFeature != s.occluderFeature || before.secondFeature != s.secondFeature)
    return false;
  const bool byVertex = s.kind == SurfaceKind::kEmitterEdgeOccluderVertex ||
                        s.kind == SurfaceKind::kNonEmitterVertexEdge;
  if (byVertex ? !unchanged.vertices[size_t(s.occluderFeature)]
               : !unchanged.edges[size_t(s.occluderFeature)])
    return false;
  return s.secondFeature < 0 || unchanged.edges[size_t(s.secondFeature)];
}

// Calls visit(polygon) for each polygon `s` cuts, once each in ascending order (cuts are in polygon
// order; a polygon cut twice gives the same candidates twice), while visit returns true: whether
// every call did.
template <class Visit>
bool forEachCutPolygon(const DiscontinuitySurface& s, Visit&& visit) {
  for (size_t c = 0; c < s.intersections.size(); ++c) {
    const PolygonId polygon = s.intersections[c].polygon;
    if (c > 0 && s.intersections[c - 1].polygon == polygon) continue;
    if (!visit(polygon)) return false;
  }
  return true;
}

// The candidates of EV surface `index` (`s`), cut polygon by cut polygon in ascending order: taken
// from the frame before where the generators and the polygon are unchanged, else found by
// `find(polygon, found)`, and recorded in `memo`. Those found are handed to `add`, and so are
// those taken over where `addKept`; the frame before's candidates of its cuts not taken over, to
// `remove`. The frame before's entry, where read, is left empty.
template <class Find, class Add, class Remove>
void surfaceCandidates(const DiscontinuitySurface& s, size_t index, EeeCandidateMemo* memo,
                       const EeeCandidateReuse* reuse, Find&& find, Add&& add, bool addKept,
                       Remove&& remove) {
  SurfaceCandidates* before = nullptr;
  if (reuse && index < reuse->previousIndex.size() && reuse->previousIndex[index] >= 0 &&
      size_t(reuse->previousIndex[index]) < reuse->before.bySurface.size()) {
    SurfaceCandidates& then = reuse->before.bySurface[size_t(reuse->previousIndex[index])];
    if (generatorsUnchanged(s, then, reuse->unchanged)) before = &then;
  }
  const auto removeAll = [&](CutCandidates& cut) {
    for (const EeeCandidate& candidate : cut.found) remove(candidate);
    cut.found.clear();
  };
  SurfaceCandidates now{s.light, s.kind, s.lightFeature, s.occluderFeature, s.secondFeature, {}};
  // Every cut polygon the frame before's, in order, and unchanged (a kept cast, away from the
  // move: most surfaces of a large room): its cuts are taken over whole, without making each
  // cut's entry again (1,245,000 cuts in a 10,000-polygon room).
  if (before && memo) {
    size_t cuts = 0;
    const bool same = forEachCutPolygon(s, [&](PolygonId polygon) {
      return cuts < before->cuts.size() && before->cuts[cuts++].polygon == polygon &&
             reuse->unchanged.polygons[size_t(polygon)];
    });
    if (same && cuts == before->cuts.size()) {
      now.cuts = std::move(before->cuts);
      before->cuts.clear();
      memo->keptCuts += (long long)now.cuts.size();
      if (addKept)
        for (const CutCandidates& cut : now.cuts)
          for (const EeeCandidate& candidate : cut.found) add(candidate);
      if (memo->bySurface.size() <= index) memo->bySurface.resize(index + 1);
      memo->bySurface[index] = std::move(now);
      return;
    }
  }
  if (memo) now.cuts.reserve(s.intersections.size());
  size_t k = 0;
  forEachCutPolygon(s, [&](PolygonId polygon) {
    CutCandidates cut{polygon, {}};
    bool kept = false;
    if (before) {
      for (; k < before->cuts.size() && before->cuts[k].polygon < polygon; ++k)
        removeAll(before->cuts[k]);
      if (k < before->cuts.size() && before->cuts[k].polygon == polygon) {
        if (reuse->unchanged.polygons[size_t(polygon)]) {
          cut.found = std::move(before->cuts[k].found);
          kept = true;
        } else {
          removeAll(before->cuts[k]);
        }
        ++k;
      }
    }
    if (kept) {
      if (memo) ++memo->keptCuts;
      if (addKept)
        for (const EeeCandidate& candidate : cut.found) add(candidate);
    } else {
      find(polygon, cut.found);
      if (memo) ++memo->foundCuts;
      for (const EeeCandidate& candidate : cut.found) add(candidate);
    }
    if (memo) now.cuts.push_back(std::move(cut));
    return true;
  });
  if (before) {
    for (; k < before->cuts.size(); ++k) removeAll(before->cuts[k]);
    before->cuts.clear();
  }
  if (memo) {
    if (memo->bySurface.size() <= index) memo->bySurface.resize(index + 1);
    memo->bySurface[index] = std::move(now);
  }
}

}  // namespace

std::vector<EeeSurface> enumerateEeeSurfaces(const PosedScene& scene,
                                             const EdgeAdjacency& adjacency,
                                             const std::vector<DiscontinuitySurface>& evSurfaces,
                                             PolygonId light, SurfaceId firstId,
                                             std::vector<CoplanarEdgePair>* coplanar,
                                             EeeCandidateMemo* memo,
                                             const EeeCandidateReuse* reuse) {
  std::vector<EeeSurface> surfaces;
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Polygon3& lv = lightPolygon.vertices;
  const int lightEdges = int(lv.size());
  const double planeTolerance = kCoplanarEdgeTolerance * scene.extent.diagonalLength();
  const auto inFront = [&](const SceneEdge& e) {
    return lightPolygon.plane.signedDistance(adjacency.position(e.a)) > 0 ||
           lightPolygon.plane.signedDistance(adjacency.position(e.b)) > 0;
  };
  const auto usable = [&](EdgeId id) {
    const SceneEdge& e = adjacency.edges()[id];
    return e.canBeSilhouette && !touchesLight(e.polygons, light) && inFront(e);
  };
  const auto keyOf = [&](int l, EdgeId i, EdgeId j) {
    return (std::uint64_t(std::uint32_t(i)) * adjacency.edges().size() + std::uint32_t(j)) *
               std::uint64_t(lightEdges) +
           std::uint64_t(l);
  };
  // What a (light edge, edge, edge) triple is: a function of the three alone, decided once.
  std::unordered_map<std::uint64_t, std::optional<EeeCandidate>> decided;
  const auto decide = [&](int l, EdgeId i, EdgeId j) -> std::optional<EeeCandidate> {
    const SceneEdge& e1 = adjacency.edges()[i];
    const SceneEdge& e2 = adjacency.edges()[j];
    if (!usable(i) || !usable(j) || sharesVertex(e1, e2)) return std::nullopt;
    const Edge3 first{adjacency.position(e1.a), adjacency.position(e1.b)};
    const Edge3 second{adjacency.position(e2.a), adjacency.position(e2.b)};
    // Lines meeting two coplanar edges lie in their plane: that is the occluder-plane event of
    // a polygon holding both, or the coplanar-edge fan (or nothing), not a quadric.
    if (inOnePlane(first, second, planeTolerance)) {
      const bool samePolygon =
          std::any_of(e1.polygons.begin(), e1.polygons.end(), [&](PolygonId p) {
            return std::find(e2.polygons.begin(), e2.polygons.end(), p) != e2.polygons.end();
          });
      if (samePolygon) return std::nullopt;
      return EeeCandidate{l, i, j, -1, true};
    }
    const Edge3 lightEdge{lv[l], lv[(l + 1) % lv.size()]};
    // An occluder edge coplanar with the light edge (e.g. parallel to it) makes the lines one
    // plane: the EV fans of that plane and the fans through the obstacles crossing it
    // (parallelEdgeCrossingSurfaces) hold the event.
    if (orientation3d(lightEdge.a, lightEdge.b, first.a, first.b) == Sign::kZero ||
        orientation3d(lightEdge.a, lightEdge.b, second.a, second.b) == Sign::kZero)
      return std::nullopt;
    if (validRanges(lightEdge, first, second).empty()) return std::nullopt;
    return EeeCandidate{l, i, j, -1, false};
  };
  // Each candidate is counted by the cuts that list them, as a key ordered by (first edge,
  // second edge, light edge). An update takes the light's counts over from the frame before (with
  // them, what its memo read: else every cut is counted afresh) and counts the cuts that changed
  // up or down; the keys whose count rose from zero or fell to it are `changed`.
  if (adjacency.edges().size() >= (std::size_t(1) << 24) || lightEdges >= (1 << 15))
    throw std::length_error("EEE enumeration: more than 2^24 occluder edges or 2^15 light edges");
  const auto keyOfCandidate = [](const EeeCandidate& c) {
    return std::uint64_t(std::uint32_t(c.a)) << 40 | std::uint64_t(std::uint32_t(c.b)) << 16 |
           std::uint64_t(std::uint32_t(c.lightEdge)) << 1 | (c.coplanar ? 1u : 0u);
  };
  EeeCandidateMemo::Counted local;
  EeeCandidateMemo::Counted& counted = memo ? memo->byLight[light] : local;
  if (reuse) {
    const auto before = reuse->before.byLight.find(light);
    if (before != reuse->before.byLight.end())
      counted = std::move(before->second);
    else
      reuse = nullptr;
  }
  std::vector<std::uint64_t> changed;
  const auto add = [&](const EeeCandidate& c) {
    const std::uint64_t key = keyOfCandidate(c);
    if (counted.counts.add(key)) changed.push_back(key);
  };
  const auto remove = [&](const EeeCandidate& c) {
    const std::uint64_t key = keyOfCandidate(c);
    if (counted.counts.remove(key)) changed.push_back(key);
  };
  // Every range of critical lines ends on a line through a light vertex or an occluder edge's
  // endpoint (validRanges), and such a line lies in the emitter EV fan of that vertex, where the
  // other edge's polygon cuts the fan: the fans' stored intersections hold every pair.
  FlatSet<std::uint64_t, IdentityHash> here;  // the keys seen in one cut polygon
  for (size_t index = 0; index < evSurfaces.size(); ++index) {
    const DiscontinuitySurface& s = evSurfaces[index];
    if (s.light != light) continue;
    std::vector<std::pair<int, EdgeId>> generators;  // (light edge, occluder edge)
    if (s.kind == SurfaceKind::kEmitterVertexOccluderEdge) {
      generators.push_back({s.lightFeature, EdgeId(s.occluderFeature)});
      generators.push_back(
          {(s.lightFeature + lightEdges - 1) % lightEdges, EdgeId(s.occluderFeature)});
    } else if (s.kind == SurfaceKind::kEmitterEdgeOccluderVertex) {
      for (EdgeId e : adjacency.vertices()[s.occluderFeature].edges)
        generators.push_back({s.lightFeature, e});
    } else if (s.kind == SurfaceKind::kLightEdgeOccluderPlane) {
      // Where an occluder edge stops being a silhouette as the light point moves along a light
      // edge: the line lies in one of the edge's faces' planes, in this fan.
      generators.push_back({s.lightFeature, EdgeId(s.occluderFeature)});
    } else {
      continue;
    }
    const auto find = [&](PolygonId polygon, std::vector<EeeCandidate>& found) {
      here.clear();
      adjacency.forEachEdgeOf(polygon, [&](EdgeId j) {
        for (auto [l, i] : generators) {
          EdgeId a = i, b = j;
          if (a == b) continue;
          if (b < a) std::swap(a, b);
          const std::uint64_t key = keyOf(l, a, b);
          if (!here.insert(key)) continue;
          auto it = decided.find(key);
          if (it == decided.end()) it = decided.emplace(key, decide(l, a, b)).first;
          if (it->second) found.push_back(*it->second);
        }
      });
    };
    surfaceCandidates(s, index, memo, reuse, find, add, false, remove);
  }
  // The frame before's surfaces of this light that no surface read: their cuts' candidates are
  // gone.
  const auto counts = [](SurfaceKind kind) {
    return kind == SurfaceKind::kEmitterVertexOccluderEdge ||
           kind == SurfaceKind::kEmitterEdgeOccluderVertex ||
           kind == SurfaceKind::kLightEdgeOccluderPlane;
  };
  if (reuse)
    for (SurfaceCandidates& gone : reuse->before.bySurface)
      if (gone.light == light && counts(gone.kind)) {
        for (CutCandidates& cut : gone.cuts)
          for (const EeeCandidate& candidate : cut.found) remove(candidate);
        gone.cuts.clear();
      }
  // The keys counted: those of the frame before, with the changed ones in or out by their count.
  sortUnique(changed);
  std::vector<std::uint64_t> keys;
  keys.reserve(counted.keys.size() + changed.size());
  size_t i = 0;
  for (const std::uint64_t key : changed) {
    for (; i < counted.keys.size() && counted.keys[i] < key; ++i) keys.push_back(counted.keys[i]);
    if (i < counted.keys.size() && counted.keys[i] == key) ++i;
    if (counted.counts.count(key) > 0) keys.push_back(key);
  }
  keys.insert(keys.end(), counted.keys.begin() + std::ptrdiff_t(i), counted.keys.end());
  counted.keys = std::move(keys);
  for (const std::uint64_t key : counted.keys) {
    const EeeCandidate c{int((key >> 1) & 0x7fffu), EdgeId(key >> 40),
                         EdgeId((key >> 16) & 0xffffffu), -1, (key & 1u) != 0};
    if (c.coplanar) {
      if (coplanar) coplanar->push_back({c.lightEdge, c.a, c.b});
      continue;
    }
    surfaces.push_back(surfaceOf(c, light, firstId + SurfaceId(surfaces.size())));
  }
  return surfaces;
}

std::vector<EeeSurface> enumerateOccluderEeeSurfaces(
    const PosedScene& scene, const EdgeAdjacency& adjacency,
    const std::vector<DiscontinuitySurface>& evSurfaces, const std::vector<EeeCrossing>& crossings,
    PolygonId light, SurfaceId firstId, EeeCandidateMemo* memo, const EeeCandidateReuse* reuse) {
  std::vector<EeeSurface> surfaces;
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const auto& edges = adjacency.edges();
  const auto inFront = [&](const SceneEdge& e) {
    return lightPolygon.plane.signedDistance(adjacency.position(e.a)) > 0 ||
           lightPolygon.plane.signedDistance(adjacency.position(e.b)) > 0;
  };
  const auto usable = [&](EdgeId id) {
    const SceneEdge& e = edges[id];
    return e.canBeSilhouette && !touchesLight(e.polygons, light) && inFront(e);
  };
  const double planeTolerance = kCoplanarEdgeTolerance * scene.extent.diagonalLength();
  const auto coplanar = [&](const SceneEdge& a, const SceneEdge& b) {
    return inOnePlane({adjacency.position(a.a), adjacency.position(a.b)},
                      {adjacency.position(b.a), adjacency.position(b.b)}, planeTolerance);
  };
  struct TripleHash {
    std::uint64_t operator()(const std::array<EdgeId, 3>& e) const {
      std::uint64_t h = 0;
      for (EdgeId id : e) h = (h ^ std::uint64_t(std::uint32_t(id))) * 0x100000001b3ull;
      return h ^ (h >> 29);
    }
  };
  // What a triple of edges is: a function of the three alone, decided once.
  std::unordered_map<std::array<EdgeId, 3>, bool, TripleHash> decided;
  const auto decide = [&](const std::array<EdgeId, 3>& e) {
    for (EdgeId id : e)
      if (!usable(id)) return false;
    const SceneEdge &a = edges[e[0]], &b = edges[e[1]], &c = edges[e[2]];
    if (sharesVertex(a, b) || sharesVertex(b, c) || sharesVertex(a, c)) return false;
    // Two coplanar edges put every line meeting both in their plane (or through one point): the
    // occluder-plane events, not a quadric.
    if (coplanar(a, b) || coplanar(b, c) || coplanar(a, c)) return false;
    EeeSurface surface;
    surface.light = light;
    surface.kind = EeeKind::kOccluderEdges;
    surface.first = e[0];
    surface.second = e[1];
    surface.third = e[2];
    return !LineFamily(surface, scene, adjacency).ranges().empty();
  };
  // The candidates among (i, j, k) for each k, each triple once.
  FlatSet<std::array<EdgeId, 3>, TripleHash> here;  // the triples seen in one cut polygon
  const auto findAll = [&](std::vector<std::array<EdgeId, 2>> pairs, PolygonId polygon,
                           std::vector<EeeCandidate>& found) {
    here.clear();
    adjacency.forEachEdgeOf(polygon, [&](EdgeId k) {
      for (auto [i, j] : pairs) {
        if (i < 0 || j < 0 || i == j || j == k || i == k) continue;
        std::array<EdgeId, 3> e{i, j, k};
        std::sort(e.begin(), e.end());
        if (!here.insert(e)) continue;
        auto it = decided.find(e);
        if (it == decided.end()) it = decided.emplace(e, decide(e)).first;
        if (it->second) found.push_back({-1, e[0], e[1], e[2], false});
      }
    });
  };
  FlatSet<std::array<EdgeId, 3>, TripleHash> emitted;
  const auto emit = [&](const EeeCandidate& c) {
    if (!emitted.insert({c.a, c.b, c.c})) return;
    surfaces.push_back(surfaceOf(c, light, firstId + SurfaceId(surfaces.size())));
  };
  // Ranges ending on a line through an occluder vertex v: it lies in the non-emitter EV fan of v
  // and one of the other edges, where the third edge's polygon cuts the fan.
  for (size_t index = 0; index < evSurfaces.size(); ++index) {
    const DiscontinuitySurface& s = evSurfaces[index];
    if (s.light != light || s.kind != SurfaceKind::kNonEmitterVertexEdge) continue;
    std::vector<std::array<EdgeId, 2>> pairs;
    for (EdgeId i : adjacency.vertices()[s.occluderFeature].edges)
      pairs.push_back({i, EdgeId(s.secondFeature)});
    surfaceCandidates(
        s, index, memo, reuse,
        [&](PolygonId polygon, std::vector<EeeCandidate>& found) {
          findAll(pairs, polygon, found);
        },
        emit, true, [](const EeeCandidate&) {});
  }
  // Ranges ending on a line through a light edge: that line belongs to a light-edge surface,
  // whose lines on one side of it cross the third edge's polygon.
  std::vector<EeeCandidate> found;
  for (const EeeCrossing& c : crossings) {
    const std::array<int, 4> key{light, c.first, c.second, c.polygon};
    int before = -1;
    if (reuse && reuse->unchanged.edges[size_t(c.first)] &&
        reuse->unchanged.edges[size_t(c.second)] && reuse->unchanged.polygons[size_t(c.polygon)])
      before = reuse->before.crossingIds.find(key);
    found.clear();
    if (before >= 0) {
      const auto [begin, end] = reuse->before.crossingRanges[size_t(before)];
      found.assign(reuse->before.crossingCandidates.begin() + begin,
                   reuse->before.crossingCandidates.begin() + end);
    } else {
      findAll({{c.first, c.second}}, c.polygon, found);
    }
    if (memo) ++(before >= 0 ? memo->keptCuts : memo->foundCuts);
    for (const EeeCandidate& candidate : found) emit(candidate);
    // A crossing met again (the same edges crossing the same polygon for another light edge)
    // has the same candidates: recorded once.
    if (memo && memo->crossingIds.idOf(key, int(memo->crossingRanges.size())).second) {
      const auto begin = std::uint32_t(memo->crossingCandidates.size());
      memo->crossingCandidates.insert(memo->crossingCandidates.end(), found.begin(), found.end());
      memo->crossingRanges.push_back({begin, std::uint32_t(memo->crossingCandidates.size())});
    }
  }
  return surfaces;
}

namespace {

// The ends of the surface's three lines: the light edge's first (kLightEdge), then the occluder
// edges'.
std::array<Vec3, 6> lineEnds(const EeeSurface& surface, const PosedScene& scene,
                             const EdgeAdjacency& adjacency) {
  std::array<Vec3, 6> ends{};
  size_t count = 0;
  if (surface.kind == EeeKind::kLightEdge) {
    const std::vector<Vec3>& v = scene.polygons[surface.light].vertices;
    ends[count++] = v[surface.lightEdge];
    ends[count++] = v[(surface.lightEdge + 1) % v.size()];
  }
  for (EdgeId e : surface.occluderEdges()) {
    const SceneEdge& edge = adjacency.edges()[e];
    ends[count++] = adjacency.position(edge.a);
    ends[count++] = adjacency.position(edge.b);
  }
  return ends;
}

}  // namespace

double eeeSide(const EeeSurface& surface, const PosedScene& scene, const EdgeAdjacency& adjacency,
               const Vec3& p) {
  const std::array<Vec3, 6> ends = lineEnds(surface, scene, adjacency);
  std::array<std::pair<Vec3, Vec3>, 3> lines{};  // a point and a direction of each
  for (size_t k = 0; k < 3; ++k) lines[k] = {ends[2 * k], ends[2 * k + 1] - ends[2 * k]};
  const auto& [a1, d1] = lines[0];
  const auto& [a2, d2] = lines[1];
  const auto& [a3, d3] = lines[2];
  // T(p) lies in the plane through p and the first line; it meets the second line where that
  // line crosses the plane, and the first line where T crosses it within the plane.
  const Vec3 planeNormal = cross(d1, a1 - p);
  const double across = dot(planeNormal, d2);
  const double scale = length(planeNormal) * length(d2);
  if (!(std::abs(across) > 1e-12 * scale)) return std::nan("");
  const Vec3 q2 = a2 + d2 * (dot(planeNormal, p - a2) / across);
  const Vec3 toQ2 = q2 - p;
  // q1 = p + t (q2 − p) on the first line: (p − a1) + t toQ2 parallel to d1.
  const Vec3 c = cross(toQ2, d1);
  const double c2 = dot(c, c);
  if (!(c2 > 1e-24 * dot(toQ2, toQ2) * dot(d1, d1))) return std::nan("");
  const double t = -dot(cross(p - a1, d1), c) / c2;
  const Vec3 q1 = p + toQ2 * t;
  const Vec3 d = q2 - q1;  // T, from the first line to the second
  const Vec3 m = cross(q1, d), m3 = cross(a3, d3);
  const double side = dot(d, m3) + dot(d3, m);
  // Relative to the product of the lengths and the scene-sized moments, so 1e-12 is rounding.
  const double magnitude = length(d) * length(d3) * (length(q1) + length(a3) + length(q2 - a3));
  return magnitude > 0 ? side / magnitude : std::nan("");
}

namespace {

// The quadric of three lines as a polynomial of degree two in p, with a bound on its rounding. The
// transversal through p meeting the first two lines is where the planes through p and each of them
// meet: normals n_i = (a_i - p) x d_i and offsets c_i = n_i . a_i (both linear in p), direction
// n_1 x n_2 and moment c_2 n_1 - c_1 n_2 (quadratic); its Plücker side product with the third
// line vanishes exactly where it meets that line, so on the quadric (and nowhere else: a
// polynomial of degree two vanishing on a quadric is a multiple of its equation).
struct QuadricValue {
  double value = 0, rounding = 0;
};
QuadricValue quadricAt(const std::array<Vec3, 6>& ends, const Vec3& p) {
  const Vec3 a1 = ends[0], d1 = ends[1] - ends[0], a2 = ends[2], d2 = ends[3] - ends[2],
             a3 = ends[4], d3 = ends[5] - ends[4];
  const Vec3 n1 = cross(a1 - p, d1), n2 = cross(a2 - p, d2);
  const double c1 = dot(n1, a1), c2 = dot(n2, a2);
  const Vec3 m3 = cross(a3, d3);
  const double direction = dot(cross(n1, n2), m3);
  const double moment = c2 * dot(d3, n1) - c1 * dot(d3, n2);
  // Each term is a product of a few roundings of products of scene-sized numbers: 1e-12 of the
  // terms' sizes bounds them generously (a bound too large only makes a count uncertain).
  const double size = length(n1) * length(n2) * length(m3) +
                      (std::abs(c2) * length(n1) + std::abs(c1) * length(n2)) * length(d3);
  return {direction + moment, 1e-12 * size};
}

}  // namespace

std::optional<int> eeeQuadricCrossings(const EeeSurface& surface, const PosedScene& scene,
                                       const EdgeAdjacency& adjacency, const Vec3& a,
                                       const Vec3& b) {
  const std::array<Vec3, 6> ends = lineEnds(surface, scene, adjacency);
  const QuadricValue f0 = quadricAt(ends, a), fh = quadricAt(ends, (a + b) * 0.5),
                     f1 = quadricAt(ends, b);
  // q(s) = A s^2 + B s + C along the segment, from its values at 0, 1/2 and 1.
  const double A = 2 * f1.value - 4 * fh.value + 2 * f0.value;
  const double B = f1.value - f0.value - A;
  const double C = f0.value;
  const double errorA = 2 * f1.rounding + 4 * fh.rounding + 2 * f0.rounding;
  const double errorB = f1.rounding + f0.rounding + errorA;
  const double errorC = f0.rounding;
  const auto certainSign = [](double value, double error) -> std::optional<int> {
    if (!(std::abs(value) > error)) return std::nullopt;
    return value > 0 ? 1 : -1;
  };
  const std::optional<int> atEnd = certainSign(f1.value, f1.rounding);
  if (!atEnd) return std::nullopt;
  const std::optional<int> atStart = certainSign(C, errorC);
  if (!atStart) {
    // A root at a (within rounding); the other one at -B/A less it (the roots sum to -B/A), which
    // must lie certainly outside (0, 1] or inside it.
    if (!certainSign(B, errorB)) return std::nullopt;
    if (std::abs(A) <= errorA) {
      // Nearly linear: the other root lies beyond |B| / |A| >= |B| / errorA.
      return std::abs(B) > 2 * errorA ? std::optional(0) : std::nullopt;
    }
    const double other = -B / A + C / B;
    const double margin = 1e-6 + (errorA / std::abs(A) + errorB / std::abs(B)) * std::abs(B / A) +
                          errorC / std::abs(B);
    if (other < -margin || other > 1 + margin) return 0;
    if (other > margin && other < 1 - margin) return 1;
    return std::nullopt;
  }
  // A quadratic whose ends have opposite signs has one root between them.
  if (*atStart != *atEnd) return 1;
  // Ends of one sign: none, or two about the extremum, if it lies between and has the other sign.
  if (std::abs(A) <= errorA) {
    // Within rounding of a line: q stands within |A| / 4 of the chord between its ends.
    return std::abs(C) > errorA / 4 + errorC && std::abs(f1.value) > errorA / 4 + f1.rounding
               ? std::optional(0)
               : std::nullopt;
  }
  const double vertex = -B / (2 * A);
  if (vertex <= 0 || vertex >= 1) return 0;
  const double extremum = C - B * B / (4 * A);
  const double errorExtremum =
      4 * (errorC + std::abs(B) * errorB / (2 * std::abs(A)) + B * B * errorA / (4 * A * A));
  const std::optional<int> atVertex = certainSign(extremum, errorExtremum);
  if (!atVertex) return std::nullopt;
  return *atVertex != *atStart ? 2 : 0;
}

namespace {

// Integer vectors: the doubles of one evaluation scaled by one power of two (exact), so that the
// sign of a homogeneous polynomial in them is the sign for the doubles themselves.
struct IntegerVec3 {
  mpz_class x, y, z;
};
IntegerVec3 operator-(const IntegerVec3& a, const IntegerVec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
IntegerVec3 operator+(const IntegerVec3& a, const IntegerVec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
IntegerVec3 operator*(const IntegerVec3& a, const mpz_class& s) {
  return {a.x * s, a.y * s, a.z * s};
}
mpz_class dot(const IntegerVec3& a, const IntegerVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
IntegerVec3 cross(const IntegerVec3& a, const IntegerVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The doubles as integers times 2^shift with one shift for all (the least exponent among them).
std::vector<IntegerVec3> scaledToIntegers(const std::vector<Vec3>& points) {
  int least = std::numeric_limits<int>::max();
  const auto mantissa = [](double v, int& exponent) {
    // v = m 2^exponent with m an integer of at most 53 bits.
    const double fraction = std::frexp(v, &exponent);
    exponent -= 53;
    return std::ldexp(fraction, 53);
  };
  for (const Vec3& p : points)
    for (const double v : {p.x, p.y, p.z}) {
      if (v == 0) continue;
      int exponent = 0;
      mantissa(v, exponent);
      least = std::min(least, exponent);
    }
  const auto integer = [&](double v) {
    if (v == 0) return mpz_class(0);
    int exponent = 0;
    mpz_class z(mantissa(v, exponent));
    mpz_mul_2exp(z.get_mpz_t(), z.get_mpz_t(), mp_bitcnt_t(exponent - least));
    return z;
  };
  std::vector<IntegerVec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) out.push_back({integer(p.x), integer(p.y), integer(p.z)});
  return out;
}

}  // namespace

std::optional<int> exactEeeSideSign(const EeeSurface& surface, const PosedScene& scene,
                                    const EdgeAdjacency& adjacency, const Vec3& p) {
  // The three lines' ends, and p.
  const std::array<Vec3, 6> ends = lineEnds(surface, scene, adjacency);
  std::vector<Vec3> points(ends.begin(), ends.end());
  points.push_back(p);
  const std::vector<IntegerVec3> z = scaledToIntegers(points);
  const IntegerVec3 &a1 = z[0], &a2 = z[2], &a3 = z[4], &x = z[6];
  const IntegerVec3 d1 = z[1] - z[0], d2 = z[3] - z[2], d3 = z[5] - z[4];
  // eeeSide's construction without its divisions (each quantity times a known factor):
  // A = N . d2 with N = d1 x (a1 - x); A q2 = Q2; q2 - x = T / A; c = C / A; A² c2 = W = |C|²;
  // W q1 = Q1; A W (q2 - q1) = D; and A W² side = W (D . m3) + d3 . (Q1 x D), every term of
  // degree 26 in the coordinates (so one power-of-two scale of them all keeps the sign).
  const IntegerVec3 normal = cross(d1, a1 - x);
  const mpz_class across = dot(normal, d2);
  if (sgn(across) == 0) return std::nullopt;
  const IntegerVec3 q2 = a2 * across + d2 * dot(normal, x - a2);
  const IntegerVec3 toQ2 = q2 - x * across;
  const IntegerVec3 c = cross(toQ2, d1);
  const mpz_class w = dot(c, c);
  if (sgn(w) == 0) return std::nullopt;
  const IntegerVec3 q1 = x * w - toQ2 * dot(cross(x - a1, d1), c);
  const IntegerVec3 d = q2 * w - q1 * across;
  const mpz_class side = w * dot(d, cross(a3, d3)) + dot(d3, cross(q1, d));
  return sgn(across) * sgn(side);
}

std::vector<EdgeId> EeeSurface::occluderEdges() const {
  if (kind == EeeKind::kOccluderEdges) return {first, second, third};
  return {first, second};
}

std::vector<DiscontinuitySegment> traceEeeSurface(EeeSurface& surface, const PosedScene& scene,
                                                  const EdgeAdjacency& adjacency,
                                                  const UniformGrid& grid, double chordTolerance,
                                                  std::vector<PolygonId>* crossed,
                                                  std::vector<std::pair<Vec3, Vec3>>* lines) {
  surface.cells.clear();
  if (crossed) crossed->clear();
  if (lines) lines->clear();
  return Tracer(surface, scene, adjacency, grid, chordTolerance, crossed, lines).trace();
}

}  // namespace penumbra
