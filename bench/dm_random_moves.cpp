// The exact soft shadows' update under adversarial motion: a seeded random walk of rigid moves of
// a few boxes, a card and the light in a small room, each applied to a live scene and an engine
// updated through it, then compared bit for bit (irradiance mesh: corners, exact irradiance,
// triangles, discontinuity edges) with an engine built from scratch at the same pose. Moves are
// drawn to hit the configurations where engines fail: objects set down on the floor or on one
// another (contacts), pushed against each other (shared planes), positions on a dyadic grid
// (exactly coplanar faces and edges in line with the light's) or at random, turns by multiples of
// 15 degrees or at random, the card stood edge-on to the light, and moves of the light itself.
//
// Usage: dm_random_moves [--moves N] [--seed S] [--check-from M] [--write-differing 1]
//   (defaults 1000, 1 and 0; exit 1 on any difference). --check-from compares only from move M on
//   (the walk up to it is the same, only faster: to reach a reported difference again);
//   --write-differing 1 writes each differing receiver's segments before and after the move to a
//   file (for a test of ReceiverMesh alone). It keeps a copy of every receiver's segments before
//   each compared move, outside the timings: off by default, since the copies change the heap
//   layout the walk runs in (a difference that depends on it may then not show).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/geometry/quaternion.h"
#include "penumbra/scene/scene_loader.h"

namespace {

using namespace penumbra;
using Clock = std::chrono::steady_clock;

// A 2 m room lit by a 0.4 m ceiling light; the movable objects are modelled around their own
// base centre (resting on y = 0 at the identity transform).
const char* kScene = R"({
  "penumbra": 1,
  "materials": {
    "white": { "reflectance": [0.7, 0.7, 0.7] },
    "light": { "reflectance": [0.5, 0.5, 0.5], "emission": [20, 20, 20] }
  },
  "objects": [
    { "name": "room", "material": "white",
      "polygons": [
        [[0, 0, 0], [0, 0, 2], [2, 0, 2], [2, 0, 0]],
        [[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]],
        [[0, 0, 0], [0, 2, 0], [0, 2, 2], [0, 0, 2]]
      ] },
    { "name": "light", "material": "light",
      "polygons": [ [[0.8, 1.9, 0.8], [1.2, 1.9, 0.8], [1.2, 1.9, 1.2], [0.8, 1.9, 1.2]] ] },
    { "name": "box", "material": "white",
      "polygons": [
        [[-0.15, 0, -0.15], [0.15, 0, -0.15], [0.15, 0, 0.15], [-0.15, 0, 0.15]],
        [[-0.15, 0.3, -0.15], [-0.15, 0.3, 0.15], [0.15, 0.3, 0.15], [0.15, 0.3, -0.15]],
        [[-0.15, 0, -0.15], [-0.15, 0.3, -0.15], [0.15, 0.3, -0.15], [0.15, 0, -0.15]],
        [[-0.15, 0, 0.15], [0.15, 0, 0.15], [0.15, 0.3, 0.15], [-0.15, 0.3, 0.15]],
        [[-0.15, 0, -0.15], [-0.15, 0, 0.15], [-0.15, 0.3, 0.15], [-0.15, 0.3, -0.15]],
        [[0.15, 0, -0.15], [0.15, 0.3, -0.15], [0.15, 0.3, 0.15], [0.15, 0, 0.15]]
      ] },
    { "name": "tall box", "material": "white",
      "polygons": [
        [[-0.1, 0, -0.1], [0.1, 0, -0.1], [0.1, 0, 0.1], [-0.1, 0, 0.1]],
        [[-0.1, 0.5, -0.1], [-0.1, 0.5, 0.1], [0.1, 0.5, 0.1], [0.1, 0.5, -0.1]],
        [[-0.1, 0, -0.1], [-0.1, 0.5, -0.1], [0.1, 0.5, -0.1], [0.1, 0, -0.1]],
        [[-0.1, 0, 0.1], [0.1, 0, 0.1], [0.1, 0.5, 0.1], [-0.1, 0.5, 0.1]],
        [[-0.1, 0, -0.1], [-0.1, 0, 0.1], [-0.1, 0.5, 0.1], [-0.1, 0.5, -0.1]],
        [[0.1, 0, -0.1], [0.1, 0.5, -0.1], [0.1, 0.5, 0.1], [0.1, 0, 0.1]]
      ] },
    { "name": "card", "material": "white",
      "polygons": [ [[-0.125, 0, -0.125], [-0.125, 0, 0.125], [0.125, 0, 0.125], [0.125, 0, -0.125]] ] }
  ]
})";

