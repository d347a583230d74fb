// Acceptance run of the exact soft-shadow engine: at random receiver points of the bundled scenes,
// of seeded generated rooms, of seeded penumbra-rich scenes (rotated boxes under a large
// light) and of seeded degenerate ones (cards and boxes on a dyadic grid touching the light's
// edges and plane, each other and the floor), and of triangulated copies of all of them, the
// irradiance from the discontinuity mesh (the located face's backprojection) against the per-point
// exact reference (the light polygon clipped by every occluder's projection, no mesh). A point
// differs when the relative difference exceeds 1e-9 (in the umbra, relative to 1e-4 of the
// brightest light's exitance). Half the points are uniform over the receivers' area, half are drawn
// among penumbra points (5-95% of the unoccluded irradiance). Run twice: faces answering from their
// sample's labels alone (the mesh as built), then with face verification (DmOptions::verifyFaces),
// with the count of faces it found unresolved.
//
// Usage: dm_exactness [--points N] [--propagate on|off] [--walked] [--only S] [--verified-only]
// [--show] [--corners]
// (N per scene and copy, default 2000; --propagate sets DmOptions::propagateBackprojections, else
// its default; --walked: the moving scenes only, their engine built at frame 0 and updated through
// every frame, the points compared at the last frame's pose; --only: the scenes whose name
// contains S; --verified-only: only the second run, the engine's default; --show: each differing
// edge midpoint, with its edge, value and the reference's; --corners: also points around every
// contact corner, 24 directions at 1e-9 to 1e-4 of the scene) Also the midpoint of
// every event edge of every mesh (where events meet, and the polylines' chords stand farthest
// from their conics), answered by the mesh or not, and compared likewise. Prints one line per
// scene and copy with its slowest query (and where, past 0.1 s), then the totals; exits 0 (a
// report, not a test).

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/geometry/predicates.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/uniform_grid.h"
#include "penumbra_points.h"
#include "polygon_json.h"

using namespace penumbra;

namespace {

using Clock = std::chrono::steady_clock;

bool showDiffering = false;  // --show: print each differing edge midpoint
bool probeCorners = false;   // --corners: probe around contact corners too

// A 4 x 3 x 4 room (y up) with a 1.2 m square light under the ceiling and four boxes turned about
// random axes at random heights: wide penumbrae that overlap, EEE events everywhere.
std::string rotatedBoxesJson(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::ostringstream json;
  json << R"({"penumbra": 1, "materials": {"white": {"reflectance": [0.6, 0.6, 0.6]},
    "lamp": {"reflectance": [0, 0, 0], "emission": [10, 10, 10]}}, "objects": [
    {"name": "room", "material": "white", "polygons": [
      [[0,0,0],[0,0,4],[4,0,4],[4,0,0]], [[0,3,0],[4,3,0],[4,3,4],[0,3,4]],
      [[0,0,0],[4,0,0],[4,3,0],[0,3,0]], [[0,0,4],[0,3,4],[4,3,4],[4,0,4]],
      [[0,0,0],[0,3,0],[0,3,4],[0,0,4]], [[4,0,0],[4,0,4],[4,3,4],[4,3,0]]]},
    {"name": "lamp", "material": "lamp",
     "polygons": [[[1.4,2.95,1.4],[2.6,2.95,1.4],[2.6,2.95,2.6],[1.4,2.95,2.6]]]})";
  for (int k = 0; k < 4; ++k) {
    const double sx = 0.1 + 0.3 * u(rng), sy = 0.05 + 0.1 * u(rng), sz = 0.1 + 0.3 * u(rng);
    const double ax = u(rng) - 0.5, ay = u(rng) - 0.5, az = u(rng) - 0.5, degrees = 170 * u(rng);
    const double cx = 1 + 2 * u(rng), cy = 0.6 + 0.4 * k, cz = 1 + 2 * u(rng);
    json << R"(, {"name": "box)" << k << R"(", "material": "white", "polygons": [)";
    const double x[2] = {-sx, sx}, y[2] = {-sy, sy}, z[2] = {-sz, sz};
    const auto v = [&](int i, int j, int l) {
      std::ostringstream corner;
      corner << '[' << x[i] << ',' << y[j] << ',' << z[l] << ']';
      return corner.str();
    };
    json << "[" << v(0, 0, 0) << "," << v(1, 0, 0) << "," << v(1, 0, 1) << "," << v(0, 0, 1)
         << "],[" << v(0, 1, 0) << "," << v(0, 1, 1) << "," << v(1, 1, 1) << "," << v(1, 1, 0)
         << "],[" << v(0, 0, 0) << "," << v(0, 1, 0) << "," << v(1, 1, 0) << "," << v(1, 0, 0)
         << "],[" << v(0, 0, 1) << "," << v(1, 0, 1) << "," << v(1, 1, 1) << "," << v(0, 1, 1)
         << "],[" << v(0, 0, 0) << "," << v(0, 0, 1) << "," << v(0, 1, 1) << "," << v(0, 1, 0)
         << "],[" << v(1, 0, 0) << "," << v(1, 1, 0) << "," << v(1, 1, 1) << "," << v(1, 0, 1)
         << "]], \"transform\": {\"translate\": [" << cx << "," << cy << "," << cz
         << "], \"rotate\": {\"axis\": [" << ax << "," << ay << "," << az
         << "], \"degrees\": " << degrees << "}}}";
  }
  json << "]}";
  return json.str();
}

