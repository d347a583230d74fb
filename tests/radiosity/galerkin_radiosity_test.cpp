#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <numeric>
#include <random>
#include <tuple>

#include "penumbra/base/parallel_for.h"
#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/cosine_direction.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/path_traced_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "support/boxes.h"
#include "support/closed_form_factors.h"
#include "support/scene_builder.h"

namespace penumbra {
namespace {

std::string scenePath(const std::string& relative) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative;
}

ElementShape shapeOf(const std::vector<Vec3>& loop) {
  ElementShape s;
  for (size_t i = 0; i < loop.size(); ++i) s.vertices[i] = loop[i];
  s.vertexCount = std::uint8_t(loop.size());
  s.normal = normalize(cross(loop[1] - loop[0], loop[2] - loop[0]));
  return s;
}

// The area mean of f over the element by the midpoint rule on its quadtree cells `levels` down:
// independent of the basis's own exact rule.
double midpointMean(const ElementShape& shape, const std::function<double(const Vec3&)>& f,
                    int levels) {
  std::vector<ElementShape> cells{shape};
  for (int level = 0; level < levels; ++level) {
    std::vector<ElementShape> next;
    for (const ElementShape& c : cells)
      for (const auto& loop : c.childVertices()) {
        ElementShape child = c;
        child.vertices = loop;
        next.push_back(child);
      }
    cells = std::move(next);
  }
  double sum = 0, area = 0;
  for (const ElementShape& c : cells) {
    const double a = elementArea(c.vertices, c.vertexCount);
    sum += a * f(c.centroid());
    area += a;
  }
  return sum / area;
}
// Richardson's extrapolation of the midpoint rule at 256 and 1,024 cells: exact for quadratics
// up to rounding (the rule's error is h² times a constant for them).
double areaMean(const ElementShape& shape, const std::function<double(const Vec3&)>& f) {
  return (4 * midpointMean(shape, f, 5) - midpointMean(shape, f, 4)) / 3;
}

GalerkinOptions atTolerance(double tolerance) {
  GalerkinOptions options;
  options.tolerance = tolerance;
  return options;
}

// A bundled scene at frame 0, solved at `tolerance`, with the exact reference of its direct light.
struct SolvedScene {
  SolvedScene(const std::string& relative, double tolerance)
      : scene(loadScene(scenePath(relative))),
        live(scene, 0),
        solver(atTolerance(tolerance)),
        exact(live.posed(), &live.grid()) {
    solver.build(live);
  }
  const Scene scene;
  const DynamicScene live;
  GalerkinRadiosity solver;
  const ExactReference exact;
};

struct Spread {
  double median = 0, p95 = 0;
};
Spread spreadOf(std::vector<double> errors) {
  std::sort(errors.begin(), errors.end());
  return {errors[errors.size() / 2], errors[errors.size() * 95 / 100]};
}

const std::vector<std::vector<Vec3>> kShapes{
    {{0, 0, 0}, {2, 0.3, 0}, {0.4, 1.5, 0}},                           // a triangle
    {{0, 0, 1}, {1.5, 0, 1.15}, {1.8, 1.1, 1.4}, {-0.2, 0.9, 1.16}}};  // a skewed quadrilateral
                                                                       // in z = 1 + x / 10 + y / 5

TEST(LinearBasis, IsOrthonormalOverTheElement) {
  for (const auto& loop : kShapes) {
    const ElementShape shape = shapeOf(loop);
    const LinearBasis basis(shape);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double product =
            areaMean(shape, [&](const Vec3& x) { return basis.at(x)[i] * basis.at(x)[j]; });
        // The extrapolated midpoint rule leaves 3e-8 on the quadrilateral (its cells are not
        // parallelograms, so the rule's error is not exactly h² times a constant).
        EXPECT_NEAR(product, i == j ? 1.0 : 0.0, 1e-7) << i << " " << j;
      }
  }
}

// Pushing a parent's linear function to its children is exact (it is linear on each child), and
// pulling the children's functions back (the projection) returns it unchanged.
TEST(LinearBasis, TransfersBetweenParentAndChildrenAreExact) {
  for (const auto& loop : kShapes) {
    const ElementShape parent = shapeOf(loop);
    const LinearBasis parentBasis(parent);
    const LinearRgb f{Rgb{1.0, 2.0, 3.0}, Rgb{-0.5, 0.25, 0.0}, Rgb{0.75, -1.0, 0.5}};
    LinearRgb pulled{};
    SplitMix rng(3);
    const double parentArea = elementArea(parent.vertices, parent.vertexCount);
    for (const auto& childLoop : parent.childVertices()) {
      ElementShape child = parent;
      child.vertices = childLoop;
      const LinearBasis childBasis(child);
      const BasisTransfer t = basisTransfer(parentBasis, childBasis, child);
      LinearRgb restricted{};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) restricted[a] += f[b] * t[b][a];
      for (int k = 0; k < 20; ++k) {
        const Vec3 x = child.samplePoint(rng.uniform(), rng.uniform());
        const Rgb expected = parentBasis.evaluate(f, x), got = childBasis.evaluate(restricted, x);
        EXPECT_NEAR(got.r, expected.r, 1e-12);
        EXPECT_NEAR(got.g, expected.g, 1e-12);
        EXPECT_NEAR(got.b, expected.b, 1e-12);
      }
      const double share = elementArea(child.vertices, child.vertexCount) / parentArea;
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) pulled[b] += restricted[a] * (share * t[b][a]);
    }
    for (int b = 0; b < 3; ++b) {
      EXPECT_NEAR(pulled[b].r, f[b].r, 1e-12);
      EXPECT_NEAR(pulled[b].g, f[b].g, 1e-12);
      EXPECT_NEAR(pulled[b].b, f[b].b, 1e-12);
    }
  }
}

