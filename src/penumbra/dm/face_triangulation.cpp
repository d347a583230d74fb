#include "penumbra/dm/face_triangulation.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <list>

namespace penumbra {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int depth = -1;  // boundary crossings from the outside; odd inside the face
};
using VertexBase = CGAL::Triangulation_vertex_base_2<Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// The boundary comes rounded from exact coordinates, so two of its edges may cross by an ulp:
// Exact_predicates_tag lets the triangulation split them instead of failing.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

// Flood fill from the outside: crossing a constrained edge adds one to the depth.
void markDepths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().depth = -1;
  std::list<Cdt::Face_handle> frontier{cdt.infinite_face()};
  cdt.infinite_face()->info().depth = 0;
  std::list<std::pair<Cdt::Face_handle, int>> next;
  int depth = 0;
  while (!frontier.empty()) {
    while (!frontier.empty()) {
      const Cdt::Face_handle f = frontier.front();
      frontier.pop_front();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle g = f->neighbor(i);
        if (g->info().depth != -1) continue;
        if (cdt.is_constrained({f, i})) {
          next.push_back({g, depth + 1});
        } else {
          g->info().depth = depth;
          frontier.push_back(g);
        }
      }
    }
    ++depth;
    for (const auto& [g, d] : next)
      if (g->info().depth == -1) {
        g->info().depth = d;
        frontier.push_back(g);
      }
    next.clear();
  }
}

}  // namespace

std::vector<std::array<Vec3, 3>> triangulateFace(const std::vector<std::pair<Vec3, Vec3>>& boundary,
                                                 const PlaneFrame& frame, double spacing) {
  Cdt cdt;
  std::vector<std::pair<Vec2, Vec2>> segments;
  for (const auto& [a, b] : boundary) {
    Vec2 p = frame.toLocal(a), q = frame.toLocal(b);
    if (p.x == q.x && p.y == q.y) continue;
    // The same points whichever face asks: the ends in a fixed order.
    if (q.x < p.x || (q.x == p.x && q.y < p.y)) std::swap(p, q);
    const double len = std::hypot(q.x - p.x, q.y - p.y);
    const int parts = spacing > 0 ? std::clamp(int(std::ceil(len / spacing)), 1, 4096) : 1;
    Vec2 from = p;
    for (int i = 1; i <= parts; ++i) {
      const Vec2 to = i == parts ? q : p + (q - p) * (double(i) / parts);
      cdt.insert_constraint(Kernel::Point_2(from.x, from.y), Kernel::Point_2(to.x, to.y));
      from = to;
    }
    segments.push_back({p, q});
  }
  if (spacing > 0 && !segments.empty()) {
    // Interior points on the receiver's lattice (half a step off its origin), not nearer than a
    // quarter step to the boundary: they subdivide large faces without touching an edge another
    // face shares.
    Vec2 lo = segments[0].first, hi = lo;
    for (const auto& [p, q] : segments)
      for (const Vec2& r : {p, q}) {
        lo = {std::min(lo.x, r.x), std::min(lo.y, r.y)};
        hi = {std::max(hi.x, r.x), std::max(hi.y, r.y)};
      }
    const auto nearBoundary = [&](const Vec2& x) {
      for (const auto& [p, q] : segments) {
        const Vec2 d = q - p;
        const double t = std::clamp(
            ((x.x - p.x) * d.x + (x.y - p.y) * d.y) / std::max(d.x * d.x + d.y * d.y, 1e-300), 0.0,
            1.0);
        if (std::hypot(x.x - p.x - d.x * t, x.y - p.y - d.y * t) < 0.25 * spacing) return true;
      }
      return false;
    };
    const long long i0 = (long long)std::floor(lo.x / spacing - 0.5);
    const long long i1 = (long long)std::ceil(hi.x / spacing - 0.5);
    const long long j0 = (long long)std::floor(lo.y / spacing - 0.5);
    const long long j1 = (long long)std::ceil(hi.y / spacing - 0.5);
    if ((i1 - i0 + 1) * (j1 - j0 + 1) <= 1'000'000)
      for (long long i = i0; i <= i1; ++i)
        for (long long j = j0; j <= j1; ++j) {
          const Vec2 x{(double(i) + 0.5) * spacing, (double(j) + 0.5) * spacing};
          if (x.x > lo.x && x.x < hi.x && x.y > lo.y && x.y < hi.y && !nearBoundary(x))
            cdt.insert(Kernel::Point_2(x.x, x.y));
        }
  }
  if (cdt.dimension() < 2) return {};  // a degenerate face (all its edges collinear) has no area
  markDepths(cdt);
  std::vector<std::array<Vec3, 3>> triangles;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info().depth % 2 == 0) continue;
    std::array<Vec3, 3> t;
    for (int i = 0; i < 3; ++i) {
      const Kernel::Point_2& p = f->vertex(i)->point();
      t[i] = frame.toWorld({p.x(), p.y()});
    }
    triangles.push_back(t);
  }
  return triangles;
}

}  // namespace penumbra
