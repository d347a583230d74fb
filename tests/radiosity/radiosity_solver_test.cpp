#include "penumbra/radiosity/radiosity_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>

#include "penumbra/base/input_error.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/path_traced_reference.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "support/boxes.h"
#include "support/closed_form_factors.h"
#include "support/scene_builder.h"

namespace penumbra {
namespace {

std::string scenePath(const std::string& relative) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative;
}

// Area mean of the total irradiance over the leaves of the polygons in [first, last).
double meanIrradiance(const RadiositySolver& solver, PolygonId first, PolygonId last) {
  double sum = 0, area = 0;
  for (const Element& e : solver.elements())
    if (e.isLeaf() && e.polygon >= first && e.polygon < last) {
      sum += (e.radiometry.irradianceDirect + e.radiometry.irradianceIndirect).average() * e.area;
      area += e.area;
    }
  return sum / area;
}

RadiosityOptions withTolerance(double tolerance) {
  RadiosityOptions o;
  o.tolerance = tolerance;
  return o;
}

// Receiver polygon 0 (reflectance 0), source polygon 1 emitting M = 1: the receiver's area-mean
// irradiance is the receiver-to-source form factor.
double solvedFormFactor(const Polygon3& receiver, const Polygon3& source, double tolerance) {
  test::SceneBuilder builder;
  builder.addMaterial("black", Rgb::gray(0)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(1));
  builder.addPolygon("black", receiver).addPolygon("lamp", source);
  RadiositySolver solver(withTolerance(tolerance));
  solver.build(builder.pose());
  return meanIrradiance(solver, 0, 1);
}

// A receiver cut by the source's plane with a vertex on that plane up to a few ulps: a triangle
// of its front part is a needle whose quadtree cells round to no area. That made the link's form
// factor NaN, and the whole solution with it (found in the furnished room: a table's underside
// over a 45-degree-turned slab). One of the 64 offsets below did it.
TEST(RadiositySolver, ReceiverCutByTheSourcePlaneAtAVertexStaysFinite) {
  const double x = 0.1;
  const Polygon3 source{{x, 0, 0}, {x, 1, 0}, {x, 1, 1}, {x, 0, 1}};  // faces +x
  int nonFinite = 0;
  double vertexX = x;
  for (int ulps = 1; ulps <= 64; ++ulps) {
    vertexX = std::nextafter(vertexX, 1.0);
    // One vertex behind the source's plane, one in front, one on it up to `ulps`.
    const Polygon3 receiver{{-0.3037, 0.5, 0.2113}, {0.6173, 0.5, 0.3091}, {vertexX, 0.5, 0.4529}};
    ASSERT_LT(newellNormal(receiver).y, 0);  // faces down, towards the source's lower half
    const double f = solvedFormFactor(receiver, source, 1e-3);
    if (!std::isfinite(f)) ++nonFinite;
    EXPECT_GT(f, 0);
    EXPECT_LT(f, 0.5);
  }
  EXPECT_EQ(nonFinite, 0);
}

TEST(RadiositySolver, ParallelSquaresMatchClosedForm) {
  const Polygon3 floor{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};    // faces +z
  const Polygon3 ceiling{{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};  // faces -z
  const double expected = test::parallelRectangles(1, 1, 1);
  EXPECT_NEAR(expected, 0.19982, 1e-5);
  // Measured (session 9): 1.5e-4 relative (the receiver-area mean of exact point form factors
  // by the links' 16-point quadrature and the leaves' cells).
  EXPECT_NEAR(solvedFormFactor(floor, ceiling, 1e-3), expected, 1e-3 * expected);
}

TEST(RadiositySolver, PerpendicularSquaresMatchClosedForm) {
  const Polygon3 floor{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};  // faces +z
  const Polygon3 wall{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};   // x = 0, faces +x
  const double expected = test::perpendicularRectangles(1, 1, 1);
  EXPECT_NEAR(expected, 0.20004, 1e-5);
  // The shared edge makes the point form factor logarithmic there: refinement resolves it.
  // Measured (session 9): -6.7e-6 relative.
  EXPECT_NEAR(solvedFormFactor(floor, wall, 1e-4), expected, 1e-4 * expected);
}

Scene furnace(Scene scene, double rho) {
  for (Material& m : scene.materials) {
    m.emission = Rgb::gray(1);
    m.reflectance = Rgb::gray(rho);
  }
  return scene;
}
// The bundled rooms' lamps are single polygons hanging 1 cm below the ceiling, emitting
// downwards only: the ceiling above one sees its dark back, where E < M/(1−ρ) in the exact
// solution too. The furnace scenes leave them out (the rooms stay closed), so that M/(1−ρ) is
// the exact answer at every point.
Scene furnace(const std::string& path, double rho) {
  Scene scene = loadScene(scenePath(path));
  std::erase_if(scene.objects, [](const SceneObject& o) { return o.name == "light"; });
  return furnace(std::move(scene), rho);
}

struct FurnaceResult {
  double meanError = 0;           // |area mean of E − M/(1−ρ)| / (M/(1−ρ))
  double directError = 0;         // |area mean of the direct part − M| / M
  double balanceError = 0;        // |absorbed / emitted − 1|
  double areaWithin1Percent = 0;  // share of the leaf area where E is within 1% of M/(1−ρ)
  double largestError = 0;        // largest |E − M/(1−ρ)| / (M/(1−ρ)) over the leaves
  // The same for the solution's leaf irradiance (the mean pushed down from the links above),
  // before the final gather.
  double solutionAreaWithin1Percent = 0;
  long long links = 0;
};

// Every polygon emits M = 1 with reflectance ρ in a closed scene: B = M/(1−ρ) and the
// irradiance equals B everywhere; the direct part (emission carried once) is M, as the form
// factors from any point sum to 1 (the rooms' one-sided lamps are left out, see furnace()).
FurnaceResult solveFurnace(const Scene& scene, double rho, const RadiosityOptions& options) {
  const double tolerance = options.tolerance;
  RadiositySolver solver(options);
  solver.build(scene, 0);
  const double expected = 1 / (1 - rho);
  double sum = 0, direct = 0, area = 0, within = 0, solutionWithin = 0, largest = 0;
  for (const Element& e : solver.elements())
    if (e.isLeaf()) {
      const double solution =
          (e.radiometry.irradianceDirect + e.radiometry.irradianceIndirect).average();
      if (std::abs(solution - expected) <= 0.01 * expected) solutionWithin += e.area;
      // What is shown at the leaf (the final gather's irradiance with the default options).
      const double irradiance = (e.radiometry.finalDirect + e.radiometry.finalIndirect).average();
      sum += irradiance * e.area;
      direct += e.radiometry.finalDirect.average() * e.area;
      area += e.area;
      if (std::abs(irradiance - expected) <= 0.01 * expected) within += e.area;
      largest = std::max(largest, std::abs(irradiance - expected) / expected);
    }
  FurnaceResult result;
  result.meanError = std::abs(sum / area - expected) / expected;
  result.directError = std::abs(direct / area - 1);
  result.balanceError =
      std::abs(solver.absorbedPower().average() / solver.emittedPower().average() - 1);
  result.areaWithin1Percent = within / area;
  result.largestError = largest;
  result.solutionAreaWithin1Percent = solutionWithin / area;
  result.links = solver.stats().links;
  std::printf(
      "tolerance %7.0e links %8lld  mean E error %.5f  direct error %.5f  absorbed/emitted "
      "error %.5f  area within 1%%: %.3f (hierarchical solution: %.3f)  largest leaf error "
      "%.2e\n",
      tolerance, result.links, result.meanError, result.directError, result.balanceError,
      result.areaWithin1Percent, result.solutionAreaWithin1Percent, result.largestError);
  return result;
}
FurnaceResult solveFurnace(const Scene& scene, double rho, double tolerance) {
  return solveFurnace(scene, rho, withTolerance(tolerance));
}

// A closed empty room (the chair room without furniture): links to all sources at one level
// cancel their variations, so the receiver oracle leaves few links and the result is exact up to
// the form factor quadrature.
TEST(RadiositySolver, FurnaceInEmptyRoom) {
  Scene scene = furnace("chair-room/chair-room.json", 0.5);
  scene.objects.resize(2);  // room-floor, room-walls
  for (double tolerance : {1e-3, 3e-4}) {
    const FurnaceResult r = solveFurnace(scene, 0.5, tolerance);
    // 1e-3: the target; measured below 1e-4 (quadrature of the exact point form factors).
    EXPECT_LT(r.meanError, 1e-3);
    EXPECT_LT(r.directError, 1e-3);
    EXPECT_LT(r.balanceError, 1e-3);
    EXPECT_GT(r.areaWithin1Percent, 0.99);
  }
}

// The chair room (227 polygons): furniture standing on the floor, doors glued on a sideboard,
// shelves in contact with their sides, partial visibility everywhere. The target: M/(1−ρ)
// everywhere to 1%. What is shown is the final solution (final_gather.cpp): at every leaf point
// the element sources' exact visible form factors, and what they leave of the hemisphere split by
// rays among the cluster sources' surfaces, so a point's transfers sum to 1 in a closed scene.
// Measured: every leaf within 0.23% of 2 at both tolerances (what is left is the rays' split of
// the remainder where some meet nothing, so it does not shrink with the tolerance); area means
// within 1e-4.
TEST(RadiositySolver, FurnaceInChairRoom) {
  const Scene scene = furnace("chair-room/chair-room.json", 0.5);
  const FurnaceResult coarse = solveFurnace(scene, 0.5, 1e-3);
  const FurnaceResult fine = solveFurnace(scene, 0.5, 3e-4);
  for (const FurnaceResult& r : {coarse, fine}) {
    EXPECT_LT(r.meanError, 1e-3);
    EXPECT_LT(r.balanceError, 1e-3);
    EXPECT_LT(r.largestError, 0.01);
    EXPECT_EQ(r.areaWithin1Percent, 1.0);
  }
  EXPECT_GT(fine.links, coarse.links);
}

// The hierarchical solution that drove refinement (each leaf the mean its ancestors' links pushed
// down) tightens with the tolerance: that is what the refinement oracles control. It shows when
// the links' visibility is estimated finely (16 rays: measured 44.8% of the chair room's area
// within 1% at 1e-3, 64.5% at 3e-4); with the default 4 rays per link the links' visibility noise
// dominates the hierarchical furnace (measured 28.9% and 31.6%), while what is shown, the final
// gather's solution, stays within 0.23% everywhere (FurnaceInChairRoom).
TEST(RadiositySolver, HierarchicalFurnaceTightensWithTheTolerance) {
  const Scene scene = furnace("chair-room/chair-room.json", 0.5);
  RadiosityOptions coarseOptions = withTolerance(1e-3), fineOptions = withTolerance(3e-4);
  coarseOptions.visibilityRays = fineOptions.visibilityRays = 16;
  const FurnaceResult coarse = solveFurnace(scene, 0.5, coarseOptions);
  const FurnaceResult fine = solveFurnace(scene, 0.5, fineOptions);
  EXPECT_GT(fine.solutionAreaWithin1Percent, coarse.solutionAreaWithin1Percent + 0.05);
}

// Exact visibility against rays in the links, side by side: with exact visible form factors at
// the receiver points the hierarchical solution's transfers sum to 1 at those points, where 16
// rays per link leave each partly hidden link's visibility off by about 0.1 of its transfer
// (measured in the Cornell box without its lamp at 1e-3: 93.6% of the solution's area within 1%
// against 67.1%). The final solution is exact in the furnace either way.
TEST(RadiositySolver, ExactVisibilityTightensTheFurnace) {
  const Scene scene = furnace("cornell-box/cornell-box.json", 0.5);
  RadiosityOptions exactOptions = withTolerance(1e-3);
  exactOptions.exactVisibility = true;
  const FurnaceResult exact = solveFurnace(scene, 0.5, exactOptions);
  const FurnaceResult sampled = solveFurnace(scene, 0.5, 1e-3);
  EXPECT_GT(exact.solutionAreaWithin1Percent, 0.9);
  EXPECT_GT(exact.solutionAreaWithin1Percent, sampled.solutionAreaWithin1Percent + 0.15);
  for (const FurnaceResult& r : {exact, sampled}) {
    EXPECT_LT(r.meanError, 1e-3);
    EXPECT_LT(r.largestError, 0.01);
  }
}

// The furnished room (1,300 polygons: desks, drawers with handles, bookshelves 1 cm off the
// walls, chairs) at 3e-4. Measured: mean and balance within 1e-4, every leaf within 0.4% (the
// hierarchical solution that drove refinement: 42.2% of the area within 1%, and it absorbed 0.83%
// more than was emitted). Rays from a point a hair beside a book standing on a shelf passed its
// near side and met its far side from inside: counted as dark, they left shelf leaves 1.3% low.
TEST(RadiositySolver, FurnaceInFurnishedRoom) {
  const FurnaceResult r = solveFurnace(furnace("chair-room/furnished-room.json", 0.5), 0.5, 3e-4);
  EXPECT_LT(r.meanError, 1e-3);
  EXPECT_LT(r.balanceError, 1e-3);
  EXPECT_EQ(r.areaWithin1Percent, 1.0);
  EXPECT_LT(r.largestError, 0.01);
}

// Small objects in a furnace: a crate on the floor (its bottom in contact, seeing only the floor),
// a stack of small cubes (contacts between them) and a floating cube. Each is a cluster of a
// few polygons far smaller than the room, which as a receiver would hand all its faces one mean
// irradiance: the crate's bottom, which sees only the floor, the same as its top. Every leaf of
// these objects must get M/(1−ρ) within 3% (the visibility estimates' noise; measured below 1%
// but for the faces next to contacts).
TEST(RadiositySolver, FurnaceOnSmallClusters) {
  test::SceneBuilder builder;
  builder.addMaterial("grey", Rgb::gray(0.5), Rgb::gray(1));
  test::addRoom(builder, "grey", {0, 0, 0}, {4, 3, 5});
  test::addBox(builder, "grey", "crate", {1.0, 0, 1.0}, {1.3, 0.3, 1.3});
  test::addBox(builder, "grey", "cube1", {2.5, 0, 3.0}, {2.7, 0.2, 3.2});
  test::addBox(builder, "grey", "cube2", {2.5, 0.2, 3.0}, {2.7, 0.4, 3.2});
  test::addBox(builder, "grey", "float", {3.0, 1.5, 1.0}, {3.2, 1.7, 1.2});
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(builder.pose());
  double lowest = 1e300, highest = 0;
  for (const Element& e : solver.elements())
    if (e.isLeaf() && e.polygon >= 6) {
      const double irradiance = (e.radiometry.finalDirect + e.radiometry.finalIndirect).average();
      lowest = std::min(lowest, irradiance);
      highest = std::max(highest, irradiance);
    }
  std::printf("small objects' leaves: E in [%.4f, %.4f] (expected 2)\n", lowest, highest);
  EXPECT_GT(lowest, 2 * 0.97);
  EXPECT_LT(highest, 2 * 1.03);
}

// Energy balance with one lamp: a closed room, a lamp that is a thin closed box 1 cm below the
// ceiling (only its underside emits, so every surface has a modelled front side), a crate
// standing on the floor. Emitted power = absorbed power.
TEST(RadiositySolver, EnergyBalanceWithOneLamp) {
  test::SceneBuilder builder;
  builder.addMaterial("white", Rgb{0.7, 0.6, 0.5})
      .addMaterial("lamp", Rgb::gray(0), Rgb{100, 90, 80})
      .addMaterial("crate", Rgb{0.3, 0.5, 0.6});
  test::addRoom(builder, "white", {0, 0, 0}, {4, 3, 5});
  const auto lamp = test::boxFaces({1.7, 2.97, 2.2}, {2.3, 2.99, 2.8});
  for (size_t i = 0; i < lamp.size(); ++i)
    builder.addPolygon(i == 2 ? "lamp" : "white", lamp[i], "lamp");
  test::addBox(builder, "crate", "crate", {1.0, 0, 1.0}, {2.0, 0.8, 1.8});
  std::vector<double> errors;
  for (double tolerance : {1e-3, 3e-4}) {
    RadiositySolver solver(withTolerance(tolerance));
    solver.build(builder.pose());
    const Rgb emitted = solver.emittedPower(), absorbed = solver.absorbedPower();
    std::printf("tolerance %7.0e links %8lld emitted %.4f absorbed %.4f %.4f %.4f\n", tolerance,
                solver.stats().links, emitted.r, absorbed.r, absorbed.g, absorbed.b);
    EXPECT_NEAR(emitted.r, 100 * 0.36, 1e-9);
    errors.push_back(
        std::max({std::abs(absorbed.r / emitted.r - 1), std::abs(absorbed.g / emitted.g - 1),
                  std::abs(absorbed.b / emitted.b - 1)}));
  }
  // 1% is the target; measured 0.44% at 1e-3 and 0.25% at 3e-4 (session 9; 0.28% and 0.32%
  // with 16 visibility rays per link; the hierarchical solution's
  // balance, before the final solution, 1.0% and 0.25%).
  for (double error : errors) EXPECT_LT(error, 0.005);
}

// The chair room under its lamp, element sources sending per cell (elementSourceShares): the
// part of a source hidden from a receiver is also the part in shadow, so the source's mean B sent
// at the visible part's visibility lost 3% of the reflected power (absorbed / emitted 0.97).
// Absorbed = emitted within 1%, the target (measured 0.996).
TEST(RadiositySolver, EnergyBalanceInChairRoomWithElementShares) {
  RadiosityOptions options = withTolerance(1e-3);
  options.elementSourceShares = true;
  RadiositySolver solver(options);
  solver.build(loadScene(scenePath("chair-room/chair-room.json")), 0);
  const double balance = solver.absorbedPower().average() / solver.emittedPower().average();
  std::printf("links %lld absorbed / emitted %.4f\n", solver.stats().links, balance);
  EXPECT_NEAR(balance, 1, 0.01);
}

// The chair room under its lamp with the default options: the final solution gathers the
// partly hidden sources by rays, which take the radiosity of the leaf they meet, so the part of a
// wall hidden from a receiver, often the part in shadow, is not sent at the wall's mean radiosity
// (the hierarchical solution lost 3% that way: absorbed / emitted 0.971). Measured 0.9944.
TEST(RadiositySolver, EnergyBalanceInChairRoom) {
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(loadScene(scenePath("chair-room/chair-room.json")), 0);
  const double balance = solver.absorbedPower().average() / solver.emittedPower().average();
  std::printf("links %lld absorbed / emitted %.4f\n", solver.stats().links, balance);
  EXPECT_NEAR(balance, 1, 0.01);
}

TEST(RadiositySolver, KeepsPassiveLinksAndShafts) {
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(loadScene(scenePath("cornell-box/cornell-box.json")), 0);
  const RadiosityStats& s = solver.stats();
  EXPECT_EQ(s.links, s.activeLinks + s.passiveLinks);
  EXPECT_GT(s.passiveLinks, 0);
  EXPECT_EQ(s.shafts, s.links);
  EXPECT_FALSE(solver.links()[0].active);  // the root self-link is always refined
  long long activeBelowPassive = 0;
  for (const Link& link : solver.links())
    if (!link.active)
      for (int child : link.children) activeBelowPassive += solver.links()[child].active;
  EXPECT_GT(activeBelowPassive, 0);
  EXPECT_GT(s.shaftBytes, 400 * std::size_t(s.shafts));
  EXPECT_GT(s.totalBytes(), 0u);
}

// Direct irradiance at element vertices against the exact reference, tolerance by tolerance.
// The direct part (emission carried once over the links) at element vertices against the exact
// reference irradiance (visible part of the lamp by polygon clipping, Lambert's formula), tolerance
// by tolerance: the mean error over the vertices and the largest, both relative to the mean exact
// irradiance (pointwise relative errors are unbounded in the umbra). The largest error does not
// shrink: the exact irradiance jumps where the boxes touch the floor (a vertex on that edge is
// half in the dark), and vertex values average the leaves around them; the 95th percentile does.
TEST(RadiositySolver, DirectPartConvergesToExactReference) {
  const Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
  const PosedScene posed = poseAt(scene, 0);
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  std::printf("tolerance     links  vertices  mean|err|/meanE  p95|err|/meanE  max|err|/meanE\n");
  std::vector<double> meanErrors, maxErrors, p95Errors;
  for (double tolerance : {1e-2, 1e-3, 3e-4}) {
    RadiositySolver solver(withTolerance(tolerance));
    solver.build(posed);
    const RadiosityMesh& mesh = solver.mesh();
    const size_t stride = std::max<size_t>(1, mesh.positions.size() / 400);
    double errorSum = 0, exactSum = 0, largest = 0;
    int count = 0;
    std::vector<double> vertexErrors;
    for (size_t v = 0; v < mesh.positions.size(); v += stride) {
      if (posed.polygons[mesh.polygons[v]].isLight) continue;
      ++count;
      const double exact =
          reference.irradiance(mesh.positions[v], mesh.normals[v], mesh.polygons[v]).average();
      const double error = std::abs(mesh.directIrradiance[v].average() - exact);
      errorSum += error;
      exactSum += exact;
      largest = std::max(largest, error);
      vertexErrors.push_back(error);
    }
    meanErrors.push_back(errorSum / exactSum);
    maxErrors.push_back(largest / (exactSum / count));
    std::sort(vertexErrors.begin(), vertexErrors.end());
    p95Errors.push_back(vertexErrors[vertexErrors.size() * 95 / 100] / (exactSum / count));
    std::printf("%9.0e %9lld %9zu %16.4f %15.4f %15.4f\n", tolerance, solver.stats().links,
                mesh.positions.size(), meanErrors.back(), p95Errors.back(), maxErrors.back());
  }
  for (size_t k = 1; k < meanErrors.size(); ++k) EXPECT_LT(meanErrors[k], meanErrors[k - 1]);
  EXPECT_LT(p95Errors.back(), p95Errors.front());
  EXPECT_LT(meanErrors.back(), 0.10);
}

// The final solution's indirect irradiance against an independent reference, path tracing with
// exact next-event estimation (lighting/path_traced_reference.h), in the Cornell box under its
// lamp: the furnace only shows that a point's transfers sum to 1, not that the light is split
// among the sources as it should be. Leaf by leaf (every 25th), the leaf's indirect irradiance
// (its area mean) against the path-traced mean over 16 points of the leaf, one uniform in each of
// its 16 grandchild cells, 96 paths each. The reference's standard error is the spread of those
// 16 values over sqrt(16): it holds the paths' noise and how the irradiance varies over the leaf
// (a leaf half over the lamp, whose back hides the room from the ceiling, varies 30-fold; the
// paths' noise alone made such a leaf look 7.8 standard errors off).
// Leaf by leaf (every stride-th), a part of the final solution's irradiance (`ours`) against the
// independent path tracer's mean over one point in each of the leaf's 16 grandchild cells; z is
// the difference over the reference's standard error (the spread of the 16 values).
struct LeafComparison {
  int leaves = 0, darkLeaves = 0, contactLeaves = 0;
  double meanZ = 0, rmsZ = 0, largestZ = 0, meanError = 0, noise = 0;
};
// Is x, a point of polygon p, covered by another polygon lying in p's plane and facing it?
bool isUnderAPolygonInContact(const PosedScene& posed, PolygonId p, const Vec3& x) {
  const WorldPolygon& receiver = posed.polygons[p];
  for (const WorldPolygon& q : posed.polygons) {
    if (dot(q.plane.normal, receiver.plane.normal) > -1 + 1e-9) continue;
    if (std::abs(q.plane.signedDistance(x)) > 1e-9) continue;
    bool inside = true;
    for (size_t i = 0; i < q.vertices.size() && inside; ++i) {
      const Vec3& a = q.vertices[i];
      const Vec3& b = q.vertices[(i + 1) % q.vertices.size()];
      inside = dot(cross(b - a, x - a), q.plane.normal) >= 0;
    }
    if (inside) return true;
  }
  return false;
}

LeafComparison compareLeavesWithPathTracing(
    const PosedScene& posed, const RadiositySolver& solver, size_t stride, int paths,
    const std::function<double(const NodeRadiometry&)>& ours,
    const std::function<double(const PathTracedEstimate&)>& theirs) {
  // Sampled direct light: visibility by the ray caster's shadow rays, none of the exact
  // reference's clipping that the solver's gather uses for partly hidden lamps.
  const RayCaster rays(posed);
  const PathTracedReference reference(posed, rays);
  std::uint64_t seed = 1;
  double errorSum = 0, referenceSum = 0, sumZ = 0, sumZ2 = 0, noiseSum = 0;
  double largestRadiosity = 0;
  for (const Element& e : solver.elements())
    largestRadiosity = std::max(largestRadiosity, e.radiometry.radiosity.maxComponent());
  LeafComparison result;
  bool everyPolygonEmits = true;
  for (const WorldPolygon& p : posed.polygons) everyPolygonEmits = everyPolygonEmits && p.isLight;
  for (size_t i = 0; i < solver.elements().size(); i += stride) {
    const Element& e = solver.elements()[i];
    // A lamp's own leaves are left out (a lamp 1 mm below the ceiling, whose paths start
    // between the two); where every polygon emits, none is a lamp of that kind.
    if (!e.isLeaf() || (posed.polygons[e.polygon].isLight && !everyPolygonEmits)) continue;
    const auto cells = e.grandchildCells();
    std::array<Vec3, 16> points{};
    bool covered = false;
    for (int k = 0; k < 16; ++k) {
      Element cell;
      cell.vertices = cells[k];
      cell.vertexCount = e.vertexCount;
      points[k] =
          cell.samplePoint(0.5 + 0.45 * std::sin(seed * 1.7), 0.5 + 0.45 * std::cos(seed * 2.3));
      ++seed;
      covered = covered || isUnderAPolygonInContact(posed, e.polygon, points[k]);
    }
    // Under a polygon in face-to-face contact (a block's foot on the floor) the sampled path
    // tracer sees the coplanar polygon edge-on and gives 0 where the limit as the gap closes,
    // which the solver models, does not: such leaves say nothing here.
    if (covered) {
      ++result.contactLeaves;
      continue;
    }
    std::array<double, 16> values{};
    double mean = 0;
    for (int k = 0; k < 16; ++k) {
      values[k] = theirs(reference.irradiance(points[k], e.normal, e.polygon, paths, seed + k));
      mean += values[k] / 16;
    }
    double variance = 0;
    for (double v : values) variance += (v - mean) * (v - mean) / (15.0 * 16.0);
    const double value = ours(e.radiometry);
    if (variance == 0) {
      // Every path from the leaf's points met nothing lit: a leaf wholly under a block, which
      // sees only the block's dark bottom. Ours is then what the leaves' Jacobi iteration leaves
      // of its starting values: it stops when no radiosity changes by more than convergence x
      // the largest, so what remains is below that x ρ / (1 − ρ) (ρ <= 0.8 here).
      EXPECT_EQ(mean, 0);
      EXPECT_LT(value, 4 * solver.options().convergence * largestRadiosity) << "leaf " << i;
      ++result.darkLeaves;
      continue;
    }
    const double z = (value - mean) / std::sqrt(variance);
    errorSum += std::abs(value - mean) * e.area;
    noiseSum += std::sqrt(variance) * e.area;
    referenceSum += mean * e.area;
    sumZ += z;
    sumZ2 += z * z;
    result.largestZ = std::max(result.largestZ, std::abs(z));
    ++result.leaves;
  }
  result.meanError = errorSum / referenceSum;
  result.noise = noiseSum / referenceSum;  // the reference's standard error, area mean
  result.meanZ = sumZ / result.leaves;
  result.rmsZ = std::sqrt(sumZ2 / result.leaves);
  std::printf(
      "%d leaves (and %d dark, %d under a contact): mean |error| %.4f of the reference, z mean "
      "%.2f rms %.2f largest %.2f; the reference's standard error %.4f\n",
      result.leaves, result.darkLeaves, result.contactLeaves, result.meanError, result.meanZ,
      result.rmsZ, result.largestZ, result.noise);
  return result;
}

// The final solution's indirect irradiance against an independent reference, path tracing
// with sampled direct light and its own visibility, in the Cornell box under its lamp: the
// furnace only shows that a point's transfers sum to 1, not that the light is split among the
// sources as it should be.
TEST(RadiositySolver, IndirectAgreesWithPathTracing) {
  const PosedScene posed = poseAt(loadScene(scenePath("cornell-box/cornell-box.json")), 0);
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(posed);
  const LeafComparison c = compareLeavesWithPathTracing(
      posed, solver, 25, 96, [](const NodeRadiometry& m) { return m.finalIndirect.average(); },
      [](const PathTracedEstimate& e) { return e.indirect.average(); });
  // Measured (session 9): 52 leaves (3 under a block's foot left out), z mean 0.05, rms 1.33,
  // largest 2.83; mean |error| 5.4% of the reference against its standard error of 5.9%: the
  // differences are the reference's own noise (pure noise: a mean |error| of 0.8 errors).
  EXPECT_LT(std::abs(c.meanZ), 4 / std::sqrt(double(c.leaves)));
  EXPECT_LT(c.rmsZ, 1.5);
  EXPECT_LT(c.largestZ, 4.5);
  EXPECT_LT(c.meanError, 1.5 * c.noise);
}

// A check the final solution's normalization cannot pass by construction (issue 21): an open
// scene with mixed reflectances where every polygon emits, so the answer is no closed form and
// light leaves through the opening. The Cornell box without its lamp and without the black room
// in front of its opening; white, red and green reflectances as modelled, each polygon emitting
// M = 1. The total irradiance per leaf against the independent path tracer.
TEST(RadiositySolver, OpenMixedEmittersAgreeWithIndependentPathTracing) {
  Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
  std::erase_if(scene.objects,
                [&](const SceneObject& o) { return o.name == "light" || o.name == "room-black"; });
  for (Material& m : scene.materials) m.emission = Rgb::gray(1);
  const PosedScene posed = poseAt(scene, 0);
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(posed);
  const LeafComparison c = compareLeavesWithPathTracing(
      posed, solver, 10, 96,
      [](const NodeRadiometry& m) { return (m.finalDirect + m.finalIndirect).average(); },
      [](const PathTracedEstimate& e) { return e.total().average(); });
  // Measured (session 9): 64 leaves (10 beside the blocks' feet left out), z mean 0.05, rms 1.19,
  // largest 3.24; mean |error| 3.0% against the reference's standard error of 3.2%.
  EXPECT_LT(std::abs(c.meanZ), 4 / std::sqrt(double(c.leaves)));
  EXPECT_LT(c.rmsZ, 1.5);
  EXPECT_LT(c.largestZ, 4.5);
  EXPECT_LT(c.meanError, 1.5 * c.noise);
}

// Direct and indirect are separate sums: with nothing reflecting, the indirect part is exactly 0
// and the direct part is unchanged by the reflectances (it depends on emission only).
TEST(RadiositySolver, DirectPartIsIndependentOfReflection) {
  Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
  RadiositySolver reflecting(withTolerance(1e-2));
  reflecting.build(scene, 0);
  for (Material& m : scene.materials) m.reflectance = Rgb::gray(0);
  RadiositySolver black(withTolerance(1e-2));
  black.build(scene, 0);
  double directReflecting = 0, directBlack = 0;
  for (const Element& e : black.elements())
    if (e.isLeaf()) {
      EXPECT_EQ(e.radiometry.irradianceIndirect, Rgb{});
      directBlack += e.radiometry.irradianceDirect.average() * e.area;
    }
  for (const Element& e : reflecting.elements())
    if (e.isLeaf()) directReflecting += e.radiometry.irradianceDirect.average() * e.area;
  // The power arriving directly is the same; the meshes differ (the oracle weighs reflected light),
  // so only to the refinement's accuracy: 1%.
  EXPECT_NEAR(directReflecting, directBlack, 0.01 * directBlack);
}

TEST(RadiositySolver, IrradianceAtPointsSplitsDirectAndIndirect) {
  RadiositySolver solver(withTolerance(1e-3));
  solver.build(loadScene(scenePath("cornell-box/cornell-box.json")), 0);
  // Floor point in the open: lit directly and indirectly.
  const auto s = solver.sample({0.1, 0, 0.45}, {0, 1, 0});
  ASSERT_TRUE(s);
  EXPECT_GT(s->direct.average(), 0);
  EXPECT_GT(s->indirect.average(), 0);
  EXPECT_EQ(solver.irradiance({0.1, 0, 0.45}, {0, 1, 0}), s->total());
  // A point in mid-air lies on no receiver.
  EXPECT_FALSE(solver.sample({0.3, 0.3, 0.3}, {0, 1, 0}));
}

// An inside-out box standing on the floor (its bottom lies on the floor facing the same way): a
// closed cavity that no light enters. Both the box's bottom and the floor under it took the light
// arriving there, so the cavity returned more than it received: refinement went past the link
// budget. The box's bottom now lies on top (coveringPolygons); the cavity stays dark, and a point
// on a rug lying on the floor is answered from the rug.
TEST(RadiositySolver, AnInsideOutBoxOnTheFloorStaysDark) {
  test::SceneBuilder b;
  b.addMaterial("wall", Rgb::gray(0.9)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(10));
  b.addMaterial("rug", Rgb::gray(0.2));
  test::addRoom(b, "wall", {0, 0, 0}, {2, 2, 2});
  b.addPolygon(
      "lamp",
      {{0.625, 1.75, 0.375}, {1.125, 1.75, 0.375}, {1.125, 1.75, 0.875}, {0.625, 1.75, 0.875}},
      "lamp");
  for (Polygon3 f : test::boxFaces({1.5, 0, 1.5}, {1.875, 0.625, 1.875})) {
    std::reverse(f.begin(), f.end());
    b.addPolygon("wall", f, "inside-out box");
  }
  b.addPolygon("rug", {{0.25, 0, 1.25}, {0.25, 0, 1.75}, {1.0, 0, 1.75}, {1.0, 0, 1.25}}, "rug");
  RadiositySolver solver;
  solver.build(b.pose());
  const double floor = solver.irradiance({0.5, 0, 0.5}, {0, 1, 0}).average();
  const double inside = solver.irradiance({1.875, 0.3, 1.6}, {-1, 0, 0}).average();
  const double onTheFloorInside = solver.irradiance({1.6, 0, 1.6}, {0, 1, 0}).average();
  const auto onTheRug = solver.sample({0.5, 0, 1.5}, {0, 1, 0});
  ASSERT_TRUE(onTheRug);
  std::printf(
      "links %lld; floor %.4f, the cavity's wall %.2e, its floor %.2e; on the rug: "
      "radiosity %.4f of irradiance %.4f\n",
      solver.stats().activeLinks, floor, inside, onTheFloorInside, onTheRug->radiosity.average(),
      onTheRug->total().average());
  EXPECT_LT(inside, 1e-3 * floor);
  EXPECT_LT(onTheFloorInside, 1e-3 * floor);
  // The rug reflects 0.2 of what it receives (the floor under it would reflect 0.9).
  EXPECT_NEAR(onTheRug->radiosity.average(), 0.2 * onTheRug->total().average(),
              1e-3 * onTheRug->total().average());
}

// A two-sided card (two polygons back to back) standing under a lamp, against the same room with
// a 0.1 mm thick box in its place (the path tracer agrees with that one: docs/radiosity.md, session
// 32). The card's sides counted as polygons in face-to-face contact, covering each other (each
// read what the other reflects); given them as no contact while still exchanging all their light
// where they overlap (contacts do), refinement ran past its budget. Now each side is lit from its
// own side alone.
TEST(RadiositySolver, BothSidesOfATwoSidedCardAreLit) {
  const auto solve = [](bool card) {
    test::SceneBuilder b;
    b.addMaterial("wall", Rgb::gray(0.6)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(10));
    test::addRoom(b, "wall", {0, 0, 0}, {2, 2, 2});
    b.addPolygon("lamp",
                 {{0.2, 1.999, 0.2}, {0.7, 1.999, 0.2}, {0.7, 1.999, 0.7}, {0.2, 1.999, 0.7}},
                 "lamp");
    if (card) {
      const Polygon3 side{{1, 0.5, 0.5}, {1, 1.5, 0.5}, {1, 1.5, 1.5}, {1, 0.5, 1.5}};
      b.addPolygon("wall", side, "card");
      b.addPolygon("wall", {side[3], side[2], side[1], side[0]}, "card");
    } else {
      test::addBox(b, "wall", "slab", {1, 0.5, 0.5}, {1.0001, 1.5, 1.5});
    }
    auto solver = std::make_unique<RadiositySolver>(withTolerance(3e-3));
    solver->build(b.pose());
    return solver;
  };
  const auto card = solve(true), slab = solve(false);
  for (const Vec3& p : {Vec3{1, 1, 1}, Vec3{1, 0.7, 1.3}})
    for (const Vec3& n : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}}) {
      const Vec3 onSlab = n.x > 0 ? p + Vec3{0.0001, 0, 0} : p;
      const double e = card->irradiance(p, n).average(), s = slab->irradiance(onSlab, n).average();
      std::printf("(%.1f %.1f %.1f) facing %+.0f: card %.4f, slab %.4f\n", p.x, p.y, p.z, n.x, e,
                  s);
      EXPECT_NEAR(e, s, 0.03 * s);
    }
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// Reflectance 1 loads (issue: MTL `Kd 1 1 1`), and radiosity either converges with it (light
// escapes an open scene) or says why it cannot (a closed scene reflecting all of a channel).
TEST(RadiositySolver, ReflectanceOneConvergesInAnOpenSceneAndIsRefusedInALosslessClosedOne) {
  const auto lossless = [](bool closed) {
    Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
    for (Material& m : scene.materials) m.reflectance = {1, 0.5, 0.5};
    if (!closed)  // drop the room's front-most polygons: an open box
      for (SceneObject& o : scene.objects)
        if (o.polygons.size() > 3) {
          o.polygons.resize(o.polygons.size() - 1);
          o.polygonMaterial.resize(o.polygons.size());
          o.polygonOrigin.resize(o.polygons.size());
        }
    return scene;
  };
  RadiosityOptions options;
  options.tolerance = 1e-2;
  RadiositySolver closed(options);
  try {
    closed.build(lossless(true), 0);
    ADD_FAILURE() << "a closed lossless scene must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot converge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("red"), std::string::npos) << e.what();
  }
  RadiositySolver open(options);
  open.build(lossless(false), 0);
  EXPECT_TRUE(open.stats().converged);
  EXPECT_TRUE(open.irradiance({0.3, 0, 0.3}, {0, 1, 0}).isFinite());
}

}  // namespace
}  // namespace penumbra
