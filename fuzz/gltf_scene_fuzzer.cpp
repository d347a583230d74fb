// Fuzz target: glTF 2.0 scenes (loadScene on a .gltf or .glb: meshes, node transforms, emissive
// materials, animations sampled into motion), loaded as every front end loads them
// (scene_file_check.h). An input that starts with the binary container's magic "glTF" is written
// as scene.glb, any other as scene.gltf. An input holding kBinSeparator is split there: what
// follows becomes buffer.bin beside the scene, for buffers given by an external "uri" (data URIs
// and the GLB's BIN chunk need no second file).

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_temp_dir.h"
#include "scene_file_check.h"

namespace {

constexpr std::string_view kBinSeparator = "\n%%BIN%%\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using penumbra::fuzz::FuzzTempDir;
  const FuzzTempDir& dir = FuzzTempDir::instance();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::string_view scene = dir.splitOff(input, kBinSeparator, "buffer.bin");
  // Only one of the two names exists at a time, so a relative "uri" naming the other one does not
  // see a previous input's file.
  const bool isBinary = scene.substr(0, 4) == "glTF";
  dir.remove(isBinary ? "scene.gltf" : "scene.glb");
  const std::string path = dir.write(isBinary ? "scene.glb" : "scene.gltf", scene);
  penumbra::fuzz::checkSceneFile(path, dir.directory());
  return 0;
}