// A black receiver under a lamp of exitance 1: its area-mean irradiance is the form factor.
TEST(GalerkinRadiosity, ParallelSquaresMatchClosedForm) {
  test::SceneBuilder builder;
  builder.addMaterial("black", Rgb::gray(0)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(1));
  builder.addPolygon("black", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  builder.addPolygon("lamp", {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}});
  const DynamicScene live(builder.pose());
  GalerkinOptions options;
  options.tolerance = 1e-3;
  GalerkinRadiosity solver(options);
  solver.build(live);
  double sum = 0, area = 0;
  for (const auto& e : solver.elements())
    if (e.isLeaf() && e.polygon == 0) {
      sum += e.node.irradianceDirect[0].average() * e.area;
      area += e.area;
    }
  const double expected = test::parallelRectangles(1, 1, 1);
  // Measured: 2e-16 relative (each receiver point's row is the exact point form factor; the
  // Gauss points integrate it over the receiver).
  EXPECT_NEAR(sum / area, expected, 1e-3 * expected);
}

// The share of polygon `source`'s Lambertian emission whose first hit is the front of each
// polygon, by cosine-distributed rays from uniform points of it: an independent count (its own
// ray-triangle tests, none of the solver's or the ray caster's code; the directions are
// geometry/cosine_direction.h's, which no visibility reads).
std::vector<double> emissionShares(const PosedScene& scene, PolygonId source, int rays) {
  const WorldPolygon& from = scene.polygons[size_t(source)];
  std::vector<double> areas;  // the fan's triangles
  for (size_t i = 1; i + 1 < from.vertices.size(); ++i)
    areas.push_back(length(
        cross(from.vertices[i] - from.vertices[0], from.vertices[i + 1] - from.vertices[0])));
  const double totalArea = std::accumulate(areas.begin(), areas.end(), 0.0);
  std::vector<double> shares(scene.polygons.size());
  SplitMix random(7);
  for (int ray = 0; ray < rays; ++ray) {
    double pick = random.uniform() * totalArea;
    size_t t = 0;
    while (t + 1 < areas.size() && pick > areas[t]) pick -= areas[t++];
    double u = random.uniform(), v = random.uniform();
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 o = from.vertices[0] + (from.vertices[t + 1] - from.vertices[0]) * u +
                   (from.vertices[t + 2] - from.vertices[0]) * v;
    const double radius = random.uniform(), turn = random.uniform();
    const Vec3 d = cosineDirection(from.plane.normal, radius, turn);
    double nearest = std::numeric_limits<double>::infinity();
    int hit = -1;
    for (const WorldPolygon& p : scene.polygons) {
      if (p.id == source) continue;
      for (size_t i = 1; i + 1 < p.vertices.size(); ++i) {
        const Vec3 e1 = p.vertices[i] - p.vertices[0], e2 = p.vertices[i + 1] - p.vertices[0];
        const Vec3 pv = cross(d, e2);
        const double det = dot(pv, e1);
        if (std::abs(det) < 1e-15) continue;
        const Vec3 tv = o - p.vertices[0];
        const double a = dot(tv, pv) / det;
        const Vec3 qv = cross(tv, e1);
        const double b = dot(d, qv) / det, along = dot(e2, qv) / det;
        if (a < 0 || b < 0 || a + b > 1 || along <= 1e-12 || along >= nearest) continue;
        nearest = along;
        hit = dot(d, p.plane.normal) < 0 ? p.id : -1;
      }
    }
    if (hit >= 0) shares[size_t(hit)] += 1.0 / rays;
  }
  return shares;
}

// The scene made black and still with polygon `emitter` alone emitting M = 1: what each polygon
// receives of one polygon's light. Still, because a moving object is a cluster subtree of its own
// (the Cornell box's moving block would not share the floor's cluster).
Scene withOneEmitter(Scene scene, PolygonId emitter) {
  scene.materials.push_back({"black", Rgb::gray(0), Rgb::gray(0)});
  scene.materials.push_back({"lamp", Rgb::gray(0), Rgb::gray(1)});
  const int black = int(scene.materials.size()) - 2, lamp = black + 1;
  PolygonId id = 0;
  for (SceneObject& o : scene.objects) {
    for (int& m : o.polygonMaterial) m = id++ == emitter ? lamp : black;
    if (o.isDynamic()) {
      o.transform = o.motion.poseAt(0);
      o.motion = {};
    }
  }
  return scene;
}

// Each polygon's share of what polygon `emitter` (M = 1) emits over its whole area, received over
// its leaves (solved at `tolerance`). Over its whole area, as the ray count: a covered part's light
// reaches nothing.
std::vector<double> receivedShares(const DynamicScene& live, PolygonId emitter, double tolerance) {
  GalerkinOptions options;
  options.tolerance = tolerance;
  GalerkinRadiosity solver(options);
  solver.build(live);
  std::vector<double> received(live.posed().polygons.size());
  for (const auto& e : solver.elements())
    if (e.isLeaf()) received[size_t(e.polygon)] += e.node.irradianceDirect[0].average() * e.area;
  const double emitted = live.posed().polygons[size_t(emitter)].area;
  for (double& r : received) r /= emitted;
  return received;
}

// The index of the scene's object named `name` (-1: none).
int objectNamed(const Scene& scene, const std::string& name) {
  for (size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].name == name) return int(o);
  return -1;
}

