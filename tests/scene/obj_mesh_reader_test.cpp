// The OBJ reader's pre-scan separates fields as tinyobjloader does (spaces and tabs), so that both
// count the same vertices: a form feed after `v` made a vertex for one and not the other, and a
// face's negative index then escaped as std::out_of_range. Found by fuzz/obj_scene_fuzzer
// (fuzz/README.md).

#include "penumbra/scene/obj_mesh_reader.h"

#include <gtest/gtest.h>

#include "penumbra/base/input_error.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

TEST(ObjMeshReader, FormFeedAfterVIsNoVertex) {
  test::TempDir dir;
  const std::string path = dir.write("ff.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv\f0 1 0\nf -4 3 4\n");
  try {
    readObjMesh(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path + ":5");
    EXPECT_NE(e.problem().find("only 3 vertices"), std::string::npos) << e.what();
  }
}

// Tabs separate fields for both readers, and a CR LF line ending is no part of the last field.
TEST(ObjMeshReader, TabsAndCrLfSeparateFields) {
  test::TempDir dir;
  const std::string path =
      dir.write("tabs.obj", "v\t0\t0\t0\r\nv 1\t0 0\r\n\tv 0 1 0\r\nf\t-3 -2\t-1\r\n");
  const ObjMesh mesh = readObjMesh(path);
  ASSERT_EQ(mesh.faces.size(), 1u);
  EXPECT_EQ(mesh.faces[0].line, 4);
  EXPECT_EQ(mesh.faces[0].vertices, (Polygon3{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

}  // namespace
}  // namespace penumbra