// The degenerate scenes' start: materials, a 4 x 4 floor and a 0.5 m square light facing down at
// y = 2; the occluders follow, each after a comma, and then "]}".
constexpr const char* kSmallLampOverFloor =
    R"({"penumbra": 1, "materials": {"white": {"reflectance": [0.7, 0.7, 0.7]},
    "lamp": {"reflectance": [0, 0, 0], "emission": [10, 10, 10]}}, "objects": [
    {"name": "floor", "material": "white", "polygons": [[[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]]]},
    {"name": "lamp", "material": "lamp",
     "polygons": [[[-0.25,2,-0.25],[0.25,2,-0.25],[0.25,2,0.25],[-0.25,2,0.25]]]})";

// A floor, a 0.5 m square light facing down at y = 2 and one to four occluders on a dyadic grid
// (multiples of 1/8): horizontal, vertical and 45-degree cards, L-shaped cards given both ways
// round, boxes standing on the floor or floating; a third of the cards reach up into the light's
// plane, where the grid puts their corners on the light's edges and vertices. Coincidences are
// the point: shadows of one occluder's edges fall on another's, edges line up with the light's.
// The last occluder moves by dyadic steps at frames 1 and 2 (turned at 2).
std::string degenerateCardsJson(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const auto dyadic = [&](double lo, double hi) { return std::round(uniform(lo, hi) * 8) / 8; };
  using bench::Corners;
  using bench::reversed;
  const auto text = [](const Corners& corners) { return bench::cornersJson(corners); };
  std::ostringstream json;
  json << kSmallLampOverFloor;
  const int count = 1 + int(rng() % 4);
  for (int k = 0; k < count; ++k) {
    std::vector<Corners> polygons;
    const double x = dyadic(-0.75, 0.75), z = dyadic(-0.75, 0.75);
    const double a = dyadic(0.125, 0.5), b = dyadic(0.125, 0.5);
    double y = uniform(0, 1) < 0.3 ? 2.0 : dyadic(0.25, 2.0);
    switch (rng() % 6) {
      case 0:  // a box, on the floor or floating
        y = uniform(0, 1) < 0.4 ? 0.0 : dyadic(0.0, 1.5);
        for (Corners face : std::vector<Corners>{{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
                                                 {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
                                                 {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
                                                 {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
                                                 {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},
                                                 {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}}) {
          for (auto& c : face) c = {x + a * c[0], y + b * c[1], z + a * c[2]};
          polygons.push_back(face);
        }
        break;
      case 1:  // horizontal
        y = std::min(y, 1.875);
        polygons.push_back({{x, y, z}, {x, y, z + b}, {x + a, y, z + b}, {x + a, y, z}});
        break;
      case 2:  // in a plane x = const
        polygons.push_back({{x, y, z}, {x, y - a, z}, {x, y - a, z + b}, {x, y, z + b}});
        break;
      case 3:  // in a plane z = const
        polygons.push_back({{x, y, z}, {x, y - a, z}, {x + b, y - a, z}, {x + b, y, z}});
        break;
      case 4:  // turned 45 degrees about x
        polygons.push_back({{x, y, z}, {x + a, y, z}, {x + a, y - b, z + b}, {x, y - b, z + b}});
        break;
      default: {  // an L, both ways round
        y = std::min(y, 1.875);
        const Corners l{{x, y, z},         {x + 2 * a, y, z},     {x + 2 * a, y, z + b},
                        {x + a, y, z + b}, {x + a, y, z + 2 * b}, {x, y, z + 2 * b}};
        polygons.push_back(l);
        polygons.push_back(reversed(l));
      }
    }
    if (polygons.size() == 1 && rng() % 2) polygons[0] = reversed(polygons[0]);
    json << ", {\"name\": \"occluder" << k << "\", \"material\": \"white\", \"polygons\": [";
    for (size_t i = 0; i < polygons.size(); ++i) json << (i ? "," : "") << text(polygons[i]);
    json << "]";
    if (k + 1 == count)
      json << R"(, "motion": [{"frame": 0, "translate": [0, 0, 0]}, {"frame": 1, "translate": [)"
           << dyadic(-0.25, 0.25) << ", 0, " << dyadic(-0.25, 0.25)
           << R"(]}, {"frame": 2, "translate": [)" << dyadic(-0.25, 0.25) << ", "
           << dyadic(-0.25, 0) << ", " << dyadic(-0.25, 0.25)
           << R"(], "rotate": {"axis": [0, 1, 0], "degrees": 45}}])";
    json << "}";
  }
  json << "]}";
  return json.str();
}

// A card standing on the light's edge (its corner on the edge) above an L-shaped card: the case
// tests/dm/discontinuity_mesh_engine_test.cpp's CardStandingOnTheLightsEdgeIsExact pins down.
std::string cardOnTheLightsEdgeJson() {
  return std::string(kSmallLampOverFloor) + R"(,
    {"name": "L", "material": "white", "polygons": [
      [[-0.5,1,-0.5],[0.3,1,-0.5],[0.3,1,-0.1],[-0.1,1,-0.1],[-0.1,1,0.5],[-0.5,1,0.5]],
      [[-0.5,1,0.5],[-0.1,1,0.5],[-0.1,1,-0.1],[0.3,1,-0.1],[0.3,1,-0.5],[-0.5,1,-0.5]]]},
    {"name": "card", "material": "white",
     "polygons": [[[0.25,2,0],[0.25,1.6,0],[0.6,1.6,0],[0.6,2,0]]]}]})";
}

bool isConvex(const Polygon3& polygon) {
  if (polygon.size() == 3) return true;
  Vec3 normal{0, 0, 0};
  for (size_t i = 0; i < polygon.size(); ++i)
    normal = normal + cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    const Vec3& c = polygon[(i + 2) % polygon.size()];
    if (dot(cross(b - a, c - b), normal) <= 0) return false;
  }
  return true;
}

