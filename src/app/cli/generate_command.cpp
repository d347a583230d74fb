// `penumbra generate --polygons N -o SCENE.json`: scenes of any size for scaling runs;
// `--disc N` / `--cylinder N`: the many-vertex stress scenes (tessellated_solid_scene.h).

#include <cstdio>

#include "commands.h"
#include "penumbra/base/output_file.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/tessellated_solid_scene.h"

namespace penumbra::cli {

int runGenerate(const GenerateOptions& options, const CommonOptions& common) {
  if (options.disc > 0 || options.cylinder > 0) {
    const std::string json =
        tessellatedSolidSceneJson({.sides = options.disc > 0 ? options.disc : options.cylinder,
                                   .cylinder = options.cylinder > 0});
    writeOutputFile(options.output, [&](std::ostream& out) { out << json; });
    if (!common.quiet) std::fprintf(stderr, "wrote %s\n", options.output.c_str());
    return kOk;
  }
  SceneGeneratorOptions generator;
  generator.targetPolygons = options.polygons;
  generator.seed = options.seed;
  generator.frames = options.frames;
  generator.movingBoxes = options.movingBoxes;
  const std::string json = generateSceneJson(generator);
  // Whole or not at all; a failure (exit 2) names the file.
  writeOutputFile(options.output, [&](std::ostream& out) { out << json; });
  if (!common.quiet) std::fprintf(stderr, "wrote %s\n", options.output.c_str());
  return kOk;
}

}  // namespace penumbra::cli