// An object's share: the sum of its polygons' shares.
double objectShare(const PosedScene& scene, const std::vector<double>& shares, int object) {
  double sum = 0;
  for (const WorldPolygon& p : scene.polygons)
    if (p.objectIndex == object) sum += shares[size_t(p.id)];
  return sum;
}

// The Cornell box with one polygon `side` emitting: each polygon's share of its light, the
// solver's against an independent ray count.
void expectSharesOfOneSidesLightAsCounted(PolygonId side, double tolerance) {
  const DynamicScene live(
      withOneEmitter(loadScene(scenePath("cornell-box/cornell-box.json")), side), 0);
  const std::vector<double> received = receivedShares(live, side, tolerance);
  const std::vector<double> counted = emissionShares(live.posed(), side, 200'000);
  for (size_t p = 0; p < received.size(); ++p) {
    if (received[p] > 0 || counted[p] > 0)
      std::printf("polygon %2zu: %.4f of polygon %d's light, counted %.4f\n", p, received[p], side,
                  counted[p]);
    EXPECT_NEAR(received[p], counted[p], 0.005) << "polygon " << p;
  }
}

// The short block's side facing the green wall stands on the floor facing away from the floor's
// middle. The floor's cluster points and Gauss points all lie behind the side, so every point pair
// of their pair read zero with zero spread, and no pass ever split it: the floor received nothing
// of the 21% of the side's light that falls on it. Such "blind" pairs now get a spread
// (GalerkinRadiosity::estimate). Measured: the floor 0.2075 against 0.2093 counted (0 before);
// every other polygon within 0.002 of its count (a count's standard error: at most 0.0011).
TEST(GalerkinRadiosity, ABlockSideFacingAwayFromTheFloorsMiddleLightsTheFloor) {
  expectSharesOfOneSidesLightAsCounted(13, 1e-3);
}

// The short block's side facing the red wall sends 2.4% of its light past the tall block to the
// back wall, and 1% to the tall block's side facing it. The pair of the whole back wall and the
// side found all 16 point pairs hidden, as did the pair of the tall block's cluster and the side:
// estimates zero, spreads zero, partly hidden terms (the smaller of hidden and visible) zero, so
// neither was ever split and both received nothing. A wholly hidden pair now counts its hidden
// transfer in the oracle (GalerkinOptions::wholeHiddenWeight). Measured: the back wall 0.0236
// against 0.0226 counted, the tall block's side 0.0083 against 0.0096 (both 0 before).
TEST(GalerkinRadiosity, LightPassingBesideAnOccluderReachesTheWallBehindIt) {
  expectSharesOfOneSidesLightAsCounted(15, 1e-3);
}

// The furnished room, black and still, with its ceiling emitting M = 1: a cluster hands the light
// arriving on a lobe to its surfaces that face the lobe, and handed it to the parts of them a
// polygon in contact covers as well (the sofa's seat under its cushion took 0.0113 of the
// ceiling's light against 0.0004 counted, the sofa 0.032 against 0.019). A root element now takes
// and gives on its lobes only its exposed share (GElement::exposedShare).
// Measured: the sofa 0.0204 against 0.0186 counted, its seat 0.0000 (before: 0.0319 and 0.0113).
TEST(GalerkinRadiosity, CoveredSurfacesTakeNoLightFromTheirCluster) {
  const PolygonId ceiling = 1, seat = 458;  // the sofa's seat, under its cushion
  const Scene scene =
      withOneEmitter(loadScene(scenePath("chair-room/furnished-room.json")), ceiling);
  const int sofa = objectNamed(scene, "sofa");
  ASSERT_GE(sofa, 0);
  const DynamicScene live(scene, 0);
  ASSERT_LT(live.posed().polygons[size_t(ceiling)].plane.normal.y, -0.99);
  ASSERT_EQ(live.posed().polygons[size_t(seat)].objectIndex, sofa);
  const std::vector<double> received = receivedShares(live, ceiling, 1e-3);
  const std::vector<double> counted = emissionShares(live.posed(), ceiling, 100'000);
  const double sofaReceived = objectShare(live.posed(), received, sofa);
  const double sofaCounted = objectShare(live.posed(), counted, sofa);
  std::printf("sofa %.4f of the ceiling's light, counted %.4f; its seat %.4f, counted %.4f\n",
              sofaReceived, sofaCounted, received[size_t(seat)], counted[size_t(seat)]);
  EXPECT_NEAR(sofaReceived, sofaCounted, 0.005);
  EXPECT_LT(received[size_t(seat)], 0.002);
}

// The chair room with its floor emitting: the moving chair (a cluster of its own) took its light
// from the room's static cluster and the floor's elements along one direction, up from the floor
// towards the room's middle or straight down, and its legs' sides and its seat's underside, lit
// from all around below, faced away from it: 0.0133 of the floor's light against 0.0191 counted.
// Where the directions between a pair's points stray from that one, refinement now splits it
// (GalerkinOptions::directionWeight). Measured: 0.0178.
TEST(GalerkinRadiosity, AChairStandingOnTheFloorTakesItsLightFromAllAround) {
  const PolygonId floor = 0;
  const Scene scene = withOneEmitter(loadScene(scenePath("chair-room/chair-room.json")), floor);
  const int chair = objectNamed(scene, "chair-moving");
  ASSERT_GE(chair, 0);
  const DynamicScene live(scene, 0);
  ASSERT_GT(live.posed().polygons[size_t(floor)].plane.normal.y, 0.99);
  const std::vector<double> received = receivedShares(live, floor, 1e-3);
  const std::vector<double> counted = emissionShares(live.posed(), floor, 200'000);
  const double chairReceived = objectShare(live.posed(), received, chair);
  const double chairCounted = objectShare(live.posed(), counted, chair);
  std::printf("the chair: %.4f of the floor's light, counted %.4f\n", chairReceived, chairCounted);
  EXPECT_NEAR(chairReceived, chairCounted, 0.0025);
}

// A closed room whose floor alone reflects (1/2), lit by its lamp, with a block turned 30 degrees
// standing on the floor: the floor elements along the block's outline are partly covered, and
// their links read their radiosity at their exposed cubature points only. Their irradiance,
// nothing under the block, already holds the cover once; sent from those points as the linear
// function through it reads there, it lost the cover a second time (one point of four open: a
// quarter of the element's reflected light). The light a move through the floor's reflection
// loses, beyond what the lamp's direct light alone leaves unbalanced, as a share of what the
// floor reflects. Measured: 1.5% at 3e-3 (4.7% before sentReflection), 0.8% at 1e-3 (2.1%).
TEST(GalerkinRadiosity, APartlyCoveredFloorSendsAllItReflects) {
  Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) +
                          "/tests/radiosity/data/block-turned-on-the-floor.json");
  const auto balance = [&](bool floorReflects, double* reflected) {
    Scene s = scene;
    s.materials.push_back({"floor", Rgb::gray(0.5), Rgb::gray(0)});
    s.materials.push_back({"black", Rgb::gray(0), Rgb::gray(0)});
    const int floorMaterial = int(s.materials.size()) - 2, black = floorMaterial + 1;
    PolygonId id = 0;
    for (SceneObject& o : s.objects)
      for (int& m : o.polygonMaterial) {
        if (s.materials[size_t(m)].emission.maxComponent() == 0)
          m = id == 0 && floorReflects ? floorMaterial : black;
        ++id;
      }
    const DynamicScene live(s, 0);
    GalerkinOptions options;
    options.tolerance = 3e-3;
    GalerkinRadiosity solver(options);
    solver.build(live);
    double sent = 0;
    for (const auto& e : solver.elements())
      if (e.isLeaf()) sent += (e.node.radiosity[0] - e.node.emission).average() * e.area;
    const double emitted = solver.emittedPower().average();
    if (reflected) *reflected = sent / emitted;
    return solver.absorbedPower().average() / emitted;
  };
  double reflected = 0;
  const double lampAlone = balance(false, nullptr), withFloor = balance(true, &reflected);
  const double lost = (lampAlone - withFloor) / reflected;
  std::printf(
      "absorbed/emitted %.5f with the lamp alone, %.5f with the floor reflecting %.4f of "
      "the light: %.2f%% of it lost\n",
      lampAlone, withFloor, reflected, 100 * lost);
  EXPECT_GT(reflected, 0.05);
  EXPECT_LT(std::abs(lost), 0.025);
}

// Every polygon of the chair room's walls emits M = 1 with reflectance 1/2: B = 2 everywhere.
TEST(GalerkinRadiosity, FurnaceInEmptyRoomConservesEnergy) {
  Scene scene = loadScene(scenePath("chair-room/chair-room.json"));
  scene.objects.resize(2);  // room-floor, room-walls
  for (Material& m : scene.materials) {
    m.emission = Rgb::gray(1);
    m.reflectance = Rgb::gray(0.5);
  }
  const DynamicScene live(scene, 0);
  for (double tolerance : {1e-2, 1e-3}) {
    GalerkinOptions options;
    options.tolerance = tolerance;
    GalerkinRadiosity solver(options);
    solver.build(live);
    double meanError = 0, area = 0;
    for (const auto& e : solver.elements())
      if (e.isLeaf()) {
        const double E = (e.node.irradianceDirect[0] + e.node.irradianceIndirect[0]).average();
        meanError += std::abs(E - 2) / 2 * e.area;
        area += e.area;
      }
    const double balance = solver.absorbedPower().average() / solver.emittedPower().average();
    std::printf("tolerance %.0e: %lld links, leaf mean error %.4f, absorbed/emitted %.5f\n",
                tolerance, solver.stats().activeLinks, meanError / area, balance);
    // Measured: absorbed/emitted 0.9970 / 0.9989, leaf mean error 2.6% / 1.6%: what is lost is
    // the Gauss points' integral over a receiver of the point form factor near the corners
    // (logarithmic there).
    EXPECT_NEAR(balance, 1, tolerance == 1e-2 ? 0.005 : 0.002);
    EXPECT_LT(meanError / area, tolerance == 1e-2 ? 0.04 : 0.025);
  }
}

// A furnace (every polygon emits M = 1 and reflects 1/2, the scene closed: E = 2 at every exposed
// point) of a 2 m room with `extra` polygons in it. Returns the largest relative difference from 2
// of the mean irradiance over a polygon's exposed leaves, among the polygons `probed`,
// absorbed/emitted, and the irradiance sampled at `point` (facing up).
std::tuple<double, double, double> furnaceWith(
    const std::function<void(test::SceneBuilder&)>& extra, const std::vector<PolygonId>& probed,
    double tolerance, const Vec3& point) {
  test::SceneBuilder builder;
  builder.addMaterial("furnace", Rgb::gray(0.5), Rgb::gray(1));
  test::addRoom(builder, "furnace", {0, 0, 0}, {2, 2, 2});
  extra(builder);
  const DynamicScene live(builder.scene(), 0);
  GalerkinOptions options;
  options.tolerance = tolerance;
  GalerkinRadiosity solver(options);
  solver.build(live);
  double worst = 0;
  for (PolygonId p : probed) {
    double sum = 0, area = 0;
    for (const auto& e : solver.elements())
      if (e.isLeaf() && e.polygon == p && e.cover != GalerkinRadiosity::GElement::kCovered) {
        sum += (e.node.irradianceDirect[0] + e.node.irradianceIndirect[0]).average() * e.area;
        area += e.area;
      }
    worst = std::max(worst, area > 0 ? std::abs(sum / area - 2) / 2 : 1.0);  // 1: all covered
  }
  return {worst, solver.absorbedPower().average() / solver.emittedPower().average(),
          solver.irradiance(point, {0, 1, 0}).average()};
}

// A box standing on the floor with its faces turned inwards (a model whose winding came out
// reversed) is a closed cavity whose bottom lies on the floor facing the same way. Both took the
// light arriving there and both sent it on: inside the cavity more light came back than left,
// the radiosity grew without bound (with reflectance 0.9 under a lamp, 1e5 times the room's at
// 1e-2) and refinement went past its budget of a million links at 1e-3. The later polygon now lies
// on top: the floor under the box's bottom neither receives nor sends (coveringPolygons). What
// still reaches the cavity comes through the clusters' lobes, which do not see that the box's
// faces hide its inside (measured: its brightest face 0.18 where the empty room's floor has 0.97).
TEST(GalerkinRadiosity, AnInsideOutBoxOnTheFloorStaysBounded) {
  const auto solve = [](bool withBox) {
    test::SceneBuilder b;
    b.addMaterial("wall", Rgb::gray(0.9)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(10));
    test::addRoom(b, "wall", {0, 0, 0}, {2, 2, 2});
    b.addPolygon(
        "lamp",
        {{0.625, 1.75, 0.375}, {1.125, 1.75, 0.375}, {1.125, 1.75, 0.875}, {0.625, 1.75, 0.875}},
        "lamp");
    if (withBox)
      for (Polygon3 f : test::boxFaces({1.5, 0, 1.5}, {1.875, 0.625, 1.875})) {
        std::reverse(f.begin(), f.end());
        b.addPolygon("wall", f, "inside-out box");
      }
    auto solver = std::make_unique<GalerkinRadiosity>();
    solver->build(DynamicScene(b.scene(), 0));
    return solver;
  };
  const auto empty = solve(false), boxed = solve(true);
  const auto meanIrradiance = [](const GalerkinRadiosity& s, PolygonId polygon) {
    double sum = 0, area = 0;
    for (const auto& e : s.elements())
      if (e.isLeaf() && e.polygon == polygon) {
        sum += (e.node.irradianceDirect[0] + e.node.irradianceIndirect[0]).average() * e.area;
        area += e.area;
      }
    return sum / area;
  };
  const double floor = meanIrradiance(*empty, 2);
  double cavity = 0;
  for (PolygonId p = 7; p < 13; ++p) cavity = std::max(cavity, meanIrradiance(*boxed, p));
  std::printf(
      "links %lld with the box, %lld without; the cavity's brightest face %.4f, the empty "
      "room's floor %.4f\n",
      boxed->stats().activeLinks, empty->stats().activeLinks, cavity, floor);
  EXPECT_LT(boxed->stats().activeLinks, 2 * empty->stats().activeLinks);
  EXPECT_LT(cavity, 0.25 * floor);
}

// A rug lying on the floor, both facing up, listed after it: where they overlap only the rug
// receives and sends (before, both did), and a point there is on the rug (the locator may find
// the floor).
TEST(GalerkinRadiosity, PolygonsLyingOnOneAnotherFacingTheSameWayAreOneSurface) {
  const auto [worst, balance, onTheRug] = furnaceWith(
      [](test::SceneBuilder& b) {
        b.addPolygon("furnace", {{0.5, 0, 0.5}, {0.5, 0, 1.5}, {1.5, 0, 1.5}, {1.5, 0, 0.5}},
                     "rug");
      },
      {0, 1, 2, 3, 4, 5, 6}, 1e-3, {1.1, 0, 0.9});
  std::printf("rug: worst polygon mean %.4f off, absorbed/emitted %.5f, E on the rug %.4f\n", worst,
              balance, onTheRug);
  EXPECT_NEAR(onTheRug, 2, 0.04);
  // Measured: 0.0006 and 0.9994 (before: 0.097 and 1.083).
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(balance, 1, 0.002);
}

// A card given as two polygons back to back (one object): the two sides of a sheet, each lit.
// They used to count as polygons in face-to-face contact, each covering the other: both sides
// received nothing (and a probe there read 0 against the path tracer's 0.45 in a generated room).
TEST(GalerkinRadiosity, BothSidesOfATwoSidedCardAreLit) {
  const auto [worst, balance, onTheFloor] = furnaceWith(
      [](test::SceneBuilder& b) {
        const Polygon3 card{{1, 0.5, 0.5}, {1, 1.5, 0.5}, {1, 1.5, 1.5}, {1, 0.5, 1.5}};
        b.addPolygon("furnace", card, "card");
        b.addPolygon("furnace", {card[3], card[2], card[1], card[0]}, "card");
      },
      {6, 7}, 3e-3, {0.5, 0, 0.5});
  std::printf("card: worst side mean %.4f off, absorbed/emitted %.5f\n", worst, balance);
  EXPECT_LT(worst, 0.03);
  EXPECT_NEAR(balance, 1, 0.005);
  EXPECT_NEAR(onTheFloor, 2, 0.04);
}

// A lamp set into the ceiling's plane lies on top of the ceiling whichever comes first in the
// scene: it emits all it emits 1 mm under the ceiling.
TEST(GalerkinRadiosity, ALampInTheCeilingsPlaneShowsWhicheverComesFirst) {
  const auto emitted = [](double below, bool lampFirst) {
    test::SceneBuilder b;
    b.addMaterial("wall", Rgb::gray(0.5)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(10));
    const Polygon3 lamp{
        {0.5, 2 - below, 0.5}, {1.5, 2 - below, 0.5}, {1.5, 2 - below, 1.5}, {0.5, 2 - below, 1.5}};
    if (lampFirst) b.addPolygon("lamp", lamp, "lamp");
    test::addRoom(b, "wall", {0, 0, 0}, {2, 2, 2});
    if (!lampFirst) b.addPolygon("lamp", lamp, "lamp");
    const DynamicScene live(b.scene(), 0);
    GalerkinOptions options;
    options.tolerance = 1e-2;
    GalerkinRadiosity solver(options);
    solver.build(live);
    return solver.emittedPower().average();
  };
  const double below = emitted(1e-3, true);
  EXPECT_GT(below, 0);
  EXPECT_NEAR(emitted(0, true), below, 1e-12 * below);
  EXPECT_NEAR(emitted(0, false), below, 1e-12 * below);
}

// The furnace with the chair room's furniture (its one-sided lamp left out: E = 2 exactly at
// every point), probed in its narrow gaps: a sideboard and a sofa stand 1 cm from the walls.
// Across such a gap the kernel is a step the Gauss points of a link can all miss; the receivers'
// corners and the spot across from a small source are sampled too (GalerkinRadiosity::estimate).
// Measured at 1e-3: the sideboard's back 1.81 (0.07 before those samples), the wall behind it
// 2.01. Not yet right, printed: behind the sofa (its back 1.48, the wall 1.24), where the wall's
// links to the sofa stay at cluster level longer (issue 19).
TEST(GalerkinRadiosity, FurnaceReachesIntoNarrowGaps) {
  Scene scene = loadScene(scenePath("chair-room/chair-room.json"));
  std::erase_if(scene.objects, [&](const SceneObject& o) {
    return std::any_of(o.polygonMaterial.begin(), o.polygonMaterial.end(),
                       [&](int m) { return scene.materials[m].isEmitter(); });
  });
  for (Material& m : scene.materials) {
    m.emission = Rgb::gray(1);
    m.reflectance = Rgb::gray(0.5);
  }
  const DynamicScene live(scene, 0);
  GalerkinOptions options;
  options.tolerance = 1e-3;
  GalerkinRadiosity solver(options);
  solver.build(live);
  struct Probe {
    const char* where;
    Vec3 point, normal;
  };
  const Probe probes[] = {
      {"sideboard's back", {4.49, 0.375, 1.18}, {1, 0, 0}},
      {"wall behind the sideboard", {4.5, 0.375, 1.18}, {-1, 0, 0}},
      {"sofa's back", {0.01, 0.4, 2.6}, {-1, 0, 0}},
      {"wall behind the sofa", {0, 0.4, 2.6}, {1, 0, 0}},
      {"wall behind the open bookshelf", {3.5, 0.5, 0}, {0, 0, 1}},
  };
  for (const Probe& probe : probes) {
    const auto sample = solver.sample(probe.point, probe.normal);
    ASSERT_TRUE(sample) << probe.where;
    std::printf("%s: %.3f\n", probe.where, sample->total().average());
  }
  const auto back = solver.sample(probes[0].point, probes[0].normal);
  EXPECT_NEAR(back->total().average(), 2, 0.2);
}

// The open floor beside the chair room's sideboard, whose footprint covers every cubature point
// of the floor elements along it but not all of them: those elements read no light at all and,
// their links' spread and mean being zero too, were never split (session 20: 0.09-0.16 total
// irradiance where the exact direct part alone is 0.66-0.84). A partly covered end's spread now
// takes what the cover took away, and refinement follows the contact's outline.
TEST(GalerkinRadiosity, FloorBesideAContactIsLit) {
  const SolvedScene room("chair-room/chair-room.json", 1e-3);
  const GalerkinRadiosity& solver = room.solver;
  const ExactReference& exact = room.exact;
  const Vec3 up{0, 1, 0};
  double direct = 0, reference = 0;
  for (const double x : {3.95, 4.0, 4.05, 4.1, 4.2, 4.3}) {
    const Vec3 p{x, 0, 1.44};
    const auto s = solver.sample(p, up);
    ASSERT_TRUE(s);
    const double here = exact.irradiance(p, up, PolygonId(0)).average();
    std::printf("floor at x = %.2f: direct %.3f, exact %.3f\n", x, s->direct.average(), here);
    EXPECT_GT(here, 0.5);  // open floor, in the lamp's light
    // A leaf's linear function across the footprint's edge is off by up to 40% at a point
    // (measured: 1.028 / 0.785 at 3.95, 0.400 / 0.665 at 4.2; issue 19's mesh that follows
    // contacts), but no point reads dark any more, and the mean is right (0.723 / 0.713).
    EXPECT_NEAR(s->direct.average(), here, 0.5 * here);
    direct += s->direct.average();
    reference += here;
  }
  EXPECT_NEAR(direct, reference, 0.1 * reference);
}

// The direct part against the exact reference (the light clipped at each point), at random
// receiver points of the Cornell box.
TEST(GalerkinRadiosity, DirectLightAgreesWithTheExactReference) {
  const SolvedScene box("cornell-box/cornell-box.json", 1e-3);
  const DynamicScene& live = box.live;
  const GalerkinRadiosity& solver = box.solver;
  const ExactReference& exact = box.exact;
  std::vector<double> errors;
  double mean = 0;
  const auto points = sampleReceiverPoints(live.posed(), 300, 11);
  for (const ReceiverPoint& p : points) mean += exact.irradiance(p.p, p.n, p.receiver).average();
  mean /= double(points.size());
  for (const ReceiverPoint& p : points) {
    const auto s = solver.sample(p.p, p.n);
    ASSERT_TRUE(s);
    errors.push_back(
        std::abs(s->direct.average() - exact.irradiance(p.p, p.n, p.receiver).average()) / mean);
  }
  const auto [median, p95] = spreadOf(errors);
  std::printf("direct part, error relative to the mean: median %.4f, p95 %.4f\n", median, p95);
  // Measured: median 0.0018, p95 0.074 of the mean (the p95 is the shadow boundaries, where a
  // linear function per leaf cannot follow the penumbra).
  EXPECT_LT(median, 0.005);
  EXPECT_LT(p95, 0.12);
}

// The same scene solved twice gives the same solution, bit for bit.
TEST(GalerkinRadiosity, IsDeterministic) {
  const Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
  const DynamicScene live(scene, 0);
  GalerkinRadiosity a, b;
  a.build(live);
  b.build(live);
  ASSERT_EQ(a.elements().size(), b.elements().size());
  ASSERT_EQ(a.links().size(), b.links().size());
  for (size_t i = 0; i < a.links().size(); ++i) EXPECT_EQ(a.links()[i].k, b.links()[i].k);
  for (size_t i = 0; i < a.elements().size(); ++i)
    EXPECT_EQ(a.elements()[i].node.radiosity[0], b.elements()[i].node.radiosity[0]);
}

// A surface facing an axis sends B A cos θ through the lobes exactly; a tilted one is shared
// between the axes its normal leans to, and over the sphere the lobes send what it emits, π B A
// (a cosine-weighted sum over directions, here by a fine midpoint rule in θ and φ).
TEST(AxisLobes, SendWhatTheSurfaceEmits) {
  const auto sentOverTheSphere = [](const AxisLobes& lobes) {
    const int n = 400;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 2 * n; ++j) {
        const double theta = (i + 0.5) * std::numbers::pi / n;
        const double phi = (j + 0.5) * std::numbers::pi / n;
        const Vec3 w{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                     std::cos(theta)};
        const double solidAngle = std::sin(theta) * (std::numbers::pi / n) * (std::numbers::pi / n);
        sum += exitanceToward(lobes, w).r * solidAngle;
      }
    return sum;
  };
  for (const Vec3& normal : {Vec3{0, 0, 1}, normalize(Vec3{1, -2, 0.5}), Vec3{-1, 0, 0}}) {
    AxisLobes lobes{};
    const std::array<double, 6> shares = exitanceShares(normal);
    const double area = 0.7;
    for (int f = 0; f < 6; ++f) lobes[f] = Rgb::gray(2.0 * area * shares[f]);  // B = 2
    EXPECT_NEAR(sentOverTheSphere(lobes), std::numbers::pi * 2.0 * area, 1e-4);
    const bool axisAligned =
        std::abs(std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z) - 1) < 1e-12;
    if (axisAligned) {
      const Vec3 w = normalize(normal + Vec3{0.3, 0.2, 0.1});
      EXPECT_NEAR(exitanceToward(lobes, w).r, 2.0 * area * dot(w, normal), 1e-12);
    }
  }
}

