// Fuzz target, structure-aware: valid small scenes with adversarial geometry (fuzzed_scene.h)
// through the exact soft-shadow engine, as `penumbra shadows` and `probe --method dm` run it. Each
// scene that validateScene accepts is built (and, when it moves, updated to frame 1 and compared
// with a build from scratch, as `shadows --mode verify` does); then
// - every corner of the irradiance mesh (`shadows --out`) has finite, non-negative irradiance;
// - probe points on the floor (free ones, occluder corners lying on it, the points under every
//   occluder corner) and at the occluders' centroids are answered with finite, non-negative
//   irradiance equal to the exact reference's (ExactReference, lighting/) to 1e-9 relative, the
//   tolerance of the engine's own tests (more for scenes far from the origin compared with their
//   size, and at points nearly touching another polygon, as the input's rounding allows:
//   checkSolution); a point strictly inside the floor must
//   be answered.
// A scene that validation rejects is not interesting (the rejection must be an InputError naming
// the polygon); anything the engine throws or breaks on an accepted scene is a finding.
//
// Open findings (fuzz/README.md) can be tolerated, to fuzz past them until they are fixed, with
// PENUMBRA_FUZZ_TOLERATE=name[,name...]:
// - contact-points: probes lying on a polygon other than their receiver (an occluder's corner or
//   edge resting on the floor, an occluder lying on it; within 1e-8 of the scene's size, where the
//   engine's own tolerances act) are points of a D0 discontinuity, where
//   the irradiance of DESIGN.md §5 (a polygon through p hides nothing) is neither one-sided limit;
//   they are left out of the comparison with the reference (still checked finite, non-negative);
// - reference-rounding-below-zero: the exact reference may answer below zero by rounding (no more
//   than DiscontinuityMeshEngine::isDegenerate allows), where the light touches the receiver's
//   plane.
//
// With PENUMBRA_FUZZ_DUMP=DIR in the environment, the accepted scene is written to DIR/scene.json
// and the probe points of each frame to DIR/points-frame-K.txt before they are checked, so that a
// finding reproduces with `penumbra probe DIR/scene.json --points ... --method dm|reference`.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "fuzz_input.h"
#include "fuzz_outcome.h"
#include "fuzzed_scene.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/reach_bounds.h"
#include "penumbra/scene/repeated_vertices.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/receiver_locator.h"
#include "scene_json_writer.h"

namespace penumbra::fuzz {
namespace {

struct Probe {
  Vec3 p, n;
  std::string what;
  bool mustBeAnswered = false;  // strictly inside the floor, facing up
};

std::string text(const Vec3& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.17g, %.17g, %.17g)", p.x, p.y, p.z);
  return buffer;
}
std::string text(const Rgb& c) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.17g, %.17g, %.17g)", c.r, c.g, c.b);
  return buffer;
}

// Where PENUMBRA_FUZZ_DUMP asks the scene and the probe points to be written, or nothing.
const char* dumpDirectory() {
  return std::getenv("PENUMBRA_FUZZ_DUMP");
}

void dumpProbes(const std::vector<Probe>& probes, int frame) {
  if (!dumpDirectory()) return;
  std::ofstream out(std::string(dumpDirectory()) + "/points-frame-" + std::to_string(frame) +
                    ".txt");
  char line[256];
  for (const Probe& probe : probes) {
    out << "# " << probe.what << "\n";
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", probe.p.x, probe.p.y,
                  probe.p.z, probe.n.x, probe.n.y, probe.n.z);
    out << line;
  }
}

