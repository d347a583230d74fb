// Polygons of many vertices and many nearly parallel edges (a finely tessellated disc, a closed
// cylinder) over a floor: the discontinuity mesh is complete (no face verification finds
// unresolved) and exact against the per-point reference at random floor points and at the
// adversarial ones, where each rim vertex's shadow from each light corner lands and a step of
// 1e-7 of the scene beside it. The cost is measured by bench/dm_many_vertices, not here.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/scene/tessellated_solid_scene.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

void expectCompleteAndExact(const TessellatedSolidOptions& options) {
  test::TempDir dir;
  const Scene scene = loadScene(dir.write("solid.json", tessellatedSolidSceneJson(options)));
  DynamicScene live(scene, 0);
  const PosedScene& posed = live.posed();
  DiscontinuityMeshEngine engine;
  engine.build(live);
  EXPECT_EQ(engine.stats().unresolvedFaces, 0);
  EXPECT_EQ(engine.stats().unlabelledBackprojections, 0);
  EXPECT_GT(engine.stats().meshFaces, 5 * options.sides);  // the rim's events cross each other

  const ExactReference reference(posed, &live.grid());
  std::vector<ReceiverPoint> points = sampleReceiverPoints(posed, 600, 5);
  const std::vector<ReceiverPoint> shadows =
      vertexShadowPoints(posed, 0, 1e-7 * posed.extent.diagonalLength());
  ASSERT_GT(shadows.size(), size_t(4 * options.sides));
  points.insert(points.end(), shadows.begin(), shadows.end());
  const double exitance = 10;  // the lamp's (tessellated_solid_scene.h)
  int differ = 0, byMesh = 0, penumbra = 0;
  std::string first;
  for (const ReceiverPoint& q : points) {
    const auto got = engine.query(q.p, q.n);
    ASSERT_TRUE(got.has_value());
    // The engine reports what rounding leaves below zero as zero; the oracle is read alike.
    const double expected = std::max(0.0, reference.irradiance(q.p, q.n, q.receiver).r);
    byMesh += got->answer == DiscontinuityMeshEngine::Answer::kMesh ? 1 : 0;
    const double unoccluded = exitance * reference.unoccludedFormFactor(q.p, q.n, posed.lights[0]);
    penumbra += expected > 1e-3 * unoccluded && expected < 0.999 * unoccluded;
    // Relative; below a millionth of the exitance (an umbra: rounding noise), to that millionth.
    const double error =
        std::abs(got->irradiance.r - expected) / std::max(expected, 1e-6 * exitance);
    if (!(error <= 1e-9) && differ++ == 0)
      first = std::to_string(q.p.x) + " " + std::to_string(q.p.z) + ": " +
              std::to_string(got->irradiance.r) + " vs " + std::to_string(expected);
  }
  EXPECT_EQ(differ, 0) << differ << " of " << points.size() << " differ, first at " << first;
  EXPECT_GT(byMesh, int(points.size() * 9 / 10));
  EXPECT_GT(penumbra, 100);  // the points do probe the soft shadow
}

TEST(ManyVertices, DiscOfTwoHundredVertices) {
  expectCompleteAndExact({.sides = 200});
}

TEST(ManyVertices, CylinderOfNinetySides) {
  expectCompleteAndExact({.sides = 90, .cylinder = true});
}

}  // namespace
}  // namespace penumbra