// Every convex non-emitting polygon split into a fan of triangles (the lights stay whole: a split
// light is two lights with other events). Returns how many polygons were split.
int triangulate(Scene& scene) {
  int split = 0;
  for (SceneObject& object : scene.objects) {
    SceneObject copy = object;
    copy.polygons.clear();
    copy.polygonMaterial.clear();
    copy.polygonOrigin.clear();
    for (size_t i = 0; i < object.polygons.size(); ++i) {
      const Polygon3& p = object.polygons[i];
      const bool emits = scene.materials[object.polygonMaterial[i]].emission.maxComponent() > 0;
      if (emits || p.size() == 3 || !isConvex(p)) {
        copy.polygons.push_back(p);
        copy.polygonMaterial.push_back(object.polygonMaterial[i]);
        copy.polygonOrigin.push_back(object.polygonOrigin[i]);
        continue;
      }
      ++split;
      for (size_t k = 1; k + 1 < p.size(); ++k) {
        copy.polygons.push_back({p[0], p[k], p[k + 1]});
        copy.polygonMaterial.push_back(object.polygonMaterial[i]);
        copy.polygonOrigin.push_back(object.polygonOrigin[i]);
      }
    }
    object = std::move(copy);
  }
  return split;
}

struct Tally {
  long long points = 0, differ = 0, byMesh = 0;
  long long edgeMidpoints = 0, edgeDiffer = 0, edgeByMesh = 0, edgeOnContacts = 0;
  long long cornerProbes = 0, cornerDiffer = 0;
  std::map<DiscontinuityMeshEngine::Answer, long long> edgeAtPoint;  // why the others were not
  double worst = 0;
  double slowestSeconds = 0;  // the slowest single query and where it was
  Vec3 slowestAt;
};