constexpr int kLight = 1;
const std::vector<int> kMovable = {2, 3, 4};
const std::vector<double> kHeights = {0.3, 0.5, 0};  // each movable object's height

Box3 boundsOf(const DynamicScene& live, int object) {
  const PosedScene& posed = live.posed();
  Box3 box;
  for (PolygonId id = posed.objectFirstPolygon[object]; id < posed.objectFirstPolygon[object + 1];
       ++id)
    box.extend(posed.polygons[id].bounds);
  return box;
}

// Do two boxes share interior (touching is allowed)?
bool interiorsOverlap(const Box3& a, const Box3& b) {
  return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y &&
         a.min.z < b.max.z && b.min.z < a.max.z;
}

}  // namespace

static int benchMain(int argc, char** argv) {
  int moves = 1000, checkFrom = 0;
  bool writeDiffering = false;
  std::uint64_t seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--moves") moves = std::atoi(argv[i + 1]);
    if (flag == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    if (flag == "--check-from") checkFrom = std::atoi(argv[i + 1]);
    if (flag == "--write-differing") writeDiffering = std::atoi(argv[i + 1]) != 0;
  }
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("dm_random_moves_" + std::to_string(seed) + ".json");
  std::ofstream(path) << kScene;
  const Scene scene = loadScene(path.string());
  std::filesystem::remove(path);

  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto pick = [&](int n) { return int(rng() % std::uint64_t(n)); };
  // Positions on a dyadic grid (exact sums: exact contacts and coplanar faces) or anywhere.
  const auto coordinate = [&](double lo, double hi) {
    const double x = lo + (hi - lo) * unit(rng);
    return pick(3) != 0 ? std::round(x * 16) / 16 : x;
  };

  int differences = 0, rebuilt = 0, kinds[6] = {};
  double updateSeconds = 0, fullSeconds = 0;
  long long reused = 0, recomputed = 0;
  for (int move = 0; move < moves; ++move) {
    SceneChange change;
    int kind = pick(6);
    if (kind == 5) {
      // The light, within the ceiling band above the objects.
      const Vec3 shift{coordinate(-0.6, 0.6), -coordinate(0, 0.3), coordinate(-0.6, 0.6)};
      change = live.changeMoving(kLight, Transform{Mat3{}, shift});
    } else {
      const int k = pick(int(kMovable.size()));
      const int object = kMovable[size_t(k)];
      const double turn = pick(2) == 0 ? M_PI / 12 * pick(24) : 2 * M_PI * unit(rng);
      Quaternion rotation = Quaternion::fromAxisAngle({0, 1, 0}, turn);
      Vec3 at{coordinate(0.3, 1.7), 0, coordinate(0.3, 1.7)};
      if (kind == 1) {  // set down on top of another object
        const int other = kMovable[size_t((k + 1 + pick(2)) % 3)];
        const Box3 below = boundsOf(live, other);
        at = {below.center().x, below.max.y, below.center().z};
      } else if (kind == 2) {  // pushed against another object along x, faces sharing a plane
        const int other = kMovable[size_t((k + 1 + pick(2)) % 3)];
        const Box3 beside = boundsOf(live, other);
        rotation = Quaternion::fromAxisAngle({0, 1, 0}, 0);
        const double half = object == 2 ? 0.15 : object == 3 ? 0.1 : 0.125;
        at = {beside.max.x + half, 0, beside.min.z + half};
      } else if (kind == 3) {  // floating
        at.y = coordinate(0.05, 1.2);
      } else if (kind == 4 && object == 4) {  // the card stood on edge, in line with the light
        rotation = Quaternion::fromAxisAngle({1, 0, 0}, M_PI / 2);
        at = {coordinate(0.3, 1.7), 0.125 + coordinate(0, 0.6), 0.8 + pick(2) * 0.4};
      }
      const Transform transform = Transform::fromTrs(at, rotation, {1, 1, 1});
      // Keep the objects apart (touching allowed) and inside the room.
      change = live.changeMoving(object, transform);
      if (change.moves.empty()) continue;
      const Box3 after = change.moves[0].boundsAfter;
      bool clear = after.min.x >= 0 && after.min.z >= 0 && after.max.x <= 2 && after.max.z <= 2 &&
                   after.max.y <= 1.8 && after.min.y >= -1e-12;
      for (int other : kMovable)
        if (other != object) clear = clear && !interiorsOverlap(after, boundsOf(live, other));
      if (!clear) {
        --move;
        continue;
      }
      kind = kind == 4 && object != 4 ? 0 : kind;
    }
    if (change.moves.empty()) continue;
    ++kinds[kind];
    // Each receiver's mesh inputs before the update, to write out a receiver whose edit differs.
    std::map<PolygonId, std::vector<DiscontinuitySegment>> inputsBefore;
    if (writeDiffering && move >= checkFrom)
      for (const WorldPolygon& p : live.posed().polygons)
        if (engine.meshOf(p.id)) inputsBefore[p.id] = engine.meshInputs(p.id);
    auto start = Clock::now();
    live.apply(change);
    engine.update(live, change);
    const double update = std::chrono::duration<double>(Clock::now() - start).count();
    updateSeconds += update;
    rebuilt += engine.stats().recomputedAll ? 1 : 0;
    reused += engine.stats().reusedFaces;
    recomputed += engine.stats().recomputedFaces;
    if (move < checkFrom) continue;
    start = Clock::now();
    const DynamicScene scratch(live.scene(), live.posed().objectTransforms, live.extent(),
                               live.frame());
    DiscontinuityMeshEngine full;
    full.build(scratch);
    const double rebuild = std::chrono::duration<double>(Clock::now() - start).count();
    fullSeconds += rebuild;
    if (update > 1 || rebuild > 1) {
      std::printf("move %d (kind %d): slow, update %.2f s, full %.2f s\n", move, kind, update,
                  rebuild);
      std::fflush(stdout);
    }
    const IrradianceMesh updatedMesh = buildIrradianceMesh(engine);
    const IrradianceMesh fullMesh = buildIrradianceMesh(full);
    const auto difference = firstDifference(updatedMesh, fullMesh);
    if (difference) {
      if (differences < 10) {
        std::printf("move %d (kind %d): DIFFERS from a full recomputation: %s\n", move, kind,
                    difference->c_str());
        // Which receivers' meshes differ, and their first differing face.
        for (const WorldPolygon& p : live.posed().polygons) {
          const ReceiverMesh* a = engine.meshOf(p.id);
          const ReceiverMesh* b = full.meshOf(p.id);
          if (!a || !b) continue;
          std::optional<size_t> face;
          for (size_t f = 0; !face && f < std::min(a->faces().size(), b->faces().size()); ++f)
            if (!(a->faces()[f].samplePoint == b->faces()[f].samplePoint) ||
                a->faceBoundary(int(f)) != b->faceBoundary(int(f)))
              face = f;
          if (!face && a->faces().size() == b->faces().size() && a->edges() == b->edges()) continue;
          std::printf("  receiver %d: vertices %d vs %d, edges %d vs %d, faces %zu vs %zu\n", p.id,
                      a->vertexCount(), b->vertexCount(), a->edgeCount(), b->edgeCount(),
                      a->faces().size(), b->faces().size());
          if (face) {
            const Vec3 &x = a->faces()[*face].samplePoint, &y = b->faces()[*face].samplePoint;
            std::printf("  face %zu: sample (%.17g %.17g %.17g) vs (%.17g %.17g %.17g)\n", *face,
                        x.x, x.y, x.z, y.x, y.y, y.z);
          }
          // The edges only one of them has, with their surfaces.
          const auto ea = a->edges(), eb = b->edges();
          const auto print = [](const char* which, const auto& e) {
            std::printf("  only %s: (%.17g %.17g %.17g) - (%.17g %.17g %.17g), surfaces", which,
                        e.first.first.x, e.first.first.y, e.first.first.z, e.first.second.x,
                        e.first.second.y, e.first.second.z);
            for (SurfaceId id : e.second) std::printf(" %d", id);
            std::printf("\n");
          };
          for (const auto& e : ea)
            if (std::find(eb.begin(), eb.end(), e) == eb.end()) print("updated", e);
          for (const auto& e : eb)
            if (std::find(ea.begin(), ea.end(), e) == ea.end()) print("full", e);
          // And the segments only one of them was built from.
          const auto& ia = engine.meshInputs(p.id);
          const auto& ib = full.meshInputs(p.id);
          const auto same = [](const DiscontinuitySegment& x, const DiscontinuitySegment& y) {
            return x.surface == y.surface && x.p0 == y.p0 && x.p1 == y.p1;
          };
          const auto printSegment = [](const char* which, const DiscontinuitySegment& x) {
            std::printf("  input only %s: surface %d (%.17g %.17g %.17g) - (%.17g %.17g %.17g)\n",
                        which, x.surface, x.p0.x, x.p0.y, x.p0.z, x.p1.x, x.p1.y, x.p1.z);
          };
          if (const auto was = inputsBefore.find(p.id); was != inputsBefore.end()) {
            // The receiver and its segments before and after, for a test of ReceiverMesh alone.
            const std::string name = "dm_random_moves_receiver_" + std::to_string(p.id) + "_move_" +
                                     std::to_string(move) + ".txt";
            std::ofstream out(name);
            out.precision(17);
            out << "diagonal " << live.posed().extent.diagonalLength() << "\n";
            out << "receiver " << p.vertices.size();
            for (const Vec3& v : p.vertices) out << " " << v.x << " " << v.y << " " << v.z;
            out << "\n";
            const std::vector<DiscontinuitySegment>& before = was->second;
            for (const std::vector<DiscontinuitySegment>* list : {&before, &ia}) {
              out << "segments " << list->size() << "\n";
              for (const DiscontinuitySegment& x : *list)
                out << x.surface << " " << x.p0.x << " " << x.p0.y << " " << x.p0.z << " " << x.p1.x
                    << " " << x.p1.y << " " << x.p1.z << "\n";
            }
            std::printf("  wrote %s\n", name.c_str());
          }
          for (const auto& x : ia)
            if (std::none_of(ib.begin(), ib.end(), [&](const auto& y) { return same(x, y); }))
              printSegment("updated", x);
          for (const auto& y : ib)
            if (std::none_of(ia.begin(), ia.end(), [&](const auto& x) { return same(x, y); }))
              printSegment("full", y);
        }
      }
      std::fflush(stdout);
      ++differences;
    }
    if ((move + 1) % 100 == 0) {
      std::printf("%d moves: %d differences; update %.3f s, full %.3f s in all (x%.2f)\n", move + 1,
                  differences, updateSeconds, fullSeconds, fullSeconds / updateSeconds);
      std::fflush(stdout);
    }
  }
  std::printf(
      "seed %llu, %d moves (floor %d, stacked %d, pushed together %d, floating %d, card on edge "
      "%d, light %d; %d recomputed everything): %d differ from a full recomputation; faces reused "
      "%lld, recomputed %lld; update %.3f s, full %.3f s (x%.2f)\n",
      (unsigned long long)seed, moves, kinds[0], kinds[1], kinds[2], kinds[3], kinds[4], kinds[5],
      rebuilt, differences, reused, recomputed, updateSeconds, fullSeconds,
      fullSeconds / updateSeconds);
  return differences == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("dm_random_moves", argc, argv, benchMain);
}
