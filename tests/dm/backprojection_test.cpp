// Backprojections: labelled at a point, then evaluated elsewhere by recomputing every vertex from
// its features. Checked against the exact reference (independent polygon booleans) at the point
// itself and at nearby points, which share the point's face of the complete mesh unless an event
// passes between them.

#include "penumbra/dm/backprojection.h"

#include <gtest/gtest.h>

#include <random>

#include "penumbra/lighting/form_factor.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "support/boxes.h"

namespace penumbra {
namespace {

double formFactorOf(const std::vector<Polygon3>& rings, const Vec3& p, const Vec3& n) {
  double f = 0;
  for (const Polygon3& ring : rings) f += pointToPolygonFormFactor(p, n, ring);
  return f;
}

struct Agreement {
  int points = 0, labelled = 0, nearbyAgree = 0, nearbyCompared = 0;
};

void checkScene(const PosedScene& scene, int count, Agreement& agreement) {
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const BackprojectionBuilder builder(scene, reference);
  const double size = scene.bounds.diagonalLength();
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> angle(0, 6.283185307179586);
  for (const ReceiverPoint& probe : sampleReceiverPoints(scene, count, 17)) {
    for (PolygonId light : scene.lights) {
      const Backprojection bp = builder.compute(light, probe.p, probe.n, probe.receiver);
      ++agreement.points;
      agreement.labelled += bp.isLabelled ? 1 : 0;
      const double exact = formFactorOf(
          reference.visibleLight(probe.p, probe.n, light, probe.receiver).rings, probe.p, probe.n);
      const double unoccluded = reference.unoccludedFormFactor(probe.p, probe.n, light);
      // At the point itself the labels must reproduce the region exactly.
      EXPECT_NEAR(
          formFactorOf(builder.evaluate(bp, probe.p, probe.n, probe.receiver), probe.p, probe.n),
          exact, 1e-12 * unoccluded + 1e-15)
          << "at " << probe.p;
      if (!bp.isLabelled) continue;
      // Nearby, within the receiver: same face unless an event passes in between.
      const PlaneFrame frame = PlaneFrame::fromPlane(scene.polygons[probe.receiver].plane, probe.p);
      const double a = angle(rng);
      const Vec3 q = probe.p + (frame.u * std::cos(a) + frame.v * std::sin(a)) * (1e-6 * size);
      const double labelled =
          formFactorOf(builder.evaluate(bp, q, probe.n, probe.receiver), q, probe.n);
      const double truth =
          formFactorOf(reference.visibleLight(q, probe.n, light, probe.receiver).rings, q, probe.n);
      ++agreement.nearbyCompared;
      if (std::abs(labelled - truth) <= 1e-11 * unoccluded + 1e-15) ++agreement.nearbyAgree;
    }
  }
}

TEST(Backprojection, LabelsReproduceTheVisibleLightAtThePointAndNearby) {
  Agreement agreement;
  {
    test::SceneBuilder b;
    b.addMaterial("lamp", {0, 0, 0}, {5, 5, 5}).addMaterial("white", {0.5, 0.5, 0.5});
    test::addRoom(b, "white", {-3, -3, 0}, {3, 3, 3});
    b.addPolygon("lamp", {{-0.4, -0.3, 2.9}, {-0.4, 0.3, 2.9}, {0.4, 0.3, 2.9}, {0.4, -0.3, 2.9}});
    test::addBox(b, "white", "floating", {-0.5, -0.4, 1.2}, {0.3, 0.2, 1.6});
    test::addBox(b, "white", "resting", {0.6, 0.5, 0.0}, {1.2, 1.1, 0.5});
    // A tilted non-convex occluder.
    b.addPolygon("white", {{-1.2, 0.4, 1.0},
                           {-0.6, 0.4, 1.1},
                           {-0.6, 0.6, 1.1},
                           {-1.0, 0.6, 1.033},
                           {-1.0, 1.2, 1.033},
                           {-1.2, 1.2, 1.0}});
    const PosedScene scene = b.pose();
    checkScene(scene, 1500, agreement);
  }
  for (const char* name : {"desk-145.json", "desk-475.json"}) {
    const Scene desk = loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/" + name);
    const PosedScene scene = poseAt(desk, 0);
    checkScene(scene, 1500, agreement);
  }
  std::printf("points %d, labelled %d (%.2f%%), nearby agree %d of %d (%.2f%%)\n", agreement.points,
              agreement.labelled, 100.0 * agreement.labelled / agreement.points,
              agreement.nearbyAgree, agreement.nearbyCompared,
              100.0 * agreement.nearbyAgree / std::max(1, agreement.nearbyCompared));
  // Measured: 4,499 of 4,500 labelled (one point left to the reference), and every one of the
  // 4,499 labelled points agrees nearby. At most ten unlabelled points (0.22%, 10x the measured
  // one); nearby disagreement only where an event passes within 1e-6 of the scene size of the
  // point, which none of these seeded points meets: all must agree (the bound was 99% for both).
  EXPECT_GE(agreement.labelled, agreement.points - 10);
  EXPECT_EQ(agreement.nearbyAgree, agreement.nearbyCompared);
}

}  // namespace
}  // namespace penumbra
