// Fuzz target: Penumbra's JSON scene files (DESIGN.md §4), loaded as every front end loads them
// (scene_file_check.h). The input is the JSON file. Beside it lie a fixed, valid box.obj and its
// box.mtl, so that objects read from OBJ files ("obj": "box.obj"), their usemtl names resolved
// against the JSON materials and the MTL, and transforms and motion of such objects are reached
// from the JSON alone (the OBJ reader itself has its own target, obj_scene).

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_temp_dir.h"
#include "scene_file_check.h"

namespace {

// A unit cube: its bottom face names no material (the object's "material" must give one), the
// others use the MTL's materials, one of them emissive; one face ends in a comment (the reader's
// uncommented-copy path).
constexpr std::string_view kBoxObj =
    "mtllib box.mtl\n"
    "o box\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\n"
    "usemtl boxwhite\n"
    "f 5 6 7 8 # top\n"
    "f 1 2 6 5\n"
    "f 2 3 7 6\n"
    "usemtl boxlamp\n"
    "f 3 4 8 7\n"
    "f 4 1 5 8\n";
constexpr std::string_view kBoxMtl =
    "newmtl boxwhite\nKd 0.7 0.7 0.7\n"
    "newmtl boxlamp\nKd 0 0 0\nKe 5 5 5\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using penumbra::fuzz::FuzzTempDir;
  const FuzzTempDir& dir = FuzzTempDir::instance();
  // Loading never writes beside the scene, so the fixed files are written once.
  static const bool written = (dir.write("box.obj", kBoxObj), dir.write("box.mtl", kBoxMtl), true);
  (void)written;
  const std::string path =
      dir.write("scene.json", std::string_view(reinterpret_cast<const char*>(data), size));
  penumbra::fuzz::checkSceneFile(path, dir.directory());
  return 0;
}
