// The path-traced reference against the one closed form diffuse global illumination has: a closed
// furnace (every polygon emits M with reflectance ρ) receives M/(1−ρ) at every point, M of it
// directly. Each path vertex adds ρ^k × its exact direct irradiance M, so the expectation is
// M (1 + ρ + ρ² + ...) whatever the geometry hides: a biased path tracer (a wrong cosine pdf, a
// wrong roulette weight, back faces counted) shifts the z-scores long before one point fails.

#include "penumbra/lighting/path_traced_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {
namespace {

TEST(PathTracedReference, FurnaceReceivesEmissionOverOneMinusReflectance) {
  Scene scene =
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json");
  // The lamp is a one-sided polygon below the ceiling: the ceiling above it sees its dark back.
  std::erase_if(scene.objects, [](const SceneObject& o) { return o.name == "light"; });
  // Points on every polygon (sampled before they all emit: the sampler skips emitters).
  const std::vector<ReceiverPoint> samples = sampleReceiverPoints(poseAt(scene, 0), 40, 3);
  const double rho = 0.5;
  for (Material& m : scene.materials) {
    m.emission = Rgb::gray(1);
    m.reflectance = Rgb::gray(rho);
  }
  const PosedScene posed = poseAt(scene, 0);
  const UniformGrid grid(posed);
  const ExactReference exact(posed, &grid);
  const RayCaster rays(posed);
  const PathTracedReference reference(posed, rays, exact);
  double sumZ = 0, sumZ2 = 0, largestZ = 0;
  int count = 0;
  for (const ReceiverPoint& s : samples) {
    const PathTracedEstimate e = reference.irradiance(s.p, s.n, s.receiver, 512, 1000 + count);
    EXPECT_NEAR(e.direct.r, 1, 1e-9);
    const double z = (e.indirect.r - rho / (1 - rho)) / e.indirectStandardError.r;
    sumZ += z;
    sumZ2 += z * z;
    largestZ = std::max(largestZ, std::abs(z));
    ++count;
  }
  const double meanZ = sumZ / count, rmsZ = std::sqrt(sumZ2 / count);
  std::printf("%d points: z mean %.3f, rms %.3f, largest |z| %.2f\n", count, meanZ, rmsZ, largestZ);
  EXPECT_LT(std::abs(meanZ), 4 / std::sqrt(double(count)));  // 4 sigma of the mean of N(0, 1)
  EXPECT_GT(rmsZ, 0.6);
  EXPECT_LT(rmsZ, 1.5);
  EXPECT_LT(largestZ, 4.5);
}

}  // namespace
}  // namespace penumbra
