// penumbra: the command-line front end (DESIGN.md §6). Exit codes: 0 ok, 1 usage, 2 bad input,
// 3 verification failed.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "commands.h"
#include "penumbra/base/input_error.h"

using namespace penumbra::cli;

namespace {

// A finite number above zero (CLI::PositiveNumber lets NaN through: NaN <= 0 is false).
const CLI::Validator kPositiveFinite(
    [](std::string& text) {
      double value = 0;
      if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || !(value > 0))
        return std::string("must be a finite number above 0, got '") + text + "'";
      return std::string();
    },
    "POSITIVE");

// The radiosity solver's budget on what refinement creates (RadiosityOptions::maxLinks). A
// number past the range (which CLI11 would saturate to the largest long long) is refused.
constexpr long long kLargestBudget = 1'000'000'000'000;
void addRadiosityBudget(CLI::App& command, penumbra::RadiosityOptions& options) {
  command
      .add_option("--max-links", options.maxLinks,
                  "Radiosity: most links refinement may create (a finer tolerance stops with "
                  "an error naming it)")
      ->capture_default_str()
      ->check(CLI::Range(1LL, kLargestBudget));
  command
      .add_option("--max-elements", options.maxElements,
                  "Radiosity: most elements refinement may create")
      ->capture_default_str()
      ->check(CLI::Range(1LL, kLargestBudget));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Penumbra: lighting that stays correct while objects move"};
  app.require_subcommand(1);
  // Global options are accepted after the verb too: a subcommand hands what it does not know to
  // the main parser (set before the subcommands are added, which inherit it).
  app.fallthrough();
  CommonOptions common;
  app.add_flag("-q,--quiet", common.quiet, "No progress output on stderr");
  app.add_option("--threads", common.threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);

  InfoOptions info;
  CLI::App* infoCommand = app.add_subcommand("info", "Counts, bounds and closedness of a scene");
  infoCommand->add_option("scene", info.scene, "Scene file (.json, .obj, .gltf, .glb)")->required();
  infoCommand->add_option("--frame", info.frame, "Frame whose bounds to print");
  infoCommand->add_flag("--json", info.json, "Print JSON instead of text");

  ProbeOptions probe;
  CLI::App* probeCommand = app.add_subcommand("probe", "Direct irradiance at points, as CSV");
  probeCommand->add_option("scene", probe.scene, "Scene file")->required();
  probeCommand->add_option("--points", probe.points, "Points file: x y z nx ny nz per line")
      ->required();
  probeCommand->add_option("--frame", probe.frame, "Frame of the scene's motion");
  probeCommand->add_option("--method", probe.method,
                           "reference | montecarlo | dm | radiosity | galerkin | combined");
  probeCommand->add_flag("--full", probe.full, "Recompute the frame from scratch (no update)");
  probeCommand->add_option("--report", probe.report,
                           "Write JSON: points, seconds, and for dm how each was answered "
                           "(answered_by_mesh, answered_at_point and why)");
  probeCommand
      ->add_option("--samples", probe.monteCarlo.samplesPerLightPerBatch,
                   "Monte Carlo: light samples per light per batch")
      ->check(CLI::PositiveNumber);
  probeCommand
      ->add_option("--batches", probe.monteCarlo.batches,
                   "Monte Carlo: independent batches for the standard error")
      ->check(CLI::Range(2, 1 << 20));
  probeCommand->add_option("--seed", probe.monteCarlo.seed, "Monte Carlo: random seed");
  probeCommand->add_flag("--with-error", probe.withError,
                         "Monte Carlo: add r_stderr,g_stderr,b_stderr columns");

  RenderOptions render;
  CLI::App* renderCommand = app.add_subcommand("render", "Render an image of a frame");
  renderCommand->add_option("scene", render.scene, "Scene file")->required();
  renderCommand->add_option("--frame", render.frame, "Frame of the scene's motion");
  renderCommand
      ->add_option("--method", render.method,
                   "raytrace | dm | radiosity | galerkin | combined | volumes")
      ->required();
  renderCommand->add_option("-o,--output", render.output, "Output PNG")->required();
  renderCommand->add_option("--size", render.size, "WxH (default: the scene camera's)");
  renderCommand->add_option("--spp", render.samplesPerPixel, "Samples per pixel (antialiasing)")
      ->check(CLI::Range(1, 4096));
  renderCommand
      ->add_option("--light-samples", render.lightSamples,
                   "volumes: stratified point lights per area light (1: its centroid)")
      ->check(CLI::Range(1, 65536));
  renderCommand->add_option("--exposure", render.exposure, "Exposure (default: automatic)")
      ->check(CLI::NonNegativeNumber);
  renderCommand->add_option("--exr", render.exr, "Also write the raw irradiance as OpenEXR");
  renderCommand->add_flag("--edges", render.edges, "dm: draw the discontinuity edges over it");
  renderCommand->add_option("--frames", render.frames,
                            "dm: frames A:B side by side in one strip, each reached by updating "
                            "the engine (per-frame times printed)");

  probeCommand
      ->add_option("--tolerance", probe.radiosity.tolerance, "Radiosity: refinement tolerance")
      ->capture_default_str()
      ->check(kPositiveFinite);
  renderCommand
      ->add_option("--tolerance", render.radiosity.tolerance, "Radiosity: refinement tolerance")
      ->capture_default_str()
      ->check(kPositiveFinite);
  for (auto [command, options] :
       {std::pair{probeCommand, &probe.radiosity}, std::pair{renderCommand, &render.radiosity}})
    addRadiosityBudget(*command, *options);

  RadiosityCommandOptions radiosity;
  CLI::App* radiosityCommand =
      app.add_subcommand("radiosity", "Hierarchical radiosity over frames, with a JSON report");
  radiosityCommand->add_option("scene", radiosity.scene, "Scene file")->required();
  radiosityCommand->add_option("--frames", radiosity.frames, "Frames A:B (default: all)");
  radiosityCommand
      ->add_option("--update", radiosity.update,
                   "full | linespace | verify (the line-space update: --solver galerkin's, "
                   "which linespace and verify choose when --solver is not given)")
      ->capture_default_str();
  radiosityCommand->add_option("--solver", radiosity.solver,
                               "hierarchical (with a final gather; the default with --update full "
                               "and no --shafts) | galerkin (linear elements)");
  radiosityCommand->add_option("--tolerance", radiosity.radiosity.tolerance, "Refinement tolerance")
      ->capture_default_str()
      ->check(kPositiveFinite);
  addRadiosityBudget(*radiosityCommand, radiosity.radiosity);
  radiosityCommand
      ->add_option("--frame-budget", radiosity.frameBudgetMs,
                   "--update linespace: milliseconds per update past which links are no longer "
                   "split (later updates split them); frame-rate control")
      ->check(kPositiveFinite);
  radiosityCommand->add_option(
      "--shafts", radiosity.shafts,
      "all | managed (default for --solver galerkin): which pairs keep their shafts' occluder "
      "candidates between updates; managed makes them on demand and ahead of moving objects, "
      "and collects old ones (results are the same)");
  radiosityCommand->add_option("--report", radiosity.report, "Write statistics as JSON");

  ShadowsOptions shadows;
  CLI::App* shadowsCommand = app.add_subcommand(
      "shadows", "Exact soft shadows (discontinuity meshing) over frames, with a JSON report");
  shadowsCommand->add_option("scene", shadows.scene, "Scene file")->required();
  shadowsCommand->add_option("--frames", shadows.frames, "Frames A:B (default: all)");
  shadowsCommand
      ->add_option("--mode", shadows.mode,
                   "incremental (build the first frame, update through the others) | full "
                   "(every frame from scratch) | verify (both, compared bit for bit; exit 3 on a "
                   "difference)")
      ->check(CLI::IsMember({"incremental", "full", "verify"}))
      ->capture_default_str();
  shadowsCommand->add_option("--report", shadows.report, "Write statistics as JSON");
  shadowsCommand->add_flag_callback(
      "--no-eee", [&shadows] { shadows.dm.eeeSurfaces = false; },
      "Skip EEE surfaces (much faster in cluttered scenes; not exact across "
      "EEE events)");
  shadowsCommand->add_option("--out", shadows.outDirectory,
                             "Write the irradiance mesh of each frame as PLY into this folder");

  GenerateOptions generate;
  CLI::App* generateCommand = app.add_subcommand(
      "generate", "Write a furnished room of about N polygons with a moving box");
  generateCommand->add_option("--polygons", generate.polygons, "Target polygon count")
      ->check(CLI::Range(50, 10000000));
  generateCommand->add_option("--seed", generate.seed, "Random seed");
  generateCommand->add_option("--frames", generate.frames, "Keyframes of the moving box")
      ->check(CLI::Range(1, 100000));
  generateCommand->add_option("--moving-boxes", generate.movingBoxes, "Boxes moving above the desk")
      ->check(CLI::Range(1, 4));
  CLI::Option* disc =
      generateCommand
          ->add_option("--disc", generate.disc,
                       "Instead of a room: a disc of N vertices floating over a floor under a "
                       "square light (the stress case for polygons of many vertices)")
          ->check(CLI::Range(3, 100000));
  generateCommand
      ->add_option("--cylinder", generate.cylinder,
                   "Instead of a room: a closed cylinder of N sides over a floor")
      ->check(CLI::Range(3, 100000))
      ->excludes(disc);
  generateCommand->add_option("-o,--output", generate.output, "Output scene JSON")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kUsage;
  }

  try {
    if (*infoCommand) return runInfo(info, common);
    if (*probeCommand) return runProbe(probe, common);
    if (*renderCommand) return runRender(render, common);
    if (*generateCommand) return runGenerate(generate, common);
    if (*radiosityCommand) return runRadiosity(radiosity, common);
    if (*shadowsCommand) return runShadows(shadows, common);
  } catch (const penumbra::InputError& e) {
    std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    return kBadInput;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "penumbra: usage error: %s\n", e.what());
    return kUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra: failed: %s\n", e.what());
    return kBadInput;
  }
  return kUsage;
}
