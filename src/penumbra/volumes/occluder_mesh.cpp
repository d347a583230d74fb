#include "penumbra/volumes/occluder_mesh.h"

#include <map>
#include <tuple>
#include <utility>

#include "penumbra/geometry/triangulation.h"

namespace penumbra {

OccluderMesh buildOccluderMesh(const std::vector<Polygon3>& objectPolygons) {
  OccluderMesh mesh;
  std::map<std::tuple<double, double, double>, int> weld;
  for (const Polygon3& polygon : objectPolygons) {
    std::vector<int> ring;
    for (const Vec3& p : polygon) {
      const auto [it, inserted] = weld.try_emplace({p.x, p.y, p.z}, int(mesh.vertices.size()));
      if (inserted) mesh.vertices.push_back(p);
      // Consecutive repeated vertices would give zero-length edges: drop them.
      if (ring.empty() || ring.back() != it->second) ring.push_back(it->second);
    }
    if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    std::vector<std::array<int, 3>> triangles;
    for (const auto& t : triangulate(polygon)) {
      // triangulate() indexes `polygon`; map its corners through the weld.
      triangles.push_back({weld.at({polygon[t[0]].x, polygon[t[0]].y, polygon[t[0]].z}),
                           weld.at({polygon[t[1]].x, polygon[t[1]].y, polygon[t[1]].z}),
                           weld.at({polygon[t[2]].x, polygon[t[2]].y, polygon[t[2]].z})});
    }
    mesh.polygons.push_back(std::move(ring));
    mesh.triangles.push_back(std::move(triangles));
  }

  // Directed edge -> (polygon, corner). An undirected edge is interior when used exactly twice,
  // once in each direction.
  std::map<std::pair<int, int>, std::vector<int>> uses;  // directed edge -> polygons
  std::map<std::pair<int, int>, int> undirectedCount;
  for (int p = 0; p < int(mesh.polygons.size()); ++p) {
    const auto& ring = mesh.polygons[p];
    for (size_t i = 0; i < ring.size(); ++i) {
      const int a = ring[i], b = ring[(i + 1) % ring.size()];
      uses[{a, b}].push_back(p);
      ++undirectedCount[{std::min(a, b), std::max(a, b)}];
    }
  }
  mesh.isClosed = !mesh.polygons.empty();
  mesh.neighbor.resize(mesh.polygons.size());
  for (int p = 0; p < int(mesh.polygons.size()); ++p) {
    const auto& ring = mesh.polygons[p];
    mesh.neighbor[p].assign(ring.size(), -1);
    for (size_t i = 0; i < ring.size(); ++i) {
      const int a = ring[i], b = ring[(i + 1) % ring.size()];
      const auto opposite = uses.find({b, a});
      if (undirectedCount[{std::min(a, b), std::max(a, b)}] == 2 && opposite != uses.end() &&
          opposite->second.size() == 1) {
        mesh.neighbor[p][i] = opposite->second.front();
      } else {
        mesh.isClosed = false;
      }
    }
  }
  return mesh;
}

}  // namespace penumbra
