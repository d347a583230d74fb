#pragma once
// Elements: the quadtree nodes into which input polygons are subdivided (Hanrahan, Salzman &
// Aupperle 1991). An element is a triangle or a convex quadrilateral lying in its polygon's plane;
// a refined element has four children (edge midpoints, plus the centre for a quadrilateral), which
// tile it exactly, so radiosity pulled up as an area-weighted mean is exact.

#include <array>
#include <cstdint>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/box.h"
#include "penumbra/scene/scene.h"

namespace penumbra {

// Radiometric state shared by elements and clusters. Irradiance is split into the part that comes
// straight from emitters ("direct") and the rest ("indirect"), so an exact direct term can replace
// ours later without touching the indirect transport.
struct NodeRadiometry {
  Rgb emission;          // radiant exitance M (area mean for inner nodes)
  Rgb gatheredDirect;    // irradiance gathered over this node's own active links from emission
  Rgb gatheredIndirect;  // ... and from reflected radiosity
  Rgb irradianceDirect;  // gathered here plus everything pushed down from ancestors
  Rgb irradianceIndirect;
  // At leaves, the irradiance shown (mesh, probes): re-gathered at the leaf's own points from
  // every active link above it (final_gather.cpp), or the above when RadiosityOptions::finalGather
  // is off.
  Rgb finalDirect;
  Rgb finalIndirect;
  Rgb radiosity;            // B = M + ρ (E_direct + E_indirect) at leaves, area mean above
  Rgb reflected;            // B − M
  double maxRadiosity = 0;  // largest leaf radiosity component below (for the refinement oracle)
  double minRadiosity = 0;  // smallest leaf radiosity component below
};

// The shape of a quadtree node: a triangle or a convex quadrilateral in its polygon's plane, and
// how it splits. Shared by the solvers (each keeps its own radiometry beside it).
struct ElementShape {
  std::array<Vec3, 4> vertices{};  // counter-clockwise seen from the front
  std::uint8_t vertexCount = 0;    // 3 or 4
  Vec3 normal;                     // unit front normal (the polygon's)

  Box3 bounds() const;
  Vec3 centroid() const;
  // The four children's vertex loops, tiling this element.
  std::array<std::array<Vec3, 4>, 4> childVertices() const;
  // The centres (vertex means) of the sixteen cells two quadtree levels down, whether or not the
  // element is split: the receiver oracle's points, and where exact visibility is evaluated.
  std::array<Vec3, 16> grandchildCentres() const;
  // Those sixteen cells' vertex loops, in the same order.
  std::array<std::array<Vec3, 4>, 16> grandchildCells() const;
  // A point of the element from two numbers in [0, 1)², uniform in area.
  Vec3 samplePoint(double u, double v) const;
  // Signed distance-like inside test: >= 0 inside (smallest of the edge distances).
  double insideness(const Vec3& p) const;
  // Which of the four children (childVertices order) holds p, a point of the element's plane:
  // sign tests against the lines between edge midpoints, which split the element into exactly
  // those children (a point on such a line goes to either side).
  int childContaining(const Vec3& p) const;
  // Which of the sixteen cells (grandchildCells order) holds p, a point of the element's plane.
  int grandchildContaining(const Vec3& p) const;
};

struct Element : ElementShape {
  std::uint8_t depth = 0;  // 0 for the root elements of a polygon
  PolygonId polygon = 0;
  int parent = -1;      // element index, -1 for a root element
  int firstChild = -1;  // four consecutive elements, -1 for a leaf
  double area = 0;
  Rgb reflectance;
  NodeRadiometry radiometry;

  bool isLeaf() const { return firstChild < 0; }
};

double elementArea(const std::array<Vec3, 4>& vertices, int count);

}  // namespace penumbra