// engine.query(p, n), its time kept in the tally when it is the slowest yet (a query that walks
// and locates exactly at a degenerate point must not stall a user's probe).
std::optional<DiscontinuityMeshEngine::Query> timedQuery(const DiscontinuityMeshEngine& engine,
                                                         const Vec3& p, const Vec3& n,
                                                         Tally& tally) {
  const auto start = Clock::now();
  auto answered = engine.query(p, n);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (seconds > tally.slowestSeconds) {
    tally.slowestSeconds = seconds;
    tally.slowestAt = p;
  }
  return answered;
}

const char* answerName(DiscontinuityMeshEngine::Answer answer) {
  using A = DiscontinuityMeshEngine::Answer;
  switch (answer) {
    case A::kMesh:
      return "mesh";
    case A::kOutsideFaces:
      return "outside faces";
    case A::kUnresolvedFace:
      return "unresolved face";
    case A::kSliverFace:
      return "sliver face";
    case A::kNearEeePolyline:
      return "near an EEE polyline";
    case A::kDegenerate:
      return "degenerate";
    case A::kUnlabelled:
      return "unlabelled";
    case A::kOnAnotherPolygon:
      return "on another polygon";
  }
  return "?";
}

// The relative difference of the engine's answer from the reference's (infinite when the engine
// finds no receiver). In the umbra and deep penumbra, relative to 1e-4 of the brightest light's
// exitance `exitance`: there the value comes out of sums and clippings of terms of the order of
// the exitance, whose rounding leaves up to a few 1e-14 of it (measured at edge midpoints of
// desk-145: on the umbra's boundary the mesh answers 0, the reference 4e-12 W/m² under a lamp of
// exitance 110, and 7.09059e-7 against 7.09063e-7 beside it).
double relativeError(const std::optional<Rgb>& got, const Rgb& expected, double exitance) {
  const double scale = std::max(1e-4 * exitance, expected.maxComponent());
  return got ? std::max({std::abs(got->r - expected.r), std::abs(got->g - expected.g),
                         std::abs(got->b - expected.b)}) /
                   scale
             : INFINITY;
}

double brightestExitance(const PosedScene& posed) {
  double brightest = 0;
  for (PolygonId light : posed.lights)
    brightest =
        std::max(brightest, posed.materialOf(posed.polygons[light]).emission.maxComponent());
  return brightest;
}

