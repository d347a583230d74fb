// Ear clipping of simple polygons.
// References:
//  - G. H. Meisters, "Polygons have ears", Amer. Math. Monthly 82(6), 1975 (every simple polygon
//    with more than 3 vertices has two non-overlapping ears, so clipping ears always terminates).
//  - D. Eberly, "Triangulation by Ear Clipping", Geometric Tools, 2002-2015 (only reflex vertices
//    can lie inside a candidate ear; keep the convexity of the remaining vertices up to date).
//  - J. O'Rourke, "Computational Geometry in C", 2nd ed., 1998, §1.6.
// Every decision (convexity, containment) is a sign from the exact orientation2d predicate, so
// collinear vertices and vertices on a candidate diagonal are classified correctly.

#include "penumbra/geometry/triangulation.h"

#include "penumbra/geometry/predicates.h"

namespace penumbra {

namespace {

// Projection onto the coordinate plane most parallel to the polygon: dropping a coordinate is an
// exact operation, so points collinear in 3D (in doubles) stay exactly collinear and the exact
// predicate sees the input itself rather than rounded PlaneFrame coordinates. A parallel projection
// onto a plane not perpendicular to the polygon preserves orientation up to a global sign, which we
// fix by the order of the two kept axes.
std::vector<Vec2> projectToDominantPlane(const Polygon3& polygon, const Vec3& normal) {
  const int drop = dominantAxis(normal);
  int first = (drop + 1) % 3, second = (drop + 2) % 3;  // (first, second, drop) right-handed
  if (normal[drop] < 0) std::swap(first, second);
  std::vector<Vec2> flat;
  flat.reserve(polygon.size());
  for (const Vec3& p : polygon) flat.push_back({p[first], p[second]});
  return flat;
}

class EarClipper {
 public:
  explicit EarClipper(std::vector<Vec2> points) : points_(std::move(points)) {
    const int n = int(points_.size());
    next_.resize(n);
    prev_.resize(n);
    // Link the vertices, skipping exact repeats (they would make zero-length edges).
    std::vector<int> kept;
    for (int i = 0; i < n; ++i)
      if (kept.empty() || !(points_[kept.back()] == points_[i])) kept.push_back(i);
    while (kept.size() > 1 && points_[kept.front()] == points_[kept.back()]) kept.pop_back();
    remaining_ = int(kept.size());
    for (int k = 0; k < remaining_; ++k) {
      next_[kept[k]] = kept[(k + 1) % remaining_];
      prev_[kept[k]] = kept[(k + remaining_ - 1) % remaining_];
    }
    start_ = kept.empty() ? -1 : kept.front();
    corner_.assign(n, Sign::kZero);
    for (int i : kept) updateCorner(i);
  }

  std::vector<std::array<int, 3>> run() {
    std::vector<std::array<int, 3>> triangles;
    if (remaining_ < 3) return triangles;
    triangles.reserve(remaining_ - 2);
    int cursor = start_;
    while (remaining_ > 3) {
      const int ear = findEar(cursor);
      if (ear >= 0) {
        triangles.push_back({prev_[ear], ear, next_[ear]});
        cursor = prev_[ear];
        remove(ear);
        continue;
      }
      // No strict ear: impossible for a simple polygon (Meisters). Degrade gracefully on bad input:
      // first drop a vertex with a straight or folded-back angle (it encloses no area), else clip
      // any convex corner, else give up on what remains (it has no positive-area corner at all).
      const int fallback = findFallback(cursor);
      if (fallback < 0) return triangles;
      if (corner_[fallback] == Sign::kPositive)
        triangles.push_back({prev_[fallback], fallback, next_[fallback]});
      cursor = prev_[fallback];
      remove(fallback);
    }
    if (corner_[cursor] == Sign::kPositive)
      triangles.push_back({prev_[cursor], cursor, next_[cursor]});
    return triangles;
  }

 private:
  void updateCorner(int i) {
    corner_[i] = orientation2d(points_[prev_[i]], points_[i], points_[next_[i]]);
  }

  void remove(int i) {
    const int a = prev_[i], c = next_[i];
    next_[a] = c;
    prev_[c] = a;
    --remaining_;
    updateCorner(a);
    updateCorner(c);
  }

  // Is (prev, i, next) an ear: a strictly convex corner whose closed triangle holds no other
  // remaining vertex? Only vertices that are not strictly convex can be inside (the one farthest
  // from the diagonal would have to be reflex or straight), so those are the only ones tested.
  bool isEar(int i) const {
    if (corner_[i] != Sign::kPositive) return false;
    const int ia = prev_[i], ic = next_[i];
    const Vec2 &a = points_[ia], &b = points_[i], &c = points_[ic];
    for (int j = next_[ic]; j != ia; j = next_[j]) {
      if (corner_[j] == Sign::kPositive) continue;
      const Vec2& p = points_[j];
      // A vertex touching a corner of the triangle (only in non-simple input) does not block it.
      if (p == a || p == b || p == c) continue;
      if (orientation2d(a, b, p) != Sign::kNegative && orientation2d(b, c, p) != Sign::kNegative &&
          orientation2d(c, a, p) != Sign::kNegative)
        return false;
    }
    return true;
  }

  int findEar(int from) const {
    int i = from;
    do {
      if (isEar(i)) return i;
      i = next_[i];
    } while (i != from);
    return -1;
  }

  int findFallback(int from) const {
    int i = from;
    do {
      if (corner_[i] == Sign::kZero) return i;
      i = next_[i];
    } while (i != from);
    do {
      if (corner_[i] == Sign::kPositive) return i;
      i = next_[i];
    } while (i != from);
    return -1;
  }

  std::vector<Vec2> points_;
  std::vector<int> next_, prev_;
  std::vector<Sign> corner_;  // orientation of (prev, i, next) for the remaining vertices
  int remaining_ = 0;
  int start_ = -1;
};

}  // namespace

std::vector<std::array<int, 3>> triangulate(const Polygon3& polygon) {
  if (polygon.size() < 3) return {};
  const Vec3 normal = newellNormal(polygon);
  if (!(squaredLength(normal) > 0)) return {};
  return EarClipper(projectToDominantPlane(polygon, normal)).run();
}

}  // namespace penumbra