// Is the open finding `name` tolerated (PENUMBRA_FUZZ_TOLERATE)?
bool tolerates(const std::string& name) {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    const char* value = std::getenv("PENUMBRA_FUZZ_TOLERATE");
    std::string rest = value ? value : "";
    for (size_t comma; (comma = rest.find(',')) != std::string::npos; rest.erase(0, comma + 1))
      list.push_back(rest.substr(0, comma));
    list.push_back(rest);
    return list;
  }();
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The distance from p to the nearest polygon other than `receiver` (its inside or boundary);
// with `lyingWithin`, leaving out the polygons lying in the receiver's plane (parallel to it, p
// within that of their plane), as the engine does where it looks for contacts.
double distanceToAnotherPolygon(const PosedScene& posed, const Vec3& p,
                                std::optional<PolygonId> receiver,
                                std::optional<double> lyingWithin = std::nullopt) {
  double nearest = INFINITY;
  for (const WorldPolygon& polygon : posed.polygons) {
    if (receiver && polygon.id == *receiver) continue;
    const double offPlane = std::abs(polygon.plane.signedDistance(p));
    if (receiver && lyingWithin && offPlane <= *lyingWithin &&
        std::abs(dot(polygon.plane.normal, posed.polygons[*receiver].plane.normal)) >= 1 - 1e-12)
      continue;
    const PlaneFrame frame = PlaneFrame::fromPlane(polygon.plane, polygon.vertices[0]);
    Polygon2 flat;
    for (const Vec3& corner : polygon.vertices) flat.push_back(frame.toLocal(corner));
    const Vec2 q = frame.toLocal(p);
    double inPlane = containsPoint(flat, q) ? 0 : INFINITY;
    for (size_t i = 0; i < flat.size() && inPlane > 0; ++i) {
      const Vec2 a = flat[i], b = flat[(i + 1) % flat.size()];
      const Vec2 ab = b - a, aq = q - a;
      const double t = std::clamp(dot(aq, ab) / dot(ab, ab), 0.0, 1.0);
      const Vec2 gap = aq - ab * t;
      inPlane = std::min(inPlane, std::sqrt(dot(gap, gap)));
    }
    nearest = std::min(nearest, std::hypot(offPlane, inPlane));
  }
  return nearest;
}

// Does p lie on a polygon other than `receiver`, within `tolerance`?
bool liesOnAnotherPolygon(const PosedScene& posed, const Vec3& p, std::optional<PolygonId> receiver,
                          double tolerance) {
  return distanceToAnotherPolygon(posed, p, receiver) <= tolerance;
}

