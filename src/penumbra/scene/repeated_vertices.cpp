#include "penumbra/scene/repeated_vertices.h"

namespace penumbra {

long long removeRepeatedVertices(Scene& scene) {
  long long removed = 0;
  for (SceneObject& object : scene.objects)
    for (Polygon3& polygon : object.polygons) {
      Polygon3 kept;
      kept.reserve(polygon.size());
      for (const Vec3& p : polygon)
        if (kept.empty() || !(p == kept.back())) kept.push_back(p);
      while (kept.size() > 1 && kept.back() == kept.front()) kept.pop_back();
      removed += (long long)(polygon.size() - kept.size());
      polygon = std::move(kept);
    }
  return removed;
}

}  // namespace penumbra