// The midpoint of every event edge of every receiver mesh (outline and contact lines left out),
// where events meet and polylines' chords stand farthest from their conics. A midpoint on another
// polygon (an event along a contact line, a stub an extended event leaves beyond the outline where
// a wall meets the floor, or on a triangulated quad's diagonal, where the other triangle lies on
// the receiver as a card would) is a contact, whose value DESIGN.md §5 defines at the point and no
// face holds: counted apart (edgeOnContacts), not in the share answered by the mesh.
void compareEdgeMidpoints(const DiscontinuityMeshEngine& engine, const PosedScene& posed,
                          const ExactReference& reference, Tally& tally) {
  for (const WorldPolygon& receiver : posed.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const auto& [segment, surfaces] : mesh->edges()) {
      if (!std::all_of(surfaces.begin(), surfaces.end(), [](SurfaceId id) { return id >= 0; }))
        continue;
      const Vec3 p = (segment.first + segment.second) * 0.5;
      const auto answered = timedQuery(engine, p, receiver.plane.normal, tally);
      using Answer = DiscontinuityMeshEngine::Answer;
      if (answered && answered->answer == Answer::kOnAnotherPolygon) {
        ++tally.edgeOnContacts;
        continue;
      }
      ++tally.edgeMidpoints;
      if (!answered || answered->answer != Answer::kMesh) {
        ++tally.edgeAtPoint[answered ? answered->answer : Answer::kOutsideFaces];
        continue;
      }
      ++tally.edgeByMesh;
      const Rgb expected = reference.irradiance(p, receiver.plane.normal, receiver.id);
      if (relativeError(answered->irradiance, expected, brightestExitance(posed)) > 1e-9) {
        ++tally.edgeDiffer;
        if (showDiffering)
          std::printf(
              "  midpoint on %d (%.17g %.17g %.17g) of (%.12g %.12g %.12g)-(%.12g %.12g "
              "%.12g): %.12g, reference %.12g\n",
              receiver.id, p.x, p.y, p.z, segment.first.x, segment.first.y, segment.first.z,
              segment.second.x, segment.second.y, segment.second.z, answered->irradiance.r,
              expected.r);
      }
    }
  }
}

// Around every contact corner (an occluder's vertex on a receiver, the polygons not coplanar),
// in 24 directions at distances 1e-9 to 1e-4 of the scene, the points inside the receiver: there
// every event through the occluder's edges standing on the receiver meets, thin faces fan out
// separated by EEE polylines alone, and one side's limit is not the other's.
void probeContactCorners(const DiscontinuityMeshEngine& engine, const PosedScene& posed,
                         const ExactReference& reference, Tally& tally) {
  const double size = posed.extent.diagonalLength(), onPlane = 1e-9 * size;
  for (const WorldPolygon& q : posed.polygons) {
    if (q.isLight) continue;
    for (const Vec3& corner : q.vertices)
      for (const WorldPolygon& r : posed.polygons) {
        if (r.id == q.id || r.isLight || !r.bounds.expanded(onPlane).contains(corner)) continue;
        if (std::abs(dot(q.plane.normal, r.plane.normal)) > 1 - 1e-12) continue;
        if (std::abs(r.plane.signedDistance(corner)) > onPlane) continue;
        const PlaneFrame frame = PlaneFrame::fromPlane(r.plane, r.plane.project(corner));
        Polygon2 loop;
        for (const Vec3& v : r.vertices) loop.push_back(frame.toLocal(v));
        for (double distance = 1e-9 * size; distance < 2e-4 * size; distance *= 10)
          for (int d = 0; d < 24; ++d) {
            const double angle = d * M_PI / 12 + 0.01;
            const Vec2 local{distance * std::cos(angle), distance * std::sin(angle)};
            if (!containsPoint(loop, local)) continue;
            const Vec3 x = frame.toWorld(local);
            const auto answered = timedQuery(engine, x, r.plane.normal, tally);
            if (!answered) continue;
            ++tally.cornerProbes;
            const Rgb expected = reference.irradiance(x, r.plane.normal, r.id);
            if (relativeError(answered->irradiance, expected, brightestExitance(posed)) <= 1e-9)
              continue;
            ++tally.cornerDiffer;
            if (showDiffering)
              std::printf(
                  "  beside corner on %d (%.17g %.17g %.17g): %.12g (answer %d), "
                  "reference %.12g\n",
                  r.id, x.x, x.y, x.z, answered->irradiance.r, int(answered->answer), expected.r);
          }
      }
  }
}