std::string shortText(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

bool isFiniteNonNegative(const Rgb& e) {
  return e.isFinite() && e.r >= 0 && e.g >= 0 && e.b >= 0;
}

std::vector<Probe> probesOf(const FuzzedScene& fuzzed, const DynamicScene& live) {
  const PosedScene& posed = live.posed();
  const WorldPolygon& floor = posed.polygons[posed.objectFirstPolygon[kFloorObject]];
  const Vec3 up = floor.plane.normal;
  // The floor is horizontal in every pose (scaled and moved, never turned): one height, one box.
  const double floorZ = floor.vertices[0].z;
  const Box3& box = floor.bounds;
  const auto isInsideFloor = [&](const Vec3& p) {
    const double margin = 1e-3 * (box.max.x - box.min.x);
    return p.x > box.min.x + margin && p.x < box.max.x - margin && p.y > box.min.y + margin &&
           p.y < box.max.y - margin;
  };
  std::vector<Probe> probes;
  for (const Vec3& q : fuzzed.floorPoints) {
    const Vec3 p = live.transformOf(kFloorObject).applyToPoint(q);
    probes.push_back({p, up, "floor point " + text(p), isInsideFloor(p)});
  }
  for (int object = kFirstOccluderObject; object < posed.objectCount(); ++object) {
    const WorldPolygon& occluder = posed.polygons[posed.objectFirstPolygon[object]];
    for (const Vec3& corner : occluder.vertices) {
      // An occluder's corner lying on the floor (contact): where Lambert's formula over a
      // backprojection degenerates (zero-length edge vectors) and the engine must answer at the
      // point.
      if (corner.z == floorZ)
        probes.push_back(
            {corner, up, "occluder corner on the floor " + text(corner), isInsideFloor(corner)});
      const Vec3 below{corner.x, corner.y, floorZ};
      if (corner.z > floorZ)
        probes.push_back({below, up, "floor point under an occluder corner " + text(below),
                          isInsideFloor(below)});
    }
    probes.push_back({centroid(occluder.vertices), occluder.plane.normal,
                      "centroid of occluder " + std::to_string(occluder.id), false});
  }
  return probes;
}

// The engine's answers at the probes against the exact reference, and the irradiance mesh.
void checkSolution(const DiscontinuityMeshEngine& engine, const DynamicScene& live,
                   const FuzzedScene& fuzzed, int frameNumber) {
  const std::string frame = "frame " + std::to_string(frameNumber);
  const IrradianceMesh mesh = buildIrradianceMesh(engine);
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (!mesh.positions[i].isFinite() || !isFiniteNonNegative(mesh.irradiance[i]))
      reportFinding(frame + ": irradiance mesh corner " + text(mesh.positions[i]) + " has " +
                    text(mesh.irradiance[i]));

  const PosedScene& posed = live.posed();
  const ExactReference reference(posed, &live.grid());
  double exitance = 0;
  for (PolygonId light : posed.lights)
    exitance = std::max(exitance, posed.materialOf(posed.polygons[light]).emission.maxComponent());
  // The engine's tests compare to 1e-9 relative, in scenes near the origin. Far from it the
  // input itself is that uncertain: every coordinate carries a rounding of eps x M (M its largest
  // magnitude), eps x M / size of this pose's size, and the irradiance moves with the geometry
  // by up to about 1e3 times as much where features are 1e-3 of that size. (A scene 0.6 across
  // 1e6 from the origin: 3e-7.) Likewise at a point h from another polygon (an occluder nearly
  // touching the floor above it): seen from there that rounding is magnified by 1/h instead of
  // 1/size (an occluder 1e-7 above the floor of a scene 0.9 across, the point under its corner:
  // the engine and the reference 2e-9 apart, each within rounding of the value).
  const double size = length(posed.bounds.max - posed.bounds.min);
  double magnitude = 0;
  for (const Vec3& corner : {posed.bounds.min, posed.bounds.max})
    magnitude = std::max({magnitude, std::abs(corner.x), std::abs(corner.y), std::abs(corner.z)});
  const auto toleranceAt = [&](double near) {
    return std::max(
        1e-9, 1e3 * std::numeric_limits<double>::epsilon() * magnitude / std::min(size, near));
  };
  // The engine's own tolerances are fractions of the extent (every pose's bounds).
  const double extentSize = length(posed.extent.max - posed.extent.min);
  const std::vector<Probe> probes = probesOf(fuzzed, live);
  dumpProbes(probes, frameNumber);
  for (const Probe& probe : probes) {
    const std::string where = frame + ", " + probe.what;
    const auto answer = engine.query(probe.p, probe.n);
    if (!answer) {
      if (probe.mustBeAnswered) reportFinding(where + ": the engine finds no receiver");
      continue;
    }
    if (!isFiniteNonNegative(answer->irradiance))
      reportFinding(where + ": the engine answers " + text(answer->irradiance));
    const auto receiver = locateReceiver(posed, live.grid(), probe.p, probe.n);
    const Rgb expected = reference.irradiance(
        probe.p, probe.n, receiver ? std::optional(receiver->polygon) : std::nullopt);
    if (!isFiniteNonNegative(expected) &&
        !(tolerates("reference-rounding-below-zero") && !engine.isDegenerate(expected)))
      reportFinding(where + ": the exact reference answers " + text(expected));
    // Within 1e-8 of the extent's size of another polygon: ten times the engine's own grey zone
    // there (discontinuity segments are lengthened by 1e-9 of the extent's size).
    if (tolerates("contact-points") &&
        liesOnAnotherPolygon(posed, probe.p,
                             receiver ? std::optional(receiver->polygon) : std::nullopt,
                             1e-8 * extentSize))
      continue;
    // As the engine's tests compare (ContactPoints): relative to the value, and below a
    // millionth of the light's exitance relative to that millionth (1e-15 of the exitance: there
    // Lambert's sum over a visible region of nothing rounds to 1e-17..1e-14 of it, either side of
    // zero; session 15 had this floor at 1e-12 of the exitance, 1e-21 of it after the relative
    // tolerance, and reported 1.8e-16 against 0 as a finding).
    const double scale = std::max(expected.maxComponent(), 1e-6 * exitance);
    // On a contact (within the engine's grey zone, 1e-9 of the extent's size: contactSegments)
    // the engine answers at the point, as the reference: no magnification there. A polygon lying
    // in the receiver's plane over the point is no such contact: it hides nothing, the engine
    // answers from the receiver's faces, and what magnifies the rounding is the nearest other
    // polygon (session 25: a point 2.2e-7 from an occluder's foot, on a triangle lying on the
    // floor, 1e3 from the origin: 4.3e-9 apart where one ulp of the point moves both by 1.4e-8).
    const double near = distanceToAnotherPolygon(
        posed, probe.p, receiver ? std::optional(receiver->polygon) : std::nullopt,
        1e-9 * extentSize);
    const double tolerance = toleranceAt(near > 1e-9 * extentSize ? near : size);
    const Rgb difference = answer->irradiance - expected;
    const double error =
        std::max({std::abs(difference.r), std::abs(difference.g), std::abs(difference.b)}) / scale;
    if (!(error <= tolerance))
      reportFinding(where + ": the engine answers " + text(answer->irradiance) + " (answer kind " +
                    std::to_string(int(answer->answer)) + "), the exact reference " +
                    text(expected) + ", relative error " + shortText(error) + " (tolerance " +
                    shortText(tolerance) + ")");
  }
}

void run(const FuzzedScene& fuzzed) {
  DynamicScene live(fuzzed.scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  checkSolution(engine, live, fuzzed, 0);
  if (!fuzzed.moves) return;
  const SceneChange change = live.changeToFrame(1);
  live.apply(change);
  engine.update(live, change);
  const DynamicScene fresh(fuzzed.scene, 1);
  DiscontinuityMeshEngine scratch;
  scratch.build(fresh);
  if (const auto difference =
          firstDifference(buildIrradianceMesh(engine), buildIrradianceMesh(scratch)))
    reportFinding("frame 1 updated differs from frame 1 built from scratch: " + *difference);
  checkSolution(engine, live, fuzzed, 1);
}

}  // namespace
}  // namespace penumbra::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra;
  using namespace penumbra::fuzz;
  FuzzInput in(data, size);
  FuzzedScene fuzzed = makeFuzzedScene(in);
  // What loadScene does after reading a file.
  removeRepeatedVertices(fuzzed.scene);
  if (!succeedsOrRejects(fuzzed.scene.sourcePath, [&] { validateScene(fuzzed.scene); })) return 0;
  // Scenes farther from the origin than the engine can resolve are refused by it (InputError,
  // exit 2 from the CLI): not interesting either.
  if (!DiscontinuityMeshEngine::resolves(reachBounds(fuzzed.scene))) {
    noteOutcome("refused: too far from the origin for its size");
    return 0;
  }
  noteOutcome("accepted: " + std::to_string(fuzzed.scene.polygonCount()) + " polygons" +
              (fuzzed.moves ? ", moving" : ""));
  if (const char* dump = dumpDirectory())
    std::ofstream(std::string(dump) + "/scene.json") << sceneToJson(fuzzed.scene);
  try {
    run(fuzzed);
  } catch (const std::exception& e) {
    reportFinding("the engine threw on a valid scene: " + describe(e));
  }
  return 0;
}