// Light arriving along u reaches a surface facing u whole and a surface facing an axis by
// |u_k|: exact for surfaces that face an axis, and for any surface facing the light.
TEST(AxisLobes, ReceiveAsTheSurfacesFace) {
  const Vec3 u = normalize(Vec3{0.2, -0.5, 0.8});
  AxisLobes lobes{};
  addArriving(lobes, Rgb::gray(3), u);
  EXPECT_NEAR(irradianceOn(lobes, u).r, 3, 1e-12);
  EXPECT_NEAR(irradianceOn(lobes, Vec3{0, 0, 1}).r, 3 * u.z, 1e-12);
  EXPECT_NEAR(irradianceOn(lobes, Vec3{0, -1, 0}).r, 3 * -u.y, 1e-12);
  EXPECT_NEAR(irradianceOn(lobes, Vec3{-1, 0, 0}).r, 0, 1e-12);
}

// One direction's lobe weights send and receive as the direction does; a link's weights, the
// directions of its point pairs weighed by what each carries, give a surface the light that
// comes from its side: a source on both sides of a cluster (a floor around a chair, seen from
// inside its box) lights the cluster's sides, where the one direction between the centres
// (straight down) gave them nothing.
TEST(AxisLobes, WeightsActAsTheirDirections) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < 100; ++i) {
    const Vec3 u = normalize(Vec3{unit(rng), unit(rng), unit(rng)});
    AxisLobes lobes{};
    for (Rgb& lobe : lobes) lobe = Rgb{unit(rng) + 1, unit(rng) + 1, unit(rng) + 1};
    const LobeWeights weights = lobeWeightsOf(u);
    EXPECT_EQ(opposite(weights), lobeWeightsOf(u * -1.0));
    EXPECT_NEAR(exitanceToward(lobes, weights).g, exitanceToward(lobes, u).g, 1e-6);
    AxisLobes byWeights{}, byDirection{};
    addArriving(byWeights, Rgb::gray(2), weights);
    addArriving(byDirection, Rgb::gray(2), u);
    for (int f = 0; f < 6; ++f) EXPECT_NEAR(byWeights[f].r, byDirection[f].r, 1e-6);
  }
  // Two halves of a source, down and to either side, carrying alike.
  const Vec3 left = normalize(Vec3{-1, -0.5, 0}), right = normalize(Vec3{1, -0.5, 0});
  LobeWeights spread{};
  for (int f = 0; f < 6; ++f)
    spread[f] = 0.5f * lobeWeightsOf(left)[f] + 0.5f * lobeWeightsOf(right)[f];
  AxisLobes lobes{};
  addArriving(lobes, Rgb::gray(1), spread);
  // Each side faces one half: cos = 2/√5 of half the light.
  EXPECT_NEAR(irradianceOn(lobes, Vec3{1, 0, 0}).r, 0.5 * 2 / std::sqrt(5.0), 1e-6);
  EXPECT_NEAR(irradianceOn(lobes, Vec3{-1, 0, 0}).r, 0.5 * 2 / std::sqrt(5.0), 1e-6);
  EXPECT_NEAR(irradianceOn(lobes, Vec3{0, -1, 0}).r, 1 / std::sqrt(5.0), 1e-6);
  AxisLobes centred{};
  addArriving(centred, Rgb::gray(1), normalize(left + right));
  EXPECT_EQ(irradianceOn(centred, Vec3{1, 0, 0}).r, 0);
}

