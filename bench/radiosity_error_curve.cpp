// Radiosity's error curve: for a range of tolerances, the solve time, elements, links and the
// median and 95th percentile of the relative error of the total irradiance at open receiver
// points (of the combined solution with --combined: exact direct light from the discontinuity
// mesh, radiosity's indirect light), against an independent path tracer
// (lighting/path_traced_reference.h with sampled direct light: its visibility is its own shadow
// rays, none of the polygon clipping the solver and the discontinuity mesh use).
//
// Usage: radiosity_error_curve [--points N] [--paths P] [--threads T] [--tolerances a,b,...]
//                              [--no-final-gather] [--combined] [--path-tracer]
//                              [--visibility-rays N]
//                              [--galerkin [--repeat N] [--hidden-weight W]
//                                          [--whole-hidden-weight W]]
//                              [--gather-rays N] [--worst N] [--by-polygon]
//                              [--degenerate-rooms A:B [--inside-out] [--moving]]
//                              [scene.json ...]
// --galerkin: the Galerkin core (radiosity/galerkin/) instead of the hierarchical solver with its
// final gather; --repeat N solves each tolerance N times and reports the fastest; --hidden-weight
// sets how many times a link's partly hidden transfer counts in its oracle, --whole-hidden-weight
// that of a pair found wholly hidden; --worst N lists the N points with the largest errors under
// each row (either solver); --by-polygon each receiver's mean signed indirect error (Galerkin).
// --degenerate-rooms A:B: also the generated rooms of seeds A..B (degenerate_rooms.h: coincident
// and touching polygons, two-sided cards, boxes against walls; --inside-out turns the boxes'
// faces inwards, --moving gives one occluder three moves), written to the working folder as
// degenerate-room-SEED[-inside-out][-moving].json for the CLI's verify modes.
// --path-tracer: instead of solving, the path tracer's own median and p95 error and cost per point
// with 16 ... 4,096 paths (what a solution must beat).
// (default: the Cornell box at 1e-2 ... 1e-4, 150 sampled points, 65,536 paths per point; the
// docs' tables use 262,144 in the Cornell box, 65,536 in the rooms).
//
// Open points: uniform by area over the receivers' front sides, minus those where the reference
// total irradiance is below 1e-3 of the points' mean (covered by a polygon in contact: relative
// error means nothing there; the sampled reference sees a polygon in contact edge-on and gives 0
// there). The reference is cached in the working folder, keyed by scene, points and paths, so the
// curve can be re-run while the solver changes.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_main.h"
#include "bench_statistics.h"
#include "degenerate_rooms.h"
#include "penumbra/base/parallel_for.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/path_traced_reference.h"
#include "penumbra/radiosity/combined_solution.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

using namespace penumbra;
using bench::percentile;

