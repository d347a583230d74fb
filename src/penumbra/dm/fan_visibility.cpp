#include "penumbra/dm/fan_visibility.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace penumbra {

namespace {

struct Hit {
  Vec3 point;
  double s;
};

// Where the critical line L(u) meets segment [p0, p1] (both in the fan plane), if it does.
std::optional<Hit> lineHit(const CriticalFan& fan, const Vec3& n, double u, const Vec3& p0,
                           const Vec3& p1) {
  const Vec3 s = fan.source(u);
  const Vec3 d = fan.hinge(u) - s;
  const Vec3 e = p1 - p0;
  const double denominator = dot(n, cross(e, d));
  if (denominator == 0) return std::nullopt;
  const double lambda = dot(n, cross(s - p0, d)) / denominator;
  if (lambda < 0 || lambda > 1) return std::nullopt;
  const Vec3 x = p0 + e * lambda;
  return Hit{x, fan.depthParameter(x, u)};
}

// Where L(u) meets the line of segment [p0, p1] (both in the fan plane), clamped to the segment;
// p0 when they are parallel.
Vec3 landing(const CriticalFan& fan, const Vec3& n, double u, const Vec3& p0, const Vec3& p1) {
  const Vec3 s = fan.source(u);
  const Vec3 d = fan.hinge(u) - s;
  const Vec3 e = p1 - p0;
  const double denominator = dot(n, cross(e, d));
  if (denominator == 0) return p0;
  const double lambda = std::clamp(dot(n, cross(s - p0, d)) / denominator, 0.0, 1.0);
  return p0 + e * lambda;
}

bool isHinge(const DiscontinuitySurface& surface, PolygonId polygon) {
  return std::find(surface.hingePolygons.begin(), surface.hingePolygons.end(), polygon) !=
         surface.hingePolygons.end();
}

}  // namespace

