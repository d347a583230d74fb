// The per-vertex output mesh over the leaf elements and point queries on it.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <unordered_map>

#include "penumbra/radiosity/face_contacts.h"
#include "penumbra/spatial/receiver_locator.h"

namespace penumbra {

void RadiositySolver::buildMesh() {
  mesh_ = {};
  leafVertices_.assign(elements_.size(), {0, 0, 0, 0});
  std::vector<double> weights;
  for (size_t p = 0; p < polygonRoots_.size(); ++p) {
    // Leaves sharing a vertex inside one polygon computed it from the same parents' vertices in
    // the same way, so equal coordinates identify shared vertices exactly.
    std::unordered_map<std::string, std::uint32_t> index;
    std::vector<int> stack(polygonRoots_[p].begin(), polygonRoots_[p].end());
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      const Element& e = elements_[id];
      if (!e.isLeaf()) {
        for (int k = 0; k < 4; ++k) stack.push_back(e.firstChild + k);
        continue;
      }
      for (int i = 0; i < e.vertexCount; ++i) {
        std::string key(sizeof(Vec3), '\0');
        std::memcpy(key.data(), &e.vertices[i], sizeof(Vec3));
        auto [it, inserted] = index.try_emplace(key, std::uint32_t(mesh_.positions.size()));
        if (inserted) {
          mesh_.positions.push_back(e.vertices[i]);
          mesh_.normals.push_back(e.normal);
          mesh_.polygons.push_back(PolygonId(p));
          mesh_.radiosity.push_back({});
          mesh_.directIrradiance.push_back({});
          mesh_.indirectIrradiance.push_back({});
          weights.push_back(0);
        }
        const std::uint32_t v = it->second;
        leafVertices_[id][i] = v;
        // What is shown: the final gather's irradiance, and the radiosity it gives.
        const NodeRadiometry& m = e.radiometry;
        mesh_.radiosity[v] +=
            (m.emission + e.reflectance * (m.finalDirect + m.finalIndirect)) * e.area;
        mesh_.directIrradiance[v] += m.finalDirect * e.area;
        mesh_.indirectIrradiance[v] += m.finalIndirect * e.area;
        weights[v] += e.area;
      }
      const auto& lv = leafVertices_[id];
      mesh_.indices.insert(mesh_.indices.end(), {lv[0], lv[1], lv[2]});
      if (e.vertexCount == 4) mesh_.indices.insert(mesh_.indices.end(), {lv[0], lv[2], lv[3]});
    }
  }
  for (size_t v = 0; v < weights.size(); ++v) {
    mesh_.radiosity[v] = mesh_.radiosity[v] / weights[v];
    mesh_.directIrradiance[v] = mesh_.directIrradiance[v] / weights[v];
    mesh_.indirectIrradiance[v] = mesh_.indirectIrradiance[v] / weights[v];
  }
}

std::optional<int> RadiositySolver::leafContaining(const Vec3& point, const Vec3& normal) const {
  if (elements_.empty()) return std::nullopt;
  const auto receiver = locateReceiver(scene_, *grid_, point, normal);
  if (!receiver) return std::nullopt;
  // The locator may have found a polygon under another lying on it facing the same way.
  const PolygonId polygon = polygonOnTop(scene_, contacts_, receiver->polygon, [&](PolygonId p) {
    return std::any_of(polygonRoots_[p].begin(), polygonRoots_[p].end(),
                       [&](int root) { return elements_[root].insideness(point) > 0; });
  });
  if (polygonRoots_[polygon].empty()) return std::nullopt;
  const auto mostInside = [&](auto begin, auto end) {
    int best = *begin;
    for (auto it = begin; it != end; ++it)
      if (elements_[*it].insideness(point) > elements_[best].insideness(point)) best = *it;
    return best;
  };
  const auto& roots = polygonRoots_[polygon];
  int id = mostInside(roots.begin(), roots.end());
  while (!elements_[id].isLeaf()) {
    const int first = elements_[id].firstChild;
    const std::array<int, 4> children{first, first + 1, first + 2, first + 3};
    id = mostInside(children.begin(), children.end());
  }
  return id;
}

std::optional<RadiositySample> RadiositySolver::sample(const Vec3& point,
                                                       const Vec3& normal) const {
  const std::optional<int> found = leafContaining(point, normal);
  if (!found) return std::nullopt;
  const int id = *found;
  // Barycentric interpolation on the leaf's triangle (a quadrilateral is two triangles).
  const Element& e = elements_[id];
  const auto& lv = leafVertices_[id];
  int a = 0, b = 1, c = 2;
  if (e.vertexCount == 4 &&
      dot(cross(e.vertices[2] - e.vertices[0], point - e.vertices[0]), e.normal) > 0)
    b = 2, c = 3;
  const Vec3 p = e.normal * 0 + point;
  const double total =
      dot(cross(e.vertices[b] - e.vertices[a], e.vertices[c] - e.vertices[a]), e.normal);
  double wa = dot(cross(e.vertices[b] - p, e.vertices[c] - p), e.normal) / total;
  double wb = dot(cross(e.vertices[c] - p, e.vertices[a] - p), e.normal) / total;
  double wc = dot(cross(e.vertices[a] - p, e.vertices[b] - p), e.normal) / total;
  wa = std::max(wa, 0.0), wb = std::max(wb, 0.0), wc = std::max(wc, 0.0);
  const double sum = wa + wb + wc;
  if (!(sum > 0))
    wa = wb = wc = 1.0 / 3;
  else
    wa /= sum, wb /= sum, wc /= sum;
  const auto lerp = [&](const std::vector<Rgb>& values) {
    return values[lv[a]] * wa + values[lv[b]] * wb + values[lv[c]] * wc;
  };
  return RadiositySample{lerp(mesh_.directIrradiance), lerp(mesh_.indirectIrradiance),
                         lerp(mesh_.radiosity)};
}

Rgb RadiositySolver::irradiance(const Vec3& point, const Vec3& normal) const {
  const auto s = sample(point, normal);
  return s ? s->total() : Rgb{};
}

}  // namespace penumbra