namespace {

struct Options {
  int points = 150;
  int paths = 65536;
  int threads = 1;
  bool finalGather = true;
  bool combined = false;          // CombinedSolution: exact direct (DM) + radiosity's indirect
  bool pathTracer = false;        // the path tracer's own error and cost at fewer paths instead
  bool galerkin = false;          // the Galerkin core (linear elements, no final gather) instead
  int repeat = 1;                 // Galerkin: solves per tolerance, the fastest one's time reported
  double hiddenWeight = -1;       // Galerkin: GalerkinOptions::hiddenWeight (negative: its default)
  double wholeHiddenWeight = -1;  // Galerkin: GalerkinOptions::wholeHiddenWeight (likewise)
  double directionWeight = -1;    // Galerkin: GalerkinOptions::directionWeight (likewise)
  int visibilityRays = 0;         // 0: the solver's default
  int gatherRays = 0;
  int worst = 0;           // the points with the largest errors, listed under each row
  bool byPolygon = false;  // each receiver's mean signed indirect error, under each row
  std::vector<double> tolerances{1e-2, 3e-3, 1e-3, 3e-4, 1e-4};
  std::vector<std::string> scenes;
};

struct OpenPoint {
  ReceiverPoint point;
  double reference = 0;  // total irradiance, mean of the channels
  double standardError = 0;
  double direct = 0;  // the exact direct irradiance (not cached: cheap)
};

std::string cachePath(const std::string& scene, const Options& o) {
  // The file's name and its contents: a scene edited under one name is sampled again.
  std::ostringstream contents;
  contents << std::ifstream(scene).rdbuf();
  const std::size_t key = std::hash<std::string>{}(scene + '\n' + contents.str());
  std::ostringstream name;
  name << "radiosity_reference_sampled_" << std::hex << key << std::dec << "_" << o.points << "_"
       << o.paths << ".txt";
  return name.str();
}

std::vector<OpenPoint> referencePoints(const std::string& path, const PosedScene& posed,
                                       const Options& o) {
  const std::vector<ReceiverPoint> sampled = sampleReceiverPoints(posed, o.points, 7);
  std::vector<OpenPoint> all(sampled.size());
  const std::string cache = cachePath(path, o);
  std::ifstream in(cache);
  bool cached = bool(in);
  for (size_t i = 0; i < all.size() && cached; ++i) {
    all[i].point = sampled[i];
    cached = bool(in >> all[i].reference >> all[i].standardError);
  }
  if (!cached) {
    const auto start = std::chrono::steady_clock::now();
    // Sampled direct light: the reference's visibility is its own shadow rays, none of the
    // exact reference's clipping that the solver and the discontinuity mesh use.
    const RayCaster rays(posed);
    const PathTracedReference tracer(posed, rays);
    parallelFor((long long)all.size(), 0, [&](long long i) {
      const ReceiverPoint& p = sampled[i];
      const PathTracedEstimate e = tracer.irradiance(p.p, p.n, p.receiver, o.paths, 1000 + i);
      all[i] = {p, e.total().average(), e.totalStandardError.average()};
    });
    std::ofstream out(cache);
    out.precision(17);
    for (const OpenPoint& p : all) out << p.reference << " " << p.standardError << "\n";
    std::printf("# reference: %zu points x %d paths in %.1f s (cached in %s)\n", all.size(),
                o.paths,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                cache.c_str());
  }
  const UniformGrid grid(posed);
  const ExactReference exact(posed, &grid);
  for (OpenPoint& p : all)
    p.direct = exact.irradiance(p.point.p, p.point.n, p.point.receiver).average();
  double mean = 0;
  for (const OpenPoint& p : all) mean += p.reference / double(all.size());
  std::vector<OpenPoint> open;
  for (const OpenPoint& p : all)
    if (p.reference > 1e-3 * mean) open.push_back(p);
  return open;
}

// The path tracer itself as a solver, beside the curve: at the same points, with fewer paths
// (another seed than the reference's), its median and p95 error and its cost per point, on one
// thread: what a combined or radiosity solution must beat to be worth its solve.
void pathTracerRows(const PosedScene& posed, const std::vector<OpenPoint>& points) {
  const RayCaster rays(posed);
  const PathTracedReference tracer(posed, rays);
  std::printf("%10s %9s %8s %8s\n", "paths", "us/point", "median", "p95");
  for (int paths : {16, 64, 256, 1024, 4096}) {
    std::vector<double> errors;
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < points.size(); ++i) {
      const OpenPoint& p = points[i];
      const PathTracedEstimate e =
          tracer.irradiance(p.point.p, p.point.n, p.point.receiver, paths, 77000 + i);
      errors.push_back(std::abs(e.total().average() - p.reference) / p.reference);
    }
    const double microseconds =
        1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
        double(points.size());
    std::printf("%10d %9.1f %7.2f%% %7.2f%%\n", paths, microseconds, 100 * percentile(errors, 0.5),
                100 * percentile(errors, 0.95));
    std::fflush(stdout);
  }
}