std::vector<DiscontinuitySegment> visibleSegments(const DiscontinuitySurface& surface,
                                                  const std::vector<WorldPolygon>& polygons) {
  const CriticalFan& fan = surface.fan;
  const Vec3 n = fan.normal();
  std::vector<const SurfaceIntersection*> records;
  for (const SurfaceIntersection& r : surface.intersections)
    if (!isHinge(surface, r.polygon)) records.push_back(&r);

  std::vector<double> breaks{0, 1};
  for (const SurfaceIntersection* r : records) {
    for (const Vec3& x : {r->p0, r->p1}) {
      const double u = fan.criticalParameter(x);
      if (u > 0 && u < 1) breaks.push_back(u);
    }
  }
  // The critical line through the crossing of segments ab and cd (in the fan plane), if they
  // cross strictly inside both.
  const auto breakAtCrossing = [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double den = dot(n, cross(b - a, d - c));
    if (den == 0) return;
    const double t = dot(n, cross(c - a, d - c)) / den;
    const double w = dot(n, cross(c - a, b - a)) / den;
    if (t <= 0 || t >= 1 || w <= 0 || w >= 1) return;
    const double u = fan.criticalParameter(a + (b - a) * t);
    if (u > 0 && u < 1) breaks.push_back(u);
  };
  // Crossings of two stored segments change the depth order.
  for (size_t i = 0; i < records.size(); ++i)
    for (size_t j = i + 1; j < records.size(); ++j)
      breakAtCrossing(records[i]->p0, records[i]->p1, records[j]->p0, records[j]->p1);
  // So do crossings of a stored segment with the hinge (a polygon the hinge edge passes through:
  // on one side the lines meet it beyond the hinge, on the other before it, where it hides the
  // event) and with the contacts where the event begins (a fan's lines meet it before the farthest
  // contact on one side, after it on the other). Without them an occluder's edge crossing the
  // floor lost its whole event there: the interval from the edge's upper end to the stored
  // segment's far end was judged by its middle, below the floor.
  std::vector<std::pair<Vec3, Vec3>> starts = fan.contacts;
  if (!(fan.hinge0 == fan.hinge1)) starts.push_back({fan.hinge0, fan.hinge1});
  for (const SurfaceIntersection* r : records)
    for (const auto& [c, d] : starts) breakAtCrossing(r->p0, r->p1, c, d);
  std::sort(breaks.begin(), breaks.end());
  // Breakpoints closer than rounding are one breakpoint (they bound no critical line of their own).
  breaks.erase(
      std::unique(breaks.begin(), breaks.end(), [](double a, double b) { return b - a <= 1e-14; }),
      breaks.end());

  std::vector<DiscontinuitySegment> out;
  std::vector<size_t> previous, current;  // the pieces made or extended by the last interval
  std::vector<std::optional<Hit>> hits(records.size());  // the middle line's, per record
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double u0 = breaks[k], u1 = breaks[k + 1];
    const double mid = 0.5 * (u0 + u1);
    const double hinge = fan.hingeDepth(mid);
    const SurfaceIntersection* nearest = nullptr;
    double nearestDepth = 0;
    bool blocked = false;
    for (size_t i = 0; i < records.size(); ++i) {
      const SurfaceIntersection* r = records[i];
      const auto& hit = hits[i] = lineHit(fan, n, mid, r->p0, r->p1);
      if (!hit) continue;
      if (hit->s > 0 && hit->s < hinge * (1 - kHingeDepthTolerance)) {
        blocked = true;
        break;
      }
      if (hit->s >= hinge * (1 - kHingeDepthTolerance) && (!nearest || hit->s < nearestDepth)) {
        nearest = r;
        nearestDepth = hit->s;
      }
    }
    previous.swap(current);
    current.clear();
    if (blocked || !nearest || nearestDepth <= hinge * (1 + kHingeDepthTolerance)) continue;
    // The event lands on the nearest polygon, and on every other the line meets there within
    // the same tolerance, from its front side: coincident polygons (a panel lying flat on the
    // floor), so that the floor under the panel has the event too (its faces there answer for
    // the floor's points, which the panel, through them, does not hide). A polygon met from
    // behind cannot see that light along the line: the event means nothing to its faces.
    const double landingDepth = nearestDepth * (1 + kHingeDepthTolerance);
    for (size_t i = 0; i < records.size(); ++i) {
      const SurfaceIntersection* r = records[i];
      if (r != nearest) {
        const std::optional<Hit>& hit = hits[i];
        if (!hit || hit->s > landingDepth ||
            !(dot(polygons[size_t(r->polygon)].plane.normal, fan.source(mid) - hit->point) > 0))
          continue;
      }
      // One piece per polygon and interval (a polygon may hold two cuts through one point).
      if (std::any_of(current.begin(), current.end(),
                      [&](size_t piece) { return out[piece].receiver == r->polygon; }))
        continue;
      // The interval's ends lie on the receiver's segment up to rounding: where the line there
      // misses it by a rounding, its nearest end is meant (choosing an end by comparing critical
      // parameters picked the far one for an interval 1e-14 wide, and the event on a desk under
      // a lamp's base shrank to a point).
      const Vec3 x0 = landing(fan, n, u0, r->p0, r->p1);
      const Vec3 x1 = landing(fan, n, u1, r->p0, r->p1);
      if (distance(x0, x1) == 0) continue;
      const auto continued = std::find_if(previous.begin(), previous.end(), [&](size_t piece) {
        return out[piece].receiver == r->polygon && out[piece].u1 == u0 && out[piece].p1 == x0;
      });
      if (continued != previous.end()) {
        out[*continued].p1 = x1;  // the same receiver continues: extend the piece
        out[*continued].u1 = u1;
        current.push_back(*continued);
        continue;
      }
      current.push_back(out.size());
      out.push_back({surface.id, r->polygon, x0, x1, u0, u1});
    }
  }
  return out;
}

}  // namespace penumbra