Tally compare(const std::string& name, const Scene& scene, int points, std::uint64_t seed,
              bool verifyFaces, bool propagate, bool walked) {
  const auto start = Clock::now();
  DiscontinuityMeshEngine engine(
      {.eeeSurfaces = true, .verifyFaces = verifyFaces, .propagateBackprojections = propagate});
  DynamicScene live(scene, 0);
  if (walked) {
    engine.build(live);
    for (int frame = 1; frame < scene.frames; ++frame) {
      const SceneChange change = live.changeToFrame(frame);
      live.apply(change);
      engine.update(live, change);
    }
  } else {
    engine.build(PosedScene(live.posed()));
  }
  const PosedScene posed = live.posed();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  std::vector<ReceiverPoint> queries = sampleReceiverPoints(posed, points / 2, seed);
  for (const bench::PenumbraPoint& q :
       bench::samplePenumbraPoints(posed, reference, size_t(points - points / 2), seed + 1))
    queries.push_back(q.point);
  Tally tally;
  std::string first;
  for (const ReceiverPoint& q : queries) {
    const Rgb expected = reference.irradiance(q.p, q.n, q.receiver);
    const auto answered = timedQuery(engine, q.p, q.n, tally);
    const std::optional<Rgb> got =
        answered ? std::optional(answered->irradiance) : std::optional<Rgb>();
    if (answered && answered->answer == DiscontinuityMeshEngine::Answer::kMesh) ++tally.byMesh;
    const double error = relativeError(got, expected, brightestExitance(posed));
    ++tally.points;
    tally.worst = std::max(tally.worst, error);
    if (error <= 1e-9) continue;
    if (tally.differ++ == 0) {
      char text[200];
      std::snprintf(text, sizeof text, "first at (%.6f %.6f %.6f) polygon %d: %.9g vs %.9g", q.p.x,
                    q.p.y, q.p.z, q.receiver, got ? got->r : -1.0, expected.r);
      first = text;
    }
  }
  compareEdgeMidpoints(engine, posed, reference, tally);
  if (probeCorners) probeContactCorners(engine, posed, reference, tally);
  const DmStats& s = engine.stats();
  char slowest[120] = "";
  if (tally.slowestSeconds > 0.1)
    std::snprintf(slowest, sizeof slowest, " at (%.9g %.9g %.9g)", tally.slowestAt.x,
                  tally.slowestAt.y, tally.slowestAt.z);
  std::printf(
      "%-34s %6zu %6lld %6lld %9.2e %7.2f %6lld/%-6lld %6.2f%% %6lld %5lld %6.2f%% %8.4f%s %s\n",
      name.c_str(), posed.polygons.size(), tally.points, tally.differ, tally.worst, seconds,
      s.unresolvedFaces, s.meshFaces, 100.0 * double(tally.byMesh) / double(tally.points),
      tally.edgeMidpoints, tally.edgeDiffer,
      100.0 * double(tally.edgeByMesh) / double(std::max(1LL, tally.edgeMidpoints)),
      tally.slowestSeconds, slowest, first.c_str());
  std::fflush(stdout);
  return tally;
}

}  // namespace