// The errors of a solution's samples at the points: the total's, and the parts of it that its
// direct and indirect terms make (each against the total, so the three are comparable).
struct PointErrors {
  std::vector<double> total, direct, indirect, signedIndirect;
  void add(const OpenPoint& p, const std::optional<RadiositySample>& sample) {
    const double d = sample ? sample->direct.average() : 0;
    const double i = sample ? sample->indirect.average() : 0;
    total.push_back(std::abs(d + i - p.reference) / p.reference);
    direct.push_back(std::abs(d - p.direct) / p.reference);
    indirect.push_back(std::abs(i - (p.reference - p.direct)) / p.reference);
    signedIndirect.push_back((i - (p.reference - p.direct)) / p.reference);
  }
};

// The points where a solution is furthest from the reference: position, receiver, both values.
void printWorst(const std::vector<OpenPoint>& points,
                const std::vector<std::optional<RadiositySample>>& samples, int worst) {
  std::vector<size_t> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto value = [&](size_t i) { return samples[i] ? samples[i]->total().average() : 0; };
  const auto error = [&](size_t i) {
    return std::abs(value(i) - points[i].reference) / points[i].reference;
  };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return error(a) > error(b); });
  for (size_t k = 0; k < std::min(order.size(), size_t(std::max(0, worst))); ++k) {
    const OpenPoint& p = points[order[k]];
    std::printf(
        "#   %+7.1f%% at (%.4f %.4f %.4f) normal (%.2f %.2f %.2f), polygon %d: %.4g against "
        "%.4g +- %.2g%% (direct %.4g)\n",
        100 * (value(order[k]) / p.reference - 1), p.point.p.x, p.point.p.y, p.point.p.z,
        p.point.n.x, p.point.n.y, p.point.n.z, int(p.point.receiver), value(order[k]), p.reference,
        100 * p.standardError / p.reference, p.direct);
  }
}

// Per receiver polygon: its points, their mean signed indirect error (of the total) and mean
// reference, so that light lost or gained on one surface shows (a median over the scene hides it).
void printByPolygon(const std::vector<OpenPoint>& points,
                    const std::vector<std::optional<RadiositySample>>& samples) {
  struct Sums {
    int count = 0;
    double signedIndirect = 0, reference = 0;
  };
  std::map<int, Sums> byPolygon;
  for (size_t i = 0; i < points.size(); ++i) {
    const OpenPoint& p = points[i];
    const double indirect = samples[i] ? samples[i]->indirect.average() : 0;
    Sums& s = byPolygon[int(p.point.receiver)];
    ++s.count;
    s.signedIndirect += (indirect - (p.reference - p.direct)) / p.reference;
    s.reference += p.reference;
  }
  for (const auto& [polygon, s] : byPolygon)
    std::printf(
        "#   polygon %3d: %3d points, mean signed indirect %+6.2f%% of the total, mean %.4g\n",
        polygon, s.count, 100 * s.signedIndirect / s.count, s.reference / s.count);
}

