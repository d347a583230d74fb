// Fuzz target: a bare Wavefront OBJ scene with its MTL (loadScene on a .obj: OBJ statements,
// usemtl names resolved against the MTL's Kd and Ke, faces as polygons), loaded as every front end
// loads it (scene_file_check.h). The input is split at the first kMtlSeparator: what comes before
// is scene.obj, what comes after is scene.mtl beside it (no separator: no MTL file), so that a
// seed's `mtllib scene.mtl` reaches the MTL parser.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_temp_dir.h"
#include "scene_file_check.h"

namespace {

constexpr std::string_view kMtlSeparator = "\n%%MTL%%\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using penumbra::fuzz::FuzzTempDir;
  const FuzzTempDir& dir = FuzzTempDir::instance();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::string path = dir.write("scene.obj", dir.splitOff(input, kMtlSeparator, "scene.mtl"));
  penumbra::fuzz::checkSceneFile(path, dir.directory());
  return 0;
}
