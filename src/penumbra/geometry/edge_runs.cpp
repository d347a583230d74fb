#include "penumbra/geometry/edge_runs.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

std::vector<VertexRun> edgeRuns(const Polygon3& polygon) {
  const size_t n = polygon.size();
  std::vector<VertexRun> runs;
  if (n <= 2 * kVertexRun) return runs;
  runs.reserve((n + kVertexRun - 1) / kVertexRun);
  for (size_t begin = 0; begin < n; begin += kVertexRun) {
    VertexRun run{begin, std::min(begin + kVertexRun, n), {}};
    for (size_t c = run.begin; c < run.end; ++c) run.box.extend(polygon[c]);
    run.box.extend(polygon[run.end == n ? 0 : run.end]);  // where the run's last edge ends
    runs.push_back(run);
  }
  return runs;
}

std::pair<double, double> signedDistanceRange(const Plane& plane, const Box3& box) {
  const Vec3 centre = box.center(), half = box.diagonal() * 0.5;
  const Vec3& n = plane.normal;
  const double centreDistance = dot(n, centre) - plane.offset;
  const double reach = std::abs(n.x) * half.x + std::abs(n.y) * half.y + std::abs(n.z) * half.z;
  // Evaluating n·x − d at a point of the box rounds by a few ulps of the magnitudes involved;
  // 1e-12 of them is far beyond that, and costs nothing but a few runs visited vertex by vertex.
  const Vec3 far = componentMax(componentMax(box.min, -box.min), componentMax(box.max, -box.max));
  const double slack = 1e-12 * (std::abs(n.x) * far.x + std::abs(n.y) * far.y +
                                std::abs(n.z) * far.z + std::abs(plane.offset));
  return {centreDistance - reach - slack, centreDistance + reach + slack};
}

void clipByPlane(const Polygon3& polygon, std::span<const VertexRun> runs, const Plane& plane,
                 Polygon3& out, std::vector<VertexRun>& outRuns) {
  out.clear();
  outRuns.clear();
  const size_t n = polygon.size();
  if (n == 0) return;
  const auto clipEdge = [&](size_t c) {
    clipEdgeByPlane(polygon[c], polygon[c + 1 == n ? 0 : c + 1], plane, out);
  };
  size_t c = 0;
  for (const VertexRun& run : runs) {
    for (; c < run.begin; ++c) clipEdge(c);
    const auto [low, high] = signedDistanceRange(plane, run.box);
    if (high < 0) {
      // Every vertex behind: the edges between them add nothing. The last one's edge leaves
      // the run, to a vertex the box need not hold.
      clipEdge(run.end - 1);
    } else if (low >= 0) {
      // Every vertex in front: the edges between them add their starts and cross nothing; the
      // run goes on in `out` as it was.
      outRuns.push_back({out.size(), out.size() + (run.end - run.begin), run.box});
      out.insert(out.end(), polygon.begin() + long(run.begin), polygon.begin() + long(run.end - 1));
      clipEdge(run.end - 1);  // adds the run's last vertex first
    } else {
      for (size_t i = run.begin; i < run.end; ++i) clipEdge(i);
    }
    c = run.end;
  }
  for (; c < n; ++c) clipEdge(c);
  if (out.size() < 3) {
    out.clear();
    outRuns.clear();
  }
}

}  // namespace penumbra