// Links are estimated in parallel and decided in order: the solution does not depend on the
// number of threads.
TEST(GalerkinRadiosity, IdenticalForAnyNumberOfThreads) {
  const Scene scene = loadScene(scenePath("chair-room/chair-room.json"));
  const DynamicScene live(scene, 0);
  GalerkinOptions one, two;
  one.tolerance = two.tolerance = 3e-3;
  one.threads = 1;
  two.threads = 2;
  GalerkinRadiosity a(one), b(two);
  a.build(live);
  b.build(live);
  ASSERT_EQ(a.links().size(), b.links().size());
  for (size_t i = 0; i < a.links().size(); ++i) {
    EXPECT_EQ(a.links()[i].receiver, b.links()[i].receiver);
    EXPECT_EQ(a.links()[i].source, b.links()[i].source);
    EXPECT_EQ(a.links()[i].k, b.links()[i].k);
  }
  for (const auto& p : sampleReceiverPoints(live.posed(), 50, 5))
    EXPECT_EQ(a.irradiance(p.p, p.n), b.irradiance(p.p, p.n));
}

// The total irradiance against the independent path tracer (sampled direct light, its own shadow
// rays) at the bench's open points of the Cornell box, 16,384 paths each.
// The chair room's sofa stands on the floor face to face (its bottom, x in [0.01, 0.85], z in
// [1.8, 3.4], lies in the floor's plane): no light reaches the floor under it, up to its edge,
// whatever the linear functions of the floor's partly covered leaves say there (they read up to
// 0.4 a centimetre inside the edge); just outside, the floor is lit.
TEST(GalerkinRadiosity, NothingArrivesUnderAPolygonLyingOnTheReceiver) {
  const SolvedScene room("chair-room/chair-room.json", 3e-3);
  const GalerkinRadiosity& solver = room.solver;
  const ExactReference& reference = room.exact;
  const Vec3 up{0, 1, 0};
  for (const Vec3& under : {Vec3{0.4, 0, 2.6}, Vec3{0.84, 0, 2.0}, Vec3{0.8, 0, 3.39},
                            Vec3{0.02, 0, 1.81}, Vec3{0.849, 0, 3.0}}) {
    const auto sample = solver.sample(under, up);
    ASSERT_TRUE(sample.has_value());
    EXPECT_EQ(sample->total().maxComponent(), 0) << under.x << ", " << under.z;
    EXPECT_EQ(reference.irradiance(under, up).maxComponent(), 0) << under.x << ", " << under.z;
  }
  for (const Vec3& beside : {Vec3{0.86, 0, 2.0}, Vec3{0.86, 0, 3.0}, Vec3{0.5, 0, 3.41}}) {
    EXPECT_GT(solver.irradiance(beside, up).maxComponent(), 0.1) << beside.x << ", " << beside.z;
  }
}

