#include "penumbra/dm/face_triangulation.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

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
                                                 const PlaneFrame& frame) {
  Cdt cdt;
  for (const auto& [a, b] : boundary) {
    const Vec2 p = frame.toLocal(a), q = frame.toLocal(b);
    if (p.x == q.x && p.y == q.y) continue;
    cdt.insert_constraint(Kernel::Point_2(p.x, p.y), Kernel::Point_2(q.x, q.y));
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
