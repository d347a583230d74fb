// Dynamic shaft management (Schöffel & Pomi 1999) in the Galerkin line-space update: which pairs
// keep their occluder candidate lists changes the cost, never the result. Solvers that differ only
// in their shaft policy are updated through the same moves and compared bit for bit after each;
// the managed lists are made ahead of a moving object by prediction, and collected by age.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"

namespace penumbra {
namespace {

Scene loadBundled(const std::string& relative) {
  return loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative);
}

GalerkinOptions withShafts(ShaftPolicy policy, double tolerance = 3e-3) {
  GalerkinOptions o;
  o.tolerance = tolerance;
  o.threads = 1;
  o.shafts = policy;
  return o;
}

// The chair room's chair moved by the caller along a straight line (then turning back): a smooth
// motion that prediction can follow.
std::vector<SceneChange> chairSlides(const Scene& scene, DynamicScene& probe, int steps) {
  int chair = -1;
  for (int o = 0; o < int(scene.objects.size()); ++o)
    if (scene.objects[o].isDynamic()) chair = o;
  EXPECT_GE(chair, 0);
  std::vector<SceneChange> changes;
  const Transform start = probe.transformOf(chair);
  for (int step = 1; step <= steps; ++step) {
    const double along = 0.04 * (step <= steps / 2 ? step : steps - step);
    const Transform pose =
        Transform::fromTrs({along, 0, 0.5 * along}, Quaternion::identity(), {1, 1, 1}) * start;
    SceneChange change = probe.changeMoving(chair, pose);
    probe.apply(change);
    changes.push_back(std::move(change));
  }
  return changes;
}

TEST(GalerkinShafts, EveryPolicyGivesTheSameSolutionBitForBit) {
  const Scene scene = loadBundled("chair-room/chair-room.json");
  DynamicScene live(scene, 0);
  std::vector<GalerkinOptions> policies(4, withShafts(ShaftPolicy::kManaged));
  policies[0].shafts = ShaftPolicy::kAll;
  policies[1].management.workerThread = false;
  policies[2].management.prediction = false;
  policies[3].management.keepCount = 0;  // only the empty lists outlive their update
  policies[3].management.keepMoversParents = false;
  std::vector<std::unique_ptr<GalerkinRadiosity>> solvers;
  for (const GalerkinOptions& o : policies) {
    solvers.push_back(std::make_unique<GalerkinRadiosity>(o));
    solvers.back()->build(live);
  }
  // The keyframes forward, then the caller's slides of the chair.
  std::vector<SceneChange> changes;
  {
    DynamicScene probe(scene, 0);
    for (int f = 1; f < scene.frames; ++f) {
      changes.push_back(probe.changeToFrame(f));
      probe.apply(changes.back());
    }
    for (SceneChange& c : chairSlides(scene, probe, 8)) changes.push_back(std::move(c));
  }
  for (size_t step = 0; step < changes.size(); ++step) {
    live.apply(changes[step]);
    for (auto& solver : solvers) {
      solver->update(live, changes[step]);
      // Queries of the solution go on beside the worker's shaft work (ThreadSanitizer checks it).
      for (int k = 0; k < 50; ++k) solver->irradiance({0.1 * k, 0, 0.05 * k}, {0, 1, 0});
    }
    for (size_t p = 1; p < solvers.size(); ++p)
      EXPECT_EQ(solvers[p]->differenceFrom(*solvers[0]), "") << "policy " << p << ", step " << step;
    EXPECT_EQ(solvers[1]->verifyLinks(), "") << "step " << step;
    EXPECT_EQ(solvers[3]->verifyLinks(), "") << "step " << step;
  }
  // Managed lists hold a small part of every pair's; with keepCount 0, nearly none.
  const GalerkinStats &all = solvers[0]->stats(), &managed = solvers[1]->stats(),
                      &lean = solvers[3]->stats();
  EXPECT_LT(managed.shaftBytes, all.shaftBytes / 2);
  EXPECT_LT(lean.shaftBytes, managed.shaftBytes / 10);
  EXPECT_EQ(managed.allShaftBytes, all.allShaftBytes);
}

TEST(GalerkinShafts, AfterABuildAllHoldsEveryPairsListAndManagedOnlyTheRoots) {
  const Scene scene = loadBundled("cornell-box/cornell-box.json");
  DynamicScene live(scene, 0);
  GalerkinRadiosity all(withShafts(ShaftPolicy::kAll)), managed(withShafts(ShaftPolicy::kManaged));
  all.build(live);
  managed.build(live);
  EXPECT_GT(all.stats().shafts, 1);
  EXPECT_EQ(all.stats().shaftBytes, all.stats().allShaftBytes);
  EXPECT_EQ(managed.stats().shafts, 1);
  EXPECT_EQ(managed.stats().allShaftBytes, all.stats().allShaftBytes);
  EXPECT_LT(managed.stats().shaftBytes, all.stats().shaftBytes / 20);
  EXPECT_LT(managed.stats().totalBytes(), all.stats().totalBytes());
}

// Lists no update has used for minAge updates are released; below collectAbove bytes, none.
TEST(GalerkinShafts, CollectionReleasesTheListsNoUpdateUsed) {
  const Scene scene = loadBundled("chair-room/chair-room.json");
  for (const bool collect : {true, false}) {
    GalerkinOptions options = withShafts(ShaftPolicy::kManaged);
    options.management.minAge = 2;
    if (!collect) options.management.collectAbove = std::size_t(1) << 40;
    DynamicScene live(scene, 0);
    GalerkinRadiosity solver(options);
    solver.build(live);
    const SceneChange move = live.changeToFrame(1);
    live.apply(move);
    solver.update(live, move);
    const long long afterMove = solver.stats().shafts;
    EXPECT_GT(afterMove, 100);
    if (collect) {
      // Beyond their update only the lists of at most keepCount candidates are kept, and those
      // the moved chair's own pairs were made from.
      EXPECT_GT(solver.lastUpdate().shaftsCollected, 0);
      long long moversParents = 0;
      for (const GalerkinRadiosity::GLink& link : solver.links())
        if (link.candidates && link.state != GalerkinRadiosity::GLink::kSelf) {
          if (link.candidates->size() > options.management.keepCount) {
            EXPECT_TRUE(link.feedsMovedEnd);
            EXPECT_EQ(link.state, GalerkinRadiosity::GLink::kPassive);
          }
          moversParents += link.feedsMovedEnd;
        }
      EXPECT_GT(moversParents, 0);
    } else {
      EXPECT_EQ(solver.lastUpdate().shaftsCollected, 0);
    }
    // Updates that move nothing age every list; the second one collects them all.
    const SceneChange still;
    solver.update(live, still);
    EXPECT_EQ(solver.stats().shafts, afterMove);
    solver.update(live, still);
    if (collect) {
      EXPECT_EQ(solver.stats().shafts, 1);  // the root pair's
      EXPECT_GT(solver.lastUpdate().shaftsCollected, 100);
    } else {
      EXPECT_EQ(solver.stats().shafts, afterMove);
      EXPECT_EQ(solver.lastUpdate().shaftsCollected, 0);
    }
    // The next move makes what it needs again, with the same result as all lists kept.
    const SceneChange back = live.changeToFrame(2);
    live.apply(back);
    solver.update(live, back);
    EXPECT_EQ(solver.verifyLinks(), "");
  }
}

// A chair sliding along a line: after the first moves, prediction has made most of the lists the
// next update needs, so fewer are made on the fly than without it.
TEST(GalerkinShafts, PredictionMakesListsAheadOfAMovingObject) {
  const Scene scene = loadBundled("chair-room/chair-room.json");
  std::vector<SceneChange> changes;
  {
    DynamicScene probe(scene, 0);
    changes = chairSlides(scene, probe, 12);
  }
  long long made[2] = {0, 0}, predicted[2] = {0, 0}, tests[2] = {0, 0};
  for (const bool prediction : {true, false}) {
    GalerkinOptions options = withShafts(ShaftPolicy::kManaged);
    options.management.prediction = prediction;
    DynamicScene live(scene, 0);
    GalerkinRadiosity solver(options);
    solver.build(live);
    for (size_t step = 0; step < changes.size(); ++step) {
      live.apply(changes[step]);
      solver.update(live, changes[step]);
      if (step < 3) continue;  // prediction needs a few poses
      made[prediction] += solver.lastUpdate().shaftsMade;
      predicted[prediction] += solver.lastUpdate().shaftsPredicted;
      tests[prediction] += solver.lastUpdate().shaftTests;
    }
  }
  EXPECT_GT(predicted[1], 0);
  EXPECT_EQ(predicted[0], 0);
  EXPECT_EQ(tests[0], tests[1]);
  EXPECT_LT(made[1], made[0]);
  EXPECT_LT(double(made[1]), 0.2 * double(tests[1]));
}

}  // namespace
}  // namespace penumbra
