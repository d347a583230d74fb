#pragma once
// The verbs of `penumbra` (DESIGN.md §6). Each returns the process exit code; InputError and
// UsageError propagate to main, which maps them to exit codes 2 and 1. Engine settings are the
// engines' own option structs, bound to the command line as they are: each default is declared
// once, in the engine.

#include <optional>
#include <stdexcept>
#include <string>

#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/shadow_volume_renderer.h"

namespace penumbra::cli {

enum ExitCode { kOk = 0, kUsage = 1, kBadInput = 2, kVerificationFailed = 3 };

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CommonOptions {
  bool quiet = false;
  int threads = 0;  // 0: all hardware threads
};

// A command's radiosity options with the global --threads (the solution does not depend on it).
inline RadiosityOptions withThreads(RadiosityOptions options, const CommonOptions& common) {
  options.threads = common.threads;
  return options;
}

// The Galerkin core (probe and render --method galerkin) takes the radiosity options it shares:
// the tolerance, the budget and the global --threads.
inline GalerkinOptions galerkinOptions(const RadiosityOptions& options,
                                       const CommonOptions& common) {
  GalerkinOptions galerkin = galerkinOptionsFrom(options);
  galerkin.threads = common.threads;
  return galerkin;
}

struct InfoOptions {
  std::string scene;
  std::optional<int> frame;
  bool json = false;
};
int runInfo(const InfoOptions& options, const CommonOptions& common);

struct ProbeOptions {
  std::string scene;
  std::string points;
  int frame = 0;
  std::string method = "reference";
  bool full = false;   // build frame K from scratch instead of updating from frame 0
  std::string report;  // JSON: how the points were answered (dm: by the mesh or at the point)
  MonteCarloOptions monteCarlo;
  bool withError = false;
  RadiosityOptions radiosity;
};
int runProbe(const ProbeOptions& options, const CommonOptions& common);

struct RenderOptions {
  std::string scene;
  int frame = 0;
  std::string method;
  std::string output;
  std::string size;  // WxH, empty: the scene camera's
  int samplesPerPixel = 1;
  // volumes: jittered point lights per area light (the renderer's default: the centroid)
  int lightSamples = ShadowVolumeRenderOptions{}.lightSamples;
  double exposure = 0;  // 0: automatic
  std::string exr;      // optional raw irradiance output
  RadiosityOptions radiosity;
  bool edges = false;  // dm: draw the discontinuity edges over the image
  std::string frames;  // dm: A:B, one strip of these frames reached by updates (empty: --frame)
};
int runRender(const RenderOptions& options, const CommonOptions& common);

struct RadiosityCommandOptions {
  std::string scene;
  std::string frames;  // A:B, empty: all frames
  std::string update = "full";
  // hierarchical | galerkin. Empty: galerkin where the line-space update or its shaft policy is
  // asked for (DESIGN §6's `radiosity SCENE --update linespace|verify`; only it has them), else
  // hierarchical.
  std::string solver;
  RadiosityOptions radiosity;
  double frameBudgetMs = 0;  // --update linespace: GalerkinOptions::frameBudgetSeconds
  std::string shafts;        // all | managed (GalerkinOptions::shafts); empty: the solver's own
  std::string report;
};
int runRadiosity(const RadiosityCommandOptions& options, const CommonOptions& common);

struct ShadowsOptions {
  std::string scene;
  std::string frames;  // A:B, empty: all frames
  std::string mode = "incremental";
  std::string report;
  std::string outDirectory;  // a PLY of the irradiance mesh per frame
  DmOptions dm;
};
int runShadows(const ShadowsOptions& options, const CommonOptions& common);

struct GenerateOptions {
  int polygons = 1000;
  std::uint64_t seed = 1;
  int frames = 4;
  int movingBoxes = 1;
  int disc = 0;      // instead of a room: a disc of this many vertices over a floor
  int cylinder = 0;  // ... or a closed cylinder of this many sides
  std::string output;
};
int runGenerate(const GenerateOptions& options, const CommonOptions& common);

}  // namespace penumbra::cli