TEST(GalerkinRadiosity, TotalAgreesWithThePathTracer) {
  const Scene scene = loadScene(scenePath("cornell-box/cornell-box.json"));
  const DynamicScene live(scene, 0);
  GalerkinOptions options;
  options.tolerance = 3e-3;
  GalerkinRadiosity solver(options);
  solver.build(live);
  const PathTracedReference tracer(live.posed(), live.rays());
  const auto points = sampleReceiverPoints(live.posed(), 150, 7);
  std::vector<double> references(points.size()), errors;
  parallelFor((long long)points.size(), 0, [&](long long i) {
    const ReceiverPoint& p = points[i];
    references[i] = tracer.irradiance(p.p, p.n, p.receiver, 16384, 500 + i).total().average();
  });
  double mean = 0;
  for (double r : references) mean += r / double(references.size());
  for (size_t i = 0; i < points.size(); ++i)
    if (references[i] > 1e-3 * mean)  // open points (not under a block)
      errors.push_back(
          std::abs(solver.irradiance(points[i].p, points[i].n).average() - references[i]) /
          references[i]);
  const auto [median, p95] = spreadOf(errors);
  std::printf("%zu open points: median %.4f, p95 %.4f\n", errors.size(), median, p95);
  // Measured: median 2.7%, p95 13.3% (the bench's 262,144-path reference, whose own noise is
  // 0.3% instead of 1.3% here, gives 2.3% and 12.8% at these points).
  EXPECT_LT(median, 0.04);
  EXPECT_LT(p95, 0.2);
}

}  // namespace
}  // namespace penumbra
