#include "penumbra/scene/scene_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <numbers>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/posed_scene.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

const char* kRoomObj = R"(# a floor and a wall, with materials from JSON and MTL
mtllib room.mtl
v 0 0 0
v 4 0 0
v 4 0 4
v 0 0 4
v 0 3 0
v 4 3 0
o floor
usemtl white
f 1 4 3 2
o wall
usemtl brick
f 1 2 6 5
)";
const char* kRoomMtl = R"(newmtl brick
Kd 0.6 0.3 0.2
Ke 0 0 0
)";

std::string sceneJson(const std::string& objects, const std::string& extra = "") {
  return R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.7, 0.7, 0.7] },
                 "lamp": { "reflectance": [0, 0, 0], "emission": [10, 10, 10] } },
  "objects": [ )" +
         objects + " ]" + extra + " }";
}

const std::string kLamp =
    R"({ "name": "lamp", "material": "lamp", "polygons": [ [[1,2.9,1],[1,2.9,2],[2,2.9,2],[2,2.9,1]] ] })";

// Expects loadScene to throw an InputError whose message contains every fragment.
void expectInputError(const std::string& path, std::initializer_list<std::string> fragments) {
  try {
    loadScene(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    for (const std::string& f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "message '" << e.what() << "' lacks '" << f << "'";
  }
}

TEST(JsonScene, LoadsObjWithJsonAndMtlMaterials) {
  test::TempDir dir;
  dir.write("room.obj", kRoomObj);
  dir.write("room.mtl", kRoomMtl);
  const std::string path = dir.write(
      "scene.json", sceneJson(kLamp + R"(, { "name": "room", "obj": "room.obj" })",
                              R"(, "camera": { "eye": [2, 1.5, 8], "target": [2, 1, 0] })"));
  const Scene scene = loadScene(path);
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.polygonCount(), 3);
  const SceneObject& room = scene.objects[1];
  EXPECT_EQ(scene.materials[room.polygonMaterial[0]].name, "white");  // JSON material
  EXPECT_EQ(scene.materials[room.polygonMaterial[1]].name, "brick");  // MTL material
  const Rgb brick = scene.materials[room.polygonMaterial[1]].reflectance;
  EXPECT_NEAR(brick.r, 0.6, 1e-15);  // tinyobjloader's MTL number parser may be 1 ulp off
  EXPECT_NEAR(brick.g, 0.3, 1e-15);
  EXPECT_NEAR(brick.b, 0.2, 1e-15);
  EXPECT_NE(room.polygonOrigin[1].find("room.obj:14"), std::string::npos);
  ASSERT_TRUE(scene.camera);
  EXPECT_EQ(scene.camera->eye, (Vec3{2, 1.5, 8}));
  const PosedScene posed = poseAt(scene, 0);
  EXPECT_EQ(posed.lights, std::vector<PolygonId>{0});
  EXPECT_EQ(posed.polygons[1].plane.normal, (Vec3{0, 1, 0}));  // floor faces up
}

TEST(JsonScene, TransformIsTranslateRotateScale) {
  test::TempDir dir;
  const std::string path = dir.write("scene.json", sceneJson(R"({ "material": "white",
      "polygons": [ [[1,0,0],[0,1,0],[0,0,1]] ],
      "transform": { "translate": [10, 0, 0], "rotate": { "axis": [0, 0, 1], "degrees": 90 },
                     "scale": [2, 2, 2] } })"));
  const PosedScene posed = poseAt(loadScene(path), 0);
  const Vec3 p = posed.polygons[0].vertices[0];  // (1,0,0) -> (2,0,0) -> (0,2,0) -> (10,2,0)
  EXPECT_NEAR(p.x, 10, 1e-14);
  EXPECT_NEAR(p.y, 2, 1e-14);
  EXPECT_NEAR(p.z, 0, 1e-14);
}

TEST(JsonScene, MotionInterpolatesAndHoldsEnds) {
  test::TempDir dir;
  const std::string path = dir.write("scene.json", sceneJson(R"({ "material": "white",
      "polygons": [ [[1,0,0],[0,1,0],[0,0,1]] ],
      "motion": [ { "frame": 1, "translate": [0, 0, 0] },
                  { "frame": 3, "translate": [4, 0, 0], "rotate": { "axis": [0, 1, 0], "degrees": 90 } } ] })"));
  const Scene scene = loadScene(path);
  EXPECT_EQ(scene.frames, 4);
  EXPECT_EQ(scene.dynamicObjectCount(), 1);
  const auto vertexAt = [&](double frame) { return poseAt(scene, frame).polygons[0].vertices[0]; };
  EXPECT_EQ(vertexAt(0), (Vec3{1, 0, 0}));  // before the first keyframe: the first holds
  const Vec3 mid = vertexAt(2);             // half-way: translate 2, rotate 45° about y
  EXPECT_NEAR(mid.x, 2 + std::cos(std::numbers::pi / 4), 1e-14);
  EXPECT_NEAR(mid.z, -std::sin(std::numbers::pi / 4), 1e-14);
  const Vec3 end = vertexAt(7);  // after the last keyframe: the last holds
  EXPECT_NEAR(end.x, 4, 1e-14);
  EXPECT_NEAR(end.z, -1, 1e-14);
}

TEST(JsonSceneErrors, EachBadInputIsNamed) {
  test::TempDir dir;
  const auto scene = [&](const std::string& name, const std::string& objects,
                         const std::string& extra = "") {
    return dir.write(name, sceneJson(objects, extra));
  };
  expectInputError(dir.path("missing.json"), {"missing.json", "cannot open"});
  expectInputError(dir.write("malformed.json", "{ \"penumbra\": 1,\n  \"objects\": [ }"),
                   {"malformed.json:2:", "malformed JSON"});
  expectInputError(scene("typo.json", kLamp, R"(, "camra": {})"),
                   {"typo.json", "unknown key 'camra'"});
  expectInputError(scene("objtypo.json", R"({ "material": "white", "polygon": [] })"),
                   {"/objects/0", "unknown key 'polygon'"});
  expectInputError(scene("unknownmat.json", R"({ "material": "chrome", "polygons": [] })"),
                   {"/objects/0/material", "unknown material 'chrome'"});
  expectInputError(
      scene("nonplanar.json",
            R"({ "material": "white", "polygons": [ [[0,0,0],[1,0,0],[1,1,0.3],[0,1,0]] ] })"),
      {"nonplanar.json: /objects/0/polygons/0", "non-planar"});
  expectInputError(
      scene("two.json", R"({ "material": "white", "polygons": [ [[0,0,0],[1,0,0],[1,0,0]] ] })"),
      {"/objects/0/polygons/0", "fewer than 3 distinct vertices"});
  expectInputError(
      scene("inf.json",
            R"({ "material": "white", "polygons": [ [[0,0,0],[1e999,0,0],[0,1,0]] ] })"),
      {"inf.json", "number overflow"});
  expectInputError(scene("string.json",
                         R"({ "material": "white", "polygons": [ [[0,0,0],["a",0,0],[0,1,0]] ] })"),
                   {"/objects/0/polygons/0/1/0", "expected a number"});
  expectInputError(scene("both.json", R"({ "material": "white", "obj": "x.obj", "polygons": [] })"),
                   {"/objects/0", "exactly one of"});
  expectInputError(
      scene("keys.json", R"({ "material": "white", "polygons": [ [[0,0,0],[1,0,0],[0,1,0]] ],
      "motion": [ { "frame": 2 }, { "frame": 1 } ] })"),
      {"/objects/0/motion/1/frame", "strictly increasing"});
  expectInputError(
      scene("scale.json", R"({ "material": "white", "polygons": [ [[0,0,0],[1,0,0],[0,1,0]] ],
      "transform": { "scale": [1, 0, 1] } })"),
      {"/objects/0/transform/scale", "non-zero"});
  expectInputError(dir.write("version.json", R"({ "penumbra": 2, "objects": [] })"),
                   {"version.json", "\"penumbra\": 1"});
  expectInputError(dir.write("empty.json", R"({ "penumbra": 1, "objects": [] })"),
                   {"empty.json: /objects", "no polygons"});
  expectInputError(
      dir.write("reflect.json",
                R"({ "penumbra": 1, "materials": { "m": { "reflectance": [1.2, 0, 0] } },
      "objects": [] })"),
      {"/materials/m/reflectance", "[0, 1]"});
  expectInputError(dir.path("scene.txt"), {"scene.txt", "unknown scene file type"});
}

