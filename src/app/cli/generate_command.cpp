// `penumbra generate --polygons N -o SCENE.json`: scenes of any size for scaling runs.

#include <cstdio>
#include <fstream>

#include "commands.h"
#include "penumbra/scene/scene_generator.h"

namespace penumbra::cli {

int runGenerate(const GenerateOptions& options, const CommonOptions& common) {
  SceneGeneratorOptions generator;
  generator.targetPolygons = options.polygons;
  generator.seed = options.seed;
  generator.frames = options.frames;
  const std::string json = generateSceneJson(generator);
  std::ofstream out(options.output);
  if (!out) throw UsageError("cannot write " + options.output);
  out << json;
  if (!out) throw UsageError("failed writing " + options.output);
  if (!common.quiet) std::fprintf(stderr, "wrote %s\n", options.output.c_str());
  return kOk;
}

}  // namespace penumbra::cli