static int benchMain(int argc, char** argv) {
  int points = 2000;
  bool propagate = DmOptions{}.propagateBackprojections;
  bool walked = false, verifiedOnly = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--walked")) walked = true;
    if (!std::strcmp(argv[i], "--verified-only")) verifiedOnly = true;
    if (!std::strcmp(argv[i], "--show")) showDiffering = true;
    if (!std::strcmp(argv[i], "--corners")) probeCorners = true;
  }
  std::string only;  // --only S: the scenes whose name contains S
  for (int i = 1; i + 1 < argc; ++i) {
    if (!std::strcmp(argv[i], "--only")) only = argv[i + 1];
    if (!std::strcmp(argv[i], "--points")) points = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--propagate")) propagate = !std::strcmp(argv[i + 1], "on");
  }
  const std::string root = PENUMBRA_SOURCE_DIR;
  const auto tmp = std::filesystem::temp_directory_path() / "penumbra-bench";
  std::filesystem::create_directories(tmp);
  const auto written = [&](const std::string& name, const std::string& json) {
    const auto path = tmp / (name + ".json");
    std::ofstream(path) << json;
    return path.string();
  };
  std::vector<std::pair<std::string, std::string>> scenes = {
      {"cornell-box", root + "/scenes/cornell-box/cornell-box.json"},
      {"cornell-everything-moves", root + "/scenes/cornell-box/cornell-everything-moves.json"},
      {"desk-145", root + "/scenes/office-desk/desk-145.json"},
      {"desk-307", root + "/scenes/office-desk/desk-307.json"},
      {"desk-475", root + "/scenes/office-desk/desk-475.json"},
      {"chair-room", root + "/scenes/chair-room/chair-room.json"},
  };
  for (std::uint64_t seed : {1, 2, 3})
    scenes.push_back(
        {"generated-300-seed" + std::to_string(seed),
         written("exact-gen-300-" + std::to_string(seed), generateSceneJson({300, seed, 2}))});
  scenes.push_back(
      {"generated-1000-three-moving-boxes",
       written(
           "exact-gen-1000-3",
           generateSceneJson({.targetPolygons = 1000, .seed = 5, .frames = 4, .movingBoxes = 3}))});
  for (std::uint64_t seed : {11, 12, 13, 14})
    scenes.push_back({"rotated-boxes-seed" + std::to_string(seed),
                      written("exact-boxes-" + std::to_string(seed), rotatedBoxesJson(seed))});
  scenes.push_back(
      {"card-on-the-lights-edge", written("exact-card-edge", cardOnTheLightsEdgeJson())});
  for (std::uint64_t seed = 21; seed <= 28; ++seed)
    scenes.push_back({"degenerate-cards-seed" + std::to_string(seed),
                      written("exact-cards-" + std::to_string(seed), degenerateCardsJson(seed))});

  std::printf(
      "# dm vs exact reference, %d points per scene (half uniform, half penumbra); "
      "backprojections %s%s\n",
      points, propagate ? "propagated between faces (where verified)" : "from scratch",
      walked ? "; engines updated through every frame, compared at the last" : "");
  std::printf("%-34s %6s %6s %6s %9s %7s %s %s %s %s %s %s\n", "scene", "polys", "points", "differ",
              "worst", "build s", "unresolved/faces", "by mesh", "edge midpoints", "differ",
              "by mesh", "slowest query s");
  for (bool verifyFaces : {false, true}) {
    if (!verifyFaces && verifiedOnly) continue;
    std::printf("\n## faces %s\n", verifyFaces ? "verified at their corners (the default)"
                                               : "answering from their sample's labels only");
    Tally total, totalTriangulated;
    std::uint64_t seed = 100;
    for (const auto& [name, path] : scenes) {
      Scene scene = loadScene(path);
      if ((walked && scene.frames < 2) || name.find(only) == std::string::npos) continue;
      const Tally a = compare(name, scene, points, seed, verifyFaces, propagate, walked);
      triangulate(scene);
      const Tally b =
          compare(name + " (triangles)", scene, points, seed + 7, verifyFaces, propagate, walked);
      total.points += a.points;
      total.differ += a.differ;
      total.byMesh += a.byMesh;
      for (const Tally* t : {&a, &b}) {
        total.edgeMidpoints += t->edgeMidpoints;
        total.edgeDiffer += t->edgeDiffer;
        total.edgeByMesh += t->edgeByMesh;
        total.edgeOnContacts += t->edgeOnContacts;
        total.cornerProbes += t->cornerProbes;
        total.cornerDiffer += t->cornerDiffer;
        for (const auto& [answer, count] : t->edgeAtPoint) total.edgeAtPoint[answer] += count;
      }
      totalTriangulated.points += b.points;
      totalTriangulated.differ += b.differ;
      seed += 17;
    }
    std::printf(
        "total: %lld of %lld points differ (%.2f%% answered by the mesh); triangulated "
        "copies: %lld of %lld\n",
        total.differ, total.points, 100.0 * double(total.byMesh) / double(total.points),
        totalTriangulated.differ, totalTriangulated.points);
    std::printf(
        "edge midpoints (both copies): %lld of %lld answered by the mesh (%.2f%%), %lld "
        "of those differ; %lld more on contacts\n",
        total.edgeByMesh, total.edgeMidpoints,
        100.0 * double(total.edgeByMesh) / double(std::max(1LL, total.edgeMidpoints)),
        total.edgeDiffer, total.edgeOnContacts);
    for (const auto& [answer, count] : total.edgeAtPoint)
      std::printf("  answered at the point, %s: %lld\n", answerName(answer), count);
    if (probeCorners)
      std::printf("beside contact corners (both copies): %lld of %lld points differ\n",
                  total.cornerDiffer, total.cornerProbes);
  }
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("dm_exactness", argc, argv, benchMain);
}