void galerkinRow(const DynamicScene& live, const std::vector<OpenPoint>& points, double tolerance,
                 const Options& o) {
  GalerkinOptions options;
  options.tolerance = tolerance;
  options.threads = o.threads;
  if (o.hiddenWeight >= 0) options.hiddenWeight = o.hiddenWeight;
  if (o.wholeHiddenWeight >= 0) options.wholeHiddenWeight = o.wholeHiddenWeight;
  if (o.directionWeight >= 0) options.directionWeight = o.directionWeight;
  GalerkinRadiosity solver(options);
  // Solves of a few milliseconds vary with the machine's load: the fastest of --repeat.
  double seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < o.repeat; ++run) {
    const auto start = std::chrono::steady_clock::now();
    solver.build(live);
    seconds = std::min(
        seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  PointErrors errors;
  const auto queryStart = std::chrono::steady_clock::now();
  std::vector<std::optional<RadiositySample>> samples;
  for (const OpenPoint& p : points) samples.push_back(solver.sample(p.point.p, p.point.n));
  const double queryMicroseconds =
      1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - queryStart).count() /
      double(points.size());
  for (size_t i = 0; i < points.size(); ++i) errors.add(points[i], samples[i]);
  const GalerkinStats& s = solver.stats();
  std::printf(
      "%10.0e %8d %9.4f %9lld %10lld %7.2f%% %7.2f%% %8.2f%% %8.2f%% %9.4f %9.4f %9s %9.1f\n",
      tolerance, o.threads, seconds, s.elements, s.activeLinks, 100 * percentile(errors.total, 0.5),
      100 * percentile(errors.total, 0.95), 100 * percentile(errors.direct, 0.5),
      100 * percentile(errors.indirect, 0.5), s.refineSeconds, s.solveSeconds, "-",
      queryMicroseconds);
  const Rgb emitted = solver.emittedPower(), absorbed = solver.absorbedPower();
  std::printf(
      "# median signed indirect error %.2f%% of the total; absorbed/emitted %.4f; %lld pairs, "
      "%lld rays, %lld unoccluded links, %d iterations\n",
      100 * percentile(errors.signedIndirect, 0.5), absorbed.average() / emitted.average(),
      s.pointPairs, s.visibilityRays, s.unoccludedLinks, s.iterations);
  printWorst(points, samples, o.worst);
  if (o.byPolygon) printByPolygon(points, samples);
  std::fflush(stdout);
}

void run(const std::string& path, const Options& o) {
  const PosedScene posed = poseAt(loadScene(path), 0);
  const std::vector<OpenPoint> points = referencePoints(path, posed, o);
  if (o.pathTracer) {
    std::printf("%s: the path tracer alone, %zu open points\n", path.c_str(), points.size());
    pathTracerRows(posed, points);
    return;
  }
  std::vector<double> relativeNoise;
  for (const OpenPoint& p : points) relativeNoise.push_back(p.standardError / p.reference);
  std::printf("%s: %zu open points, reference standard error median %.2f%%\n", path.c_str(),
              points.size(), 100 * percentile(relativeNoise, 0.5));
  std::printf("%10s %8s %9s %9s %10s %8s %8s %9s %9s %9s %9s %9s %9s\n", "tolerance", "threads",
              "seconds", "elements", "links", "median", "p95", "direct", "indirect", "refine",
              "solve", "gather", "us/point");
  for (double tolerance : o.tolerances) {
    RadiosityOptions options;
    options.tolerance = tolerance;
    options.finalGather = o.finalGather;
    options.threads = o.threads;
    if (o.visibilityRays > 0) options.visibilityRays = o.visibilityRays;
    if (o.gatherRays > 0) options.finalGatherRays = o.gatherRays;
    // Radiosity alone, or the combined solution (its direct part from the discontinuity mesh);
    // both on one live scene built outside the timing, as the CLI shares it between engines.
    const DynamicScene live(posed);
    if (o.galerkin) {
      galerkinRow(live, points, tolerance, o);
      continue;
    }
    RadiositySolver alone(options);
    CombinedSolution combined(options);
    const auto start = std::chrono::steady_clock::now();
    if (o.combined)
      combined.build(live);
    else
      alone.build(live);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const RadiositySolver& solver = o.combined ? combined.indirect() : alone;
    const auto sampleAt = [&](const ReceiverPoint& p) -> std::optional<RadiositySample> {
      if (!o.combined) return solver.sample(p.p, p.n);
      const std::optional<CombinedSample> c = combined.sample(p.p, p.n);
      if (!c) return std::nullopt;
      return RadiositySample{c->direct, c->indirect, {}};
    };
    const auto queryStart = std::chrono::steady_clock::now();
    std::vector<std::optional<RadiositySample>> samples;
    for (const OpenPoint& p : points) samples.push_back(sampleAt(p.point));
    const double queryMicroseconds =
        1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - queryStart).count() /
        double(points.size());
    PointErrors errors;
    for (size_t i = 0; i < points.size(); ++i) errors.add(points[i], samples[i]);
    const RadiosityStats& s = solver.stats();
    std::printf(
        "%10.0e %8d %9.3f %9lld %10lld %7.2f%% %7.2f%% %8.2f%% %8.2f%% %9.3f %9.3f %9.3f %9.1f\n",
        tolerance, o.threads, seconds, s.elements, s.activeLinks,
        100 * percentile(errors.total, 0.5), 100 * percentile(errors.total, 0.95),
        100 * percentile(errors.direct, 0.5), 100 * percentile(errors.indirect, 0.5),
        s.refineSeconds, s.solveSeconds, s.finalGatherSeconds, queryMicroseconds);
    // Issue 19's measure of a bias: the indirect part summed over the points, against the
    // reference's (its total less the exact direct part).
    double indirectSum = 0, referenceIndirectSum = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      indirectSum += samples[i] ? samples[i]->indirect.average() : 0;
      referenceIndirectSum += points[i].reference - points[i].direct;
    }
    std::printf(
        "# median signed indirect error %.2f%% of the total; indirect summed over the points "
        "%.4f of the reference's\n",
        100 * percentile(errors.signedIndirect, 0.5), indirectSum / referenceIndirectSum);
    printWorst(points, samples, o.worst);
    std::fflush(stdout);
  }
}

