#pragma once
// Which polygon a probe point lies on. Points read from files carry decimal rounding, so "on" means
// within a distance tolerance of the polygon's plane, inside the polygon (with the same tolerance
// at its edges), with the polygon's front facing the probe normal's side.

#include <optional>
#include <vector>

#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

struct ReceiverMatch {
  PolygonId polygon = 0;
  double planeDistance = 0;  // |signed distance| of the point from the polygon's plane
};

// Relative to the scene's bounding-box diagonal.
inline constexpr double kReceiverRelativeTolerance = 1e-6;

// The polygon nearest to p's plane among those that contain p within the tolerance and face n
// (n · normal > 0), or nothing.
std::optional<ReceiverMatch> locateReceiver(const PosedScene& scene, const UniformGrid& grid,
                                            const Vec3& p, const Vec3& n);
// Every such polygon, nearest plane first (locateReceiver's match first): a point on the edge
// shared by two coplanar polygons (a triangulated quad's diagonal) lies on both.
std::vector<ReceiverMatch> locateReceivers(const PosedScene& scene, const UniformGrid& grid,
                                           const Vec3& p, const Vec3& n);

}  // namespace penumbra
