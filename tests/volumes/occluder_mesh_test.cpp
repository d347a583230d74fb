#include "penumbra/volumes/occluder_mesh.h"

#include <gtest/gtest.h>

#include "penumbra/base/check.h"
#include "penumbra/volumes/object_volume.h"

namespace penumbra {
namespace {

// A unit cube with outward, counter-clockwise faces.
std::vector<Polygon3> cube() {
  const Vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  return {{p[0], p[3], p[2], p[1]}, {p[4], p[5], p[6], p[7]}, {p[0], p[1], p[5], p[4]},
          {p[2], p[3], p[7], p[6]}, {p[1], p[2], p[6], p[5]}, {p[0], p[4], p[7], p[3]}};
}

// Signed volume of the closed surface made by a finite-base volume (divergence theorem): positive
// and equal to the frustum's volume exactly when every face is outward and the surface is closed.
double signedVolume(const ObjectVolume& v) {
  CHECK_GT(v.baseW, 0);
  auto base = [&](int i) { return v.baseVertices[i] / v.baseW; };
  double sum = 0;
  auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) { sum += dot(a, cross(b, c)) / 6; };
  for (const auto& t : v.capTriangles) {
    tri(v.nearVertices[t[0]], v.nearVertices[t[1]], v.nearVertices[t[2]]);
    tri(base(t[2]), base(t[1]), base(t[0]));
  }
  for (const auto& [a, b] : v.silhouetteEdges) {
    tri(v.nearVertices[b], v.nearVertices[a], base(a));
    tri(v.nearVertices[b], base(a), base(b));
  }
  return sum;
}

TEST(OccluderMeshTest, CubeIsClosedAndEveryEdgeHasANeighbour) {
  const OccluderMesh mesh = buildOccluderMesh(cube());
  EXPECT_TRUE(mesh.isClosed);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  for (const auto& ring : mesh.neighbor)
    for (int q : ring) EXPECT_GE(q, 0);
}

TEST(OccluderMeshTest, SquareIsOpenWithBoundaryEdges) {
  const OccluderMesh mesh = buildOccluderMesh({{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}});
  EXPECT_FALSE(mesh.isClosed);
  for (int q : mesh.neighbor[0]) EXPECT_EQ(q, -1);
}

TEST(ObjectVolumeTest, CubeFromAboveHasOneCapAndFourSilhouetteEdges) {
  const OccluderMesh mesh = buildOccluderMesh(cube());
  const Vec3 light{0.5, 0.5, 5};
  const ObjectVolume v = buildObjectVolume(mesh, mesh.vertices, light, 0.25, -1);
  EXPECT_EQ(v.capTriangles.size(), 2u);  // the top face only
  EXPECT_EQ(v.silhouetteEdges.size(), 4u);
  // Frustum from the top face (z = 1, area 1, distance 4 from the light) to k = 4 (distance 16):
  // volume = (16^3 - 4^3) / (3 * 4^2) * 1 = 84.
  EXPECT_NEAR(signedVolume(v), 84.0, 1e-9);
}

TEST(ObjectVolumeTest, CubeFromACornerDirectionIsClosedAndOutward) {
  const OccluderMesh mesh = buildOccluderMesh(cube());
  const ObjectVolume v = buildObjectVolume(mesh, mesh.vertices, {3, 4, 5}, 0.1, -1);
  EXPECT_EQ(v.capTriangles.size(), 6u);  // three faces see the light
  EXPECT_EQ(v.silhouetteEdges.size(), 6u);
  EXPECT_GT(signedVolume(v), 0);
}

TEST(ObjectVolumeTest, OpenSquareCastsFromEitherSide) {
  // A single polygon is opaque from both sides: it casts whether it faces the light or not, and
  // the volumes from both sides are mirror images with the same (positive) volume.
  const OccluderMesh mesh = buildOccluderMesh({{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}});
  const ObjectVolume above = buildObjectVolume(mesh, mesh.vertices, {0.5, 0.5, 1}, 0.5, -1);
  const ObjectVolume below = buildObjectVolume(mesh, mesh.vertices, {0.5, 0.5, -1}, 0.5, -1);
  EXPECT_EQ(above.silhouetteEdges.size(), 4u);
  EXPECT_EQ(below.silhouetteEdges.size(), 4u);
  // Frustum from distance 1 to 2 over a unit square: (8 - 1) / 3 = 7/3.
  EXPECT_NEAR(signedVolume(above), 7.0 / 3, 1e-12);
  EXPECT_NEAR(signedVolume(below), 7.0 / 3, 1e-12);
}

TEST(ObjectVolumeTest, OpenBoxFoldsAreSilhouettes) {
  // A box without its top, lit from above and to the side: some walls face the light, some do
  // not; every polygon casts and the surface stays closed and outward.
  auto faces = cube();
  faces.erase(faces.begin() + 1);
  const OccluderMesh mesh = buildOccluderMesh(faces);
  EXPECT_FALSE(mesh.isClosed);
  const ObjectVolume v = buildObjectVolume(mesh, mesh.vertices, {2.5, 0.3, 4}, 0.2, -1);
  EXPECT_EQ(v.capTriangles.size(), 10u);
  EXPECT_GT(signedVolume(v), 0);
}

}  // namespace
}  // namespace penumbra