std::vector<double> parseList(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(std::stod(item));
  return values;
}

}  // namespace

static int benchMain(int argc, char** argv) {
  Options o;
  std::string rooms;  // --degenerate-rooms A:B
  bool insideOut = false, moving = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--points")
      o.points = std::stoi(next());
    else if (arg == "--paths")
      o.paths = std::stoi(next());
    else if (arg == "--threads")
      o.threads = std::stoi(next());
    else if (arg == "--tolerances")
      o.tolerances = parseList(next());
    else if (arg == "--no-final-gather")
      o.finalGather = false;
    else if (arg == "--combined")
      o.combined = true;
    else if (arg == "--path-tracer")
      o.pathTracer = true;
    else if (arg == "--galerkin")
      o.galerkin = true;
    else if (arg == "--repeat")
      o.repeat = std::max(1, std::stoi(next()));
    else if (arg == "--hidden-weight")
      o.hiddenWeight = std::stod(next());
    else if (arg == "--whole-hidden-weight")
      o.wholeHiddenWeight = std::stod(next());
    else if (arg == "--direction-weight")
      o.directionWeight = std::stod(next());
    else if (arg == "--visibility-rays")
      o.visibilityRays = std::stoi(next());
    else if (arg == "--gather-rays")
      o.gatherRays = std::stoi(next());
    else if (arg == "--worst")
      o.worst = std::stoi(next());
    else if (arg == "--by-polygon")
      o.byPolygon = true;
    else if (arg == "--degenerate-rooms")
      rooms = next();
    else if (arg == "--inside-out")
      insideOut = true;
    else if (arg == "--moving")
      moving = true;
    else
      o.scenes.push_back(arg);
  }
  if (!rooms.empty()) {
    // Written to the working folder (the reference cache's key is the file), named by seed.
    const size_t colon = rooms.find(':');
    const int first = std::stoi(rooms.substr(0, colon)),
              last = colon == std::string::npos ? first : std::stoi(rooms.substr(colon + 1));
    for (int seed = first; seed <= last; ++seed) {
      const std::string name = "degenerate-room-" + std::to_string(seed) +
                               (insideOut ? "-inside-out" : "") + (moving ? "-moving" : "") +
                               ".json";
      std::ofstream(name) << bench::degenerateRoomJson(std::uint64_t(seed), insideOut, moving);
      o.scenes.push_back(name);
    }
  }
  if (o.scenes.empty())
    o.scenes.push_back(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json");
  for (const std::string& scene : o.scenes) run(scene, o);
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("radiosity_error_curve", argc, argv, benchMain);
}