TEST(ObjErrors, EachBadInputNamesTheLine) {
  test::TempDir dir;
  const auto objScene = [&](const std::string& name, const std::string& obj) {
    dir.write(name + ".obj", obj);
    return dir.write(name + ".json",
                     sceneJson(R"({ "material": "white", "obj": ")" + name + R"(.obj" })"));
  };
  expectInputError(objScene("nan", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"),
                   {"nan.obj:3", "finite"});
  expectInputError(objScene("range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
                   {"range.obj:4", "vertex 7"});
  expectInputError(objScene("short", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
                   {"short.obj:4", "fewer than 3"});
  expectInputError(objScene("bent", "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\n\nf 1 2 3 4\n"),
                   {"bent.obj:6", "non-planar"});
  expectInputError(objScene("nomat", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl gold\nf 1 2 3\n"),
                   {"nomat.obj:5", "unknown material 'gold'"});
  expectInputError(
      dir.write("nofile.json", sceneJson(R"({ "material": "white", "obj": "absent.obj" })")),
      {"nofile.json: /objects/0/obj", "absent.obj", "cannot open"});
  expectInputError(objScene("mtl", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                   {"mtl.obj", "MTL"});
}

// A comment may end a vertex or face statement; the faces and their lines are those of the
// same file without the comments, and nothing is left in the temporary folder.
TEST(ObjScene, CommentsAfterStatements) {
  test::TempDir dir;
  dir.write("room.mtl", kRoomMtl);
  const std::string path = dir.write("commented.obj", R"(mtllib room.mtl
usemtl brick
v 0 0 0
v 1 0 0 # second
v 1 1 0
v 0 1 0#fourth
f 1 2 3 4 # the lid
f 1 2 4#x
)");
  const Scene scene = loadScene(path);
  ASSERT_EQ(scene.polygonCount(), 2);
  const SceneObject& o = scene.objects[0];
  EXPECT_EQ(o.polygons[0].size(), 4u);
  EXPECT_EQ(o.polygons[1].size(), 3u);
  EXPECT_EQ(o.polygons[0][1], (Vec3{1, 0, 0}));
  EXPECT_NE(o.polygonOrigin[0].find("commented.obj:7"), std::string::npos) << o.polygonOrigin[0];
  EXPECT_NE(o.polygonOrigin[1].find("commented.obj:8"), std::string::npos) << o.polygonOrigin[1];
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::temp_directory_path()))
    EXPECT_EQ(entry.path().filename().string().find("penumbra-" + std::to_string(::getpid())),
              std::string::npos)
        << entry.path();
}

TEST(ObjScene, FaceLinesFollowGroupsAndMaterials) {
  test::TempDir dir;
  dir.write("room.mtl", kRoomMtl);
  // Faces interleaved across objects and materials: each must keep its own line and material.
  const std::string path = dir.write("direct.obj", R"(mtllib room.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
o a
usemtl brick
f 1 2 3
o b
f 1 3 4
usemtl brick
f 1 2 4
)");
  const Scene scene = loadScene(path);
  ASSERT_EQ(scene.polygonCount(), 3);
  const SceneObject& o = scene.objects[0];
  EXPECT_NE(o.polygonOrigin[0].find("direct.obj:8"), std::string::npos);
  EXPECT_NE(o.polygonOrigin[1].find("direct.obj:10"), std::string::npos);
  EXPECT_NE(o.polygonOrigin[2].find("direct.obj:12"), std::string::npos);
  EXPECT_EQ(o.polygons[1][2], (Vec3{0, 1, 0}));
}

}  // namespace
}  // namespace penumbra
