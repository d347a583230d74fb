#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kFloat = 5126;
constexpr int kUnsignedShort = 5123;
constexpr double kPi = std::numbers::pi;

void expectNear(const Vec3& actual, const Vec3& expected, double tolerance = 1e-9) {
  EXPECT_NEAR(actual.x, expected.x, tolerance) << actual << " vs " << expected;
  EXPECT_NEAR(actual.y, expected.y, tolerance) << actual << " vs " << expected;
  EXPECT_NEAR(actual.z, expected.z, tolerance) << actual << " vs " << expected;
}

// Same rotation (q and -q are equal rotations).
void expectSameRotation(const Quaternion& actual, const Quaternion& expected,
                        double tolerance = 1e-6) {
  EXPECT_NEAR(std::abs(actual.dotWith(expected)), 1.0, tolerance)
      << "(" << actual.w << ", " << actual.x << ", " << actual.y << ", " << actual.z << ") vs ("
      << expected.w << ", " << expected.x << ", " << expected.y << ", " << expected.z << ")";
}

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t chunk = uint32_t(bytes[i]) << 16 |
                           (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                           (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0);
    out += kAlphabet[(chunk >> 18) & 63];
    out += kAlphabet[(chunk >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(chunk >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
  }
  return out;
}

// Builds small glTF documents with one binary buffer, and writes them as .gltf (data URI or
// external .bin) or .glb into a directory of its own per test.
class GltfBuilder {
 public:
  GltfBuilder() {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(PENUMBRA_BINARY_DIR) / "test-tmp" / "gltf_loader" /
           (std::string(test->test_suite_name()) + "." + test->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    doc["asset"] = {{"version", "2.0"}};
  }

  template <typename T>
  int view(const std::vector<T>& values) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    const size_t offset = bin_.size();
    bin_.resize(offset + values.size() * sizeof(T));
    if (!values.empty())
      std::memcpy(bin_.data() + offset, values.data(), values.size() * sizeof(T));
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    return int(doc["bufferViews"].size()) - 1;
  }

  int accessor(int bufferView, int componentType, size_t count, const std::string& type) {
    doc["accessors"].push_back({{"bufferView", bufferView},
                                {"componentType", componentType},
                                {"count", count},
                                {"type", type}});
    return int(doc["accessors"].size()) - 1;
  }

  int floats(const std::vector<float>& values, const std::string& type) {
    const size_t components = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 2;
    return accessor(view(values), kFloat, values.size() / components, type);
  }

  int indices(const std::vector<uint16_t>& values) {
    return accessor(view(values), kUnsignedShort, values.size(), "SCALAR");
  }

  // A mesh of one primitive.
  int mesh(int positions, int indexAccessor = -1, int material = -1, int mode = 4) {
    json primitive = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
    if (indexAccessor >= 0) primitive["indices"] = indexAccessor;
    if (material >= 0) primitive["material"] = material;
    doc["meshes"].push_back({{"primitives", {primitive}}});
    return int(doc["meshes"].size()) - 1;
  }

  int node(const json& node) {
    doc["nodes"].push_back(node);
    return int(doc["nodes"].size()) - 1;
  }

  // The unit quad [0,1]^2 at z = 0, facing +z, as two indexed triangles.
  int quadMesh(int material = -1) {
    const int positions = floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3");
    return mesh(positions, indices({0, 1, 2, 0, 2, 3}), material);
  }

  void animate(int node, const std::string& path, const std::vector<float>& times,
               const std::vector<float>& values, const std::string& interpolation = "LINEAR") {
    const int input = floats(times, "SCALAR");
    const int output = floats(values, path == "rotation" ? "VEC4" : "VEC3");
    if (!doc.contains("animations")) doc["animations"].push_back({{"channels", json::array()}});
    json& animation = doc["animations"][0];
    animation["samplers"].push_back(
        {{"input", input}, {"output", output}, {"interpolation", interpolation}});
    animation["channels"].push_back({{"sampler", animation["samplers"].size() - 1},
                                     {"target", {{"node", node}, {"path", path}}}});
  }

  // Root nodes (those nobody lists as a child) form scene 0, unless a test set scenes itself.
  void finishScenes() {
    if (doc.contains("scenes") || !doc.contains("nodes")) return;
    std::vector<bool> isChild(doc["nodes"].size(), false);
    for (const json& n : doc["nodes"])
      if (n.contains("children"))
        for (const json& c : n["children"]) isChild[c.get<size_t>()] = true;
    json roots = json::array();
    for (size_t i = 0; i < isChild.size(); ++i)
      if (!isChild[i]) roots.push_back(i);
    doc["scenes"] = {{{"nodes", roots}}};
    doc["scene"] = 0;
  }

  std::string writeGltf(const std::string& name = "scene.gltf") {
    finishScenes();
    json out = doc;
    out["buffers"] = {{{"byteLength", bin_.size()},
                       {"uri", "data:application/octet-stream;base64," + base64(bin_)}}};
    return writeText(name, out.dump(1));
  }

  std::string writeGltfWithBin(const std::string& name = "scene.gltf") {
    finishScenes();
    json out = doc;
    out["buffers"] = {{{"byteLength", bin_.size()}, {"uri", "scene data.bin"}}};
    std::ofstream(dir_ / "scene data.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bin_.data()), std::streamsize(bin_.size()));
    return writeText(name, out.dump(1));
  }

  std::string writeGlb(const std::string& name = "scene.glb") {
    finishScenes();
    json out = doc;
    out["buffers"] = {{{"byteLength", bin_.size()}}};
    std::string text = out.dump();
    while (text.size() % 4 != 0) text += ' ';
    std::vector<unsigned char> binChunk = bin_;
    while (binChunk.size() % 4 != 0) binChunk.push_back(0);
    std::vector<unsigned char> glb;
    auto u32 = [&glb](uint32_t v) {
      for (int i = 0; i < 4; ++i) glb.push_back((v >> (8 * i)) & 0xFF);
    };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + binChunk.size()));
    u32(uint32_t(text.size()));
    u32(0x4E4F534A);  // "JSON"
    glb.insert(glb.end(), text.begin(), text.end());
    u32(uint32_t(binChunk.size()));
    u32(0x004E4942);  // "BIN"
    glb.insert(glb.end(), binChunk.begin(), binChunk.end());
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
    return path.string();
  }

  std::string writeText(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }

  json doc;

 private:
  fs::path dir_;
  std::vector<unsigned char> bin_;
};

// Loading `path` throws an InputError whose message contains every fragment.
void expectInputError(const std::string& path, const std::vector<std::string>& fragments) {
  try {
    loadGltfScene(path);
    ADD_FAILURE() << "no InputError for " << path;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "'" << fragment << "' missing from: " << message;
  }
}

std::vector<Vec3> worldVertices(const SceneObject& object, size_t polygon, double frame = 0) {
  const Transform transform = object.transformAt(frame);
  std::vector<Vec3> out;
  for (const Vec3& p : object.polygons[polygon]) out.push_back(transform.applyToPoint(p));
  return out;
}

std::vector<float> axisAngle(const Vec3& axis, double radians) {
  const Quaternion q = Quaternion::fromAxisAngle(axis, radians);
  return {float(q.x), float(q.y), float(q.z), float(q.w)};  // glTF order: x, y, z, w
}

TEST(GltfLoader, QuadWithTrsNodeGivesWorldPositions) {
  GltfBuilder b;
  const int quad = b.quadMesh();
  b.node({{"name", "floor"},
          {"mesh", quad},
          {"translation", {1, 2, 3}},
          {"rotation", axisAngle({0, 1, 0}, kPi / 2)},
          {"scale", {2, 2, 2}}});
  const std::string path = b.writeGltf();
  const Scene scene = loadGltfScene(path);

  EXPECT_EQ(scene.sourcePath, path);
  EXPECT_EQ(scene.frames, 1);
  ASSERT_EQ(scene.objects.size(), 1u);
  const SceneObject& object = scene.objects[0];
  EXPECT_EQ(object.name, "floor");
  EXPECT_FALSE(object.isDynamic());
  ASSERT_EQ(object.polygons.size(), 2u);
  // Object space keeps the mesh; the node's TRS is the object's transform.
  expectNear(object.polygons[0][1], {1, 0, 0});
  expectNear(object.transform.translate, {1, 2, 3});
  expectNear(object.transform.scale, {2, 2, 2});
  // R_y(90°) maps x to -z: (1,1,0) -> scale (2,2,0) -> rotate (0,2,-2) -> translate (1,4,1).
  const std::vector<Vec3> second = worldVertices(object, 1);
  expectNear(second[0], {1, 2, 3});
  expectNear(second[1], {1, 4, 1});
  expectNear(second[2], {1, 4, 3});
  // Counter-clockwise around +z in the mesh stays the front: the world normal is R_y(90°)·z = x.
  const PosedScene posed = poseAt(scene, 0);
  expectNear(posed.polygons[0].plane.normal, {1, 0, 0});
  EXPECT_EQ(object.polygonOrigin[1], path + ": /meshes/0/primitives/0 triangle 1");
  // No material: the glTF default (white, clamped below 1).
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "default");
  EXPECT_NEAR(scene.materials[0].reflectance.r, 0.99, 1e-12);
  EXPECT_FALSE(scene.materials[0].isEmitter());
  EXPECT_EQ(object.polygonMaterial, (std::vector<int>{0, 0}));
}

TEST(GltfLoader, MatrixNodeAndExternalBinLoad) {
  GltfBuilder b;
  const int quad = b.quadMesh();
  // Column-major: translation (5, 0, 0), uniform scale 3.
  b.node({{"mesh", quad}, {"matrix", {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 5, 0, 0, 1}}});
  const Scene scene = loadGltfScene(b.writeGltfWithBin());
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].name, "node 0");
  expectNear(worldVertices(scene.objects[0], 0)[2], {8, 3, 0});
}

TEST(GltfLoader, HierarchyComposesParentAndChild) {
  GltfBuilder b;
  const int quad = b.quadMesh();
  b.node({{"name", "parent"},
          {"children", {1}},
          {"rotation", axisAngle({0, 0, 1}, kPi / 2)},
          {"scale", {2, 2, 2}}});
  b.node({{"name", "child"}, {"mesh", quad}, {"translation", {1, 0, 0}}});
  const Scene scene = loadGltfScene(b.writeGltf());
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].name, "child");
  // p -> child (p + (1,0,0)) -> scale 2 -> R_z(90°): (x, y) -> (-y, x).
  const std::vector<Vec3> first = worldVertices(scene.objects[0], 0);
  expectNear(first[0], {0, 2, 0});   // (0,0,0) -> (1,0,0) -> (2,0,0) -> (0,2,0)
  expectNear(first[2], {-2, 4, 0});  // (1,1,0) -> (2,1,0) -> (4,2,0) -> (-2,4,0)
}

TEST(GltfLoader, ShearIsBakedIntoVertices) {
  GltfBuilder b;
  const int quad = b.quadMesh();
  b.node({{"children", {1}}, {"scale", {2, 1, 1}}});
  b.node({{"mesh", quad}, {"rotation", axisAngle({0, 0, 1}, kPi / 4)}});
  const Scene scene = loadGltfScene(b.writeGltf());
  const SceneObject& object = scene.objects[0];
  expectNear(object.transform.translate, {0, 0, 0});
  expectNear(object.transform.scale, {1, 1, 1});
  const double h = std::sqrt(0.5);
  // (1,0,0) -> R_z(45°) (h, h, 0) -> scale x by 2 (2h, h, 0); the file's rotation is float32.
  expectNear(object.polygons[0][1], {2 * h, h, 0}, 1e-7);
  expectNear(object.polygons[0][2], {0, 2 * h, 0}, 1e-7);  // (1,1,0) -> (0, 2h, 0) -> (0, 2h, 0)
}

TEST(GltfLoader, MirroredNodeKeepsTheFrontSide) {
  GltfBuilder b;
  const int quad = b.quadMesh();
  b.node({{"mesh", quad}, {"scale", {-1, 1, 1}}});
  // A mirror with shear is baked, and must keep the front too.
  b.node({{"children", {2}}, {"scale", {-2, 1, 1}}});
  b.node({{"mesh", quad}, {"rotation", axisAngle({0, 0, 1}, kPi / 4)}});
  const Scene scene = loadGltfScene(b.writeGltf());
  ASSERT_EQ(scene.objects.size(), 2u);
  // glTF: with a negative determinant the front is the clockwise side, i.e. it stays at +z.
  const PosedScene posed = poseAt(scene, 0);
  for (const WorldPolygon& polygon : posed.polygons) expectNear(polygon.plane.normal, {0, 0, 1});
}

TEST(GltfLoader, StripsAndFansBecomeTrianglesAndLinesAreIgnored) {
  GltfBuilder b;
  // Strip over the unit quad: (0,0) (1,0) (0,1) (1,1), counter-clockwise triangles.
  const int stripPositions = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3");
  b.doc["meshes"].push_back({{"primitives",
                              {{{"attributes", {{"POSITION", stripPositions}}}, {"mode", 5}},
                               {{"attributes", {{"POSITION", stripPositions}}}, {"mode", 1}},
                               // A fan around (0,0): (1,0) (1,1) (0,1).
                               {{"attributes", {{"POSITION", stripPositions}}},
                                {"indices", b.indices({0, 1, 3, 2})},
                                {"mode", 6}}}}});
  b.node({{"mesh", 0}});
  const Scene scene = loadGltfScene(b.writeGltf());
  ASSERT_EQ(scene.objects.size(), 1u);
  ASSERT_EQ(scene.objects[0].polygons.size(), 4u);
  const PosedScene posed = poseAt(scene, 0);
  double total = 0;
  for (const WorldPolygon& polygon : posed.polygons) {
    expectNear(polygon.plane.normal, {0, 0, 1});
    total += polygon.area;
  }
  EXPECT_NEAR(total, 2.0, 1e-12);
  EXPECT_NE(scene.objects[0].polygonOrigin[2].find("/meshes/0/primitives/2 triangle 0"),
            std::string::npos);
}

TEST(GltfLoader, SparseAccessorsOverrideTheirBase) {
  GltfBuilder b;
  // Vertex 2 is wrong in the base data; the sparse part moves it to (1, 1, 0).
  const int positions = b.floats({0, 0, 0, 1, 0, 0, 5, 5, 0, 0, 1, 0}, "VEC3");
  b.doc["accessors"][positions]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", b.view(std::vector<uint16_t>{2})}, {"componentType", 5123}}},
      {"values", {{"bufferView", b.view(std::vector<float>{1, 1, 0})}}}};
  b.node({{"mesh", b.mesh(positions, b.indices({0, 1, 2, 0, 2, 3}))}});
  const Scene scene = loadGltfScene(b.writeGltf());
  expectNear(scene.objects[0].polygons[0][2], {1, 1, 0});
  expectNear(scene.objects[0].polygons[1][1], {1, 1, 0});
}

TEST(GltfLoader, QuantizedPositionsNeedTheExtension) {
  GltfBuilder b;
  const std::vector<int16_t> quantized = {0, 0, 0, 32767, 0, 0, 32767, 32767, 0};
  const int positions = b.accessor(b.view(quantized), /*SHORT*/ 5122, 3, "VEC3");
  b.doc["accessors"][positions]["normalized"] = true;
  b.node({{"mesh", b.mesh(positions)}, {"scale", {4, 4, 4}}});
  expectInputError(b.writeGltf("plain.gltf"),
                   {"plain.gltf: /meshes/0/primitives/0/attributes/POSITION", "normalized SHORT",
                    "KHR_mesh_quantization"});
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  const Scene scene = loadGltfScene(b.writeGltf("quantized.gltf"));
  expectNear(worldVertices(scene.objects[0], 0)[2], {4, 4, 0});
}

TEST(GltfLoader, EmissiveMaterialsAreLightsWithUniqueNames) {
  GltfBuilder b;
  b.doc["materials"] = {
      {{"name", "paint"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.3, 0.4, 1}}}}},
      {{"name", "paint"},
       {"emissiveFactor", {1, 0.5, 0.25}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
      {{"emissiveFactor", {0.5, 0.5, 0.5}}}};
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  b.node({{"name", "wall"}, {"mesh", b.quadMesh(0)}});
  b.node({{"name", "lamp"}, {"mesh", b.quadMesh(1)}, {"translation", {0, 0, 1}}});
  b.node({{"name", "lamp"}, {"mesh", b.quadMesh(2)}, {"translation", {0, 0, 2}}});
  const Scene scene = loadGltfScene(b.writeGltf());
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].name, "paint");
  EXPECT_EQ(scene.materials[1].name, "paint (2)");
  EXPECT_EQ(scene.materials[2].name, "material 2");
  EXPECT_EQ(scene.materials[0].reflectance, (Rgb{0.2, 0.3, 0.4}));
  EXPECT_FALSE(scene.materials[0].isEmitter());
  EXPECT_EQ(scene.materials[1].emission, (Rgb{4, 2, 1}));
  EXPECT_EQ(scene.materials[2].emission, (Rgb{0.5, 0.5, 0.5}));
  EXPECT_NEAR(scene.materials[1].reflectance.g, 0.99, 1e-12);  // default white, clamped
  ASSERT_EQ(scene.objects.size(), 3u);
  EXPECT_EQ(scene.objects[1].name, "lamp");
  EXPECT_EQ(scene.objects[2].name, "lamp (2)");
  EXPECT_EQ(scene.objects[1].polygonMaterial[0], 1);
  const PosedScene posed = poseAt(scene, 0);
  EXPECT_EQ(posed.lights.size(), 4u);
}

TEST(GltfLoader, LinearTranslationAndRotationAreSampledAtFrames) {
  GltfBuilder b;
  const int box = b.node({{"name", "box"}, {"mesh", b.quadMesh()}});
  b.animate(box, "translation", {0, 0.5, 1}, {0, 0, 0, 2, 0, 0, 2, 4, 0});
  std::vector<float> rotations;
  for (double degrees : {0.0, 90.0, 180.0}) {
    const std::vector<float> q = axisAngle({0, 1, 0}, degrees * kPi / 180);
    rotations.insert(rotations.end(), q.begin(), q.end());
  }
  b.animate(box, "rotation", {0, 0.5, 1}, rotations);
  b.node({{"name", "static"}, {"mesh", b.quadMesh()}, {"translation", {0, 5, 0}}});
  const Scene scene = loadGltfScene(b.writeGltf());

  EXPECT_EQ(scene.frames, kGltfFramesPerSecond + 1);  // t = 0 .. 1 s
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_FALSE(scene.objects[1].isDynamic());
  const SceneObject& object = scene.objects[0];
  ASSERT_TRUE(object.isDynamic());
  const std::vector<Keyframe>& keys = object.motion.keyframes();
  ASSERT_EQ(keys.size(), size_t(kGltfFramesPerSecond + 1));
  for (size_t f = 0; f < keys.size(); ++f) EXPECT_EQ(keys[f].frame, int(f));
  auto rotationY = [](double degrees) {
    return Quaternion::fromAxisAngle({0, 1, 0}, degrees * kPi / 180);
  };
  // Keyed times: exact (up to the file's float32 values).
  expectNear(keys[0].pose.translate, {0, 0, 0}, 1e-7);
  expectNear(keys[12].pose.translate, {2, 0, 0}, 1e-7);
  expectNear(keys[24].pose.translate, {2, 4, 0}, 1e-7);
  expectSameRotation(keys[12].pose.rotate, rotationY(90));
  expectSameRotation(keys[24].pose.rotate, rotationY(180));
  // Between keys: linear translation, slerped rotation.
  expectNear(keys[6].pose.translate, {1, 0, 0}, 1e-6);
  expectNear(keys[18].pose.translate, {2, 2, 0}, 1e-6);
  expectNear(keys[3].pose.translate, {0.5, 0, 0}, 1e-6);
  expectSameRotation(keys[6].pose.rotate, rotationY(45));
  expectSameRotation(keys[18].pose.rotate, rotationY(135));
  expectNear(keys[6].pose.scale, {1, 1, 1}, 1e-9);
  EXPECT_EQ(object.transform.translate, keys[0].pose.translate);
}

TEST(GltfLoader, StepHoldsUntilTheNextKeyEvenAtFloatTimes) {
  GltfBuilder b;
  const int box = b.node({{"mesh", b.quadMesh()}});
  // 1/3 s is 0.33333334f: frame 8 (t = 0.3333...) must already show the second key.
  b.animate(box, "translation", {0, 1.0f / 3, 0.5f}, {0, 0, 0, 1, 0, 0, 2, 0, 0}, "STEP");
  const Scene scene = loadGltfScene(b.writeGltf());
  EXPECT_EQ(scene.frames, 13);
  const std::vector<Keyframe>& keys = scene.objects[0].motion.keyframes();
  ASSERT_EQ(keys.size(), 13u);
  EXPECT_EQ(keys[7].pose.translate.x, 0);
  EXPECT_EQ(keys[8].pose.translate.x, 1);
  EXPECT_EQ(keys[11].pose.translate.x, 1);
  EXPECT_EQ(keys[12].pose.translate.x, 2);
}

TEST(GltfLoader, CubicSplineFollowsTheHermiteCurve) {
  GltfBuilder b;
  const int box = b.node({{"mesh", b.quadMesh()}});
  // Keys at 0 s (value 0, out-tangent 4) and 1 s (value 1, in-tangent 0), x only.
  b.animate(box, "translation", {0, 1},
            {0, 0, 0, 0, 0, 0, 4, 0, 0,  // in, value, out of key 0
             0, 0, 0, 1, 0, 0, 0, 0, 0},
            "CUBICSPLINE");
  const Scene scene = loadGltfScene(b.writeGltf());
  const std::vector<Keyframe>& keys = scene.objects[0].motion.keyframes();
  ASSERT_EQ(keys.size(), 25u);
  const double u = 6.0 / 24;  // frame 6
  const double expected = 4 * (u * u * u - 2 * u * u + u) + (-2 * u * u * u + 3 * u * u);
  EXPECT_NEAR(keys[6].pose.translate.x, expected, 1e-9);
  EXPECT_NEAR(keys[24].pose.translate.x, 1, 1e-9);
}

TEST(GltfLoader, AnimatedParentMakesChildDynamic) {
  GltfBuilder b;
  const int parent = b.node({{"children", {1}}});
  b.node({{"mesh", b.quadMesh()}, {"translation", {0, 1, 0}}});
  b.animate(parent, "translation", {0, 2}, {0, 0, 0, 4, 0, 0});
  const Scene scene = loadGltfScene(b.writeGltf());
  EXPECT_EQ(scene.frames, 49);
  ASSERT_TRUE(scene.objects[0].isDynamic());
  expectNear(scene.objects[0].motion.keyframes()[24].pose.translate, {2, 1, 0}, 1e-6);
  // Between integer frames the Motion interpolates the keyframes.
  expectNear(scene.objects[0].transformAt(12.5).translation, {12.5 / 12, 1, 0}, 1e-6);
}

TEST(GltfLoader, GlbLoadsLikeGltf) {
  GltfBuilder b;
  const int box = b.node({{"name", "box"}, {"mesh", b.quadMesh()}, {"scale", {1, 2, 3}}});
  b.animate(box, "translation", {0, 1}, {0, 0, 0, 1, 0, 0});
  const Scene fromGltf = loadGltfScene(b.writeGltf());
  const Scene fromGlb = loadGltfScene(b.writeGlb());
  ASSERT_EQ(fromGlb.objects.size(), fromGltf.objects.size());
  EXPECT_EQ(fromGlb.frames, fromGltf.frames);
  EXPECT_EQ(fromGlb.objects[0].name, "box");
  EXPECT_EQ(fromGlb.objects[0].polygons, fromGltf.objects[0].polygons);
  ASSERT_EQ(fromGlb.objects[0].motion.keyframes().size(),
            fromGltf.objects[0].motion.keyframes().size());
  for (size_t k = 0; k < fromGlb.objects[0].motion.keyframes().size(); ++k)
    EXPECT_EQ(fromGlb.objects[0].motion.keyframes()[k].pose.translate,
              fromGltf.objects[0].motion.keyframes()[k].pose.translate);
}

TEST(GltfLoader, FirstPerspectiveCameraBecomesTheSceneCamera) {
  GltfBuilder b;
  b.doc["cameras"] = {{{"type", "perspective"},
                       {"perspective", {{"yfov", kPi / 4}, {"aspectRatio", 1.5}, {"znear", 0.1}}}}};
  b.node({{"mesh", b.quadMesh()}});
  b.node({{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", axisAngle({0, 1, 0}, kPi / 2)}});
  const Scene scene = loadGltfScene(b.writeGltf());
  ASSERT_TRUE(scene.camera.has_value());
  expectNear(scene.camera->eye, {1, 2, 3});
  expectNear(scene.camera->target, {0, 2, 3}, 1e-7);  // -z rotated 90° about y is -x
  expectNear(scene.camera->up, {0, 1, 0}, 1e-7);
  EXPECT_NEAR(scene.camera->fovYDegrees, 45, 1e-9);
  EXPECT_EQ(scene.camera->width, 720);
  EXPECT_EQ(scene.camera->height, 480);
}

TEST(GltfLoader, BundledAnimatedBoxSceneLoads) {
  const std::string path = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/gltf/animated-box.gltf";
  const Scene scene = loadGltfScene(path);
  EXPECT_EQ(scene.frames, kGltfFramesPerSecond + 1);  // the box moves for 1 s
  EXPECT_EQ(scene.dynamicObjectCount(), 1);
  ASSERT_TRUE(scene.camera.has_value());
  for (double frame : {0.0, 12.0, 24.0}) {
    const PosedScene posed = poseAt(scene, frame);
    ASSERT_FALSE(posed.lights.empty());
    double lightArea = 0;
    for (PolygonId id : posed.lights) {
      expectNear(posed.polygons[size_t(id)].plane.normal, {0, -1, 0});  // the lamp faces down
      lightArea += posed.polygons[size_t(id)].area;
    }
    EXPECT_GT(lightArea, 0);
    for (const WorldPolygon& polygon : posed.polygons)
      EXPECT_FALSE(findPolygonDefect(polygon.vertices)) << "polygon " << polygon.id;
  }
  // The box moves.
  const SceneObject* box = nullptr;
  for (const SceneObject& object : scene.objects)
    if (object.isDynamic()) box = &object;
  ASSERT_NE(box, nullptr);
  EXPECT_GT(distance(box->transformAt(0).translation, box->transformAt(24).translation), 0.5);
}

// ---- Errors -----------------------------------------------------------------------------------

TEST(GltfLoaderErrors, MissingFile) {
  const std::string path = std::string(PENUMBRA_BINARY_DIR) + "/no-such-dir/missing.gltf";
  expectInputError(path, {"missing.gltf", "not found"});
}

TEST(GltfLoaderErrors, MalformedJson) {
  GltfBuilder b;
  expectInputError(b.writeText("broken.gltf", "{\"asset\": {\"version\": \"2.0\"},"),
                   {"broken.gltf", "malformed JSON"});
}

TEST(GltfLoaderErrors, MissingBufferFile) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.finishScenes();
  json doc = b.doc;
  doc["buffers"] = {{{"byteLength", 68}, {"uri", "missing.bin"}}};
  expectInputError(b.writeText("nobin.gltf", doc.dump()),
                   {"nobin.gltf: /buffers/0/uri", "missing.bin", "not found"});
}

// What tinygltf accepts silently: a default scene that does not exist, a transform that is not
// an array of numbers (dropped: the node at the origin), a colour without alpha (read as white).
TEST(GltfLoaderErrors, PropertiesTinygltfWouldDropSilently) {
  {
    GltfBuilder b;
    b.node({{"mesh", b.quadMesh()}});
    b.doc["scene"] = 0;
    b.doc["scenes"] = json::array();
    expectInputError(b.writeGltf("noscenes.gltf"), {"noscenes.gltf: /scene", "does not exist"});
  }
  {
    GltfBuilder b;
    b.node({{"mesh", b.quadMesh()}, {"translation", "1 2 3"}});
    b.finishScenes();
    expectInputError(b.writeGltf("string.gltf"),
                     {"string.gltf: /nodes/0/translation", "array of 3 numbers"});
  }
  {
    GltfBuilder b;
    b.node({{"mesh", b.quadMesh()}});
    b.finishScenes();
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5}}}}}};
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    expectInputError(
        b.writeGltf("rgb.gltf"),
        {"rgb.gltf: /materials/0/pbrMetallicRoughness/baseColorFactor", "array of 4 numbers"});
  }
}

TEST(GltfLoaderErrors, BufferViewOutsideBuffer) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.doc["bufferViews"][0]["byteLength"] = 4096;
  expectInputError(b.writeGltf("range.gltf"), {"range.gltf: /bufferViews/0", "past the end"});
}

TEST(GltfLoaderErrors, AccessorOutsideBufferView) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.doc["accessors"][0]["count"] = 5;  // the view holds 4 positions
  expectInputError(b.writeGltf("count.gltf"),
                   {"count.gltf: /accessors/0", "/meshes/0/primitives/0/attributes/POSITION"});
}

TEST(GltfLoaderErrors, MissingAccessor) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 17;
  expectInputError(b.writeGltf("accessor.gltf"),
                   {"accessor.gltf: /meshes/0/primitives/0/attributes/POSITION", "accessor 17"});
}

TEST(GltfLoaderErrors, PositionNotVec3) {
  GltfBuilder b;
  const int positions = b.floats({0, 0, 1, 0, 1, 1}, "VEC2");
  b.node({{"mesh", b.mesh(positions)}});
  expectInputError(b.writeGltf("vec2.gltf"),
                   {"vec2.gltf: /meshes/0/primitives/0/attributes/POSITION", "VEC3", "VEC2"});
}

TEST(GltfLoaderErrors, IndexOutOfRange) {
  GltfBuilder b;
  const int positions = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0}, "VEC3");
  b.node({{"mesh", b.mesh(positions, b.indices({0, 1, 7}))}});
  expectInputError(b.writeGltf("index.gltf"),
                   {"index.gltf: /meshes/0/primitives/0/indices", "index 2 is 7", "3 vertices"});
}

TEST(GltfLoaderErrors, NanPosition) {
  GltfBuilder b;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int positions = b.floats({0, 0, 0, 1, nan, 0, 1, 1, 0}, "VEC3");
  b.node({{"mesh", b.mesh(positions)}});
  expectInputError(b.writeGltf("nan.gltf"),
                   {"nan.gltf: /meshes/0/primitives/0/attributes/POSITION", "element 1", "nan"});
}

TEST(GltfLoaderErrors, NoPolygons) {
  GltfBuilder b;
  const int positions = b.floats({0, 0, 0, 1, 0, 0}, "VEC3");
  b.node({{"mesh", b.mesh(positions, -1, -1, /*LINES*/ 1)}});
  expectInputError(b.writeGltf("lines.gltf"), {"lines.gltf: /scenes/0", "no polygons"});
}

TEST(GltfLoaderErrors, DegenerateTriangle) {
  GltfBuilder b;
  const int positions = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0}, "VEC3");
  b.node({{"mesh", b.mesh(positions, b.indices({0, 1, 2, 0, 1, 1}))}});
  expectInputError(b.writeGltf("degenerate.gltf"),
                   {"degenerate.gltf: /meshes/0/primitives/0", "triangle 1", "distinct"});
}

TEST(GltfLoaderErrors, NodeCycle) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.node({{"children", {2}}});
  b.node({{"children", {1}}});
  b.doc["scenes"] = {{{"nodes", {0}}}};
  expectInputError(b.writeGltf("cycle.gltf"), {"cycle.gltf: /nodes/1", "cycle"});
}

TEST(GltfLoaderErrors, AnimatedShear) {
  GltfBuilder b;
  const int parent = b.node({{"children", {1}}, {"scale", {2, 1, 1}}});
  const int child = b.node({{"mesh", b.quadMesh()}});
  b.animate(child, "rotation", {0, 1}, [] {
    std::vector<float> q = axisAngle({0, 0, 1}, 0);
    const std::vector<float> r = axisAngle({0, 0, 1}, kPi / 2);
    q.insert(q.end(), r.begin(), r.end());
    return q;
  }());
  (void)parent;
  expectInputError(b.writeGltf("shear.gltf"), {"shear.gltf: /nodes/1", "shear", "frame 1"});
}

TEST(GltfLoaderErrors, UnsupportedRequiredExtension) {
  GltfBuilder b;
  b.node({{"mesh", b.quadMesh()}});
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expectInputError(b.writeGltf("draco.gltf"),
                   {"draco.gltf: /extensionsRequired/0", "KHR_draco_mesh_compression"});
}

TEST(GltfLoaderErrors, ConflictingChannels) {
  GltfBuilder b;
  const int box = b.node({{"mesh", b.quadMesh()}});
  b.animate(box, "translation", {0, 1}, {0, 0, 0, 1, 0, 0});
  b.animate(box, "translation", {0, 1}, {0, 0, 0, 2, 0, 0});
  expectInputError(b.writeGltf("conflict.gltf"),
                   {"conflict.gltf: /animations/0/channels/1", "/animations/0/channels/0"});
}

// Hostile edits of a valid file (every number replaced by awkward values, every key removed) must
// load or throw InputError: never crash, assert or throw anything else.
TEST(GltfLoaderErrors, MutatedFilesLoadOrThrowInputError) {
  std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/gltf/animated-box.gltf");
  const json original = json::parse(in);
  std::vector<json::json_pointer> numbers, keys;
  std::vector<std::pair<json::json_pointer, const json*>> stack = {
      {json::json_pointer(), &original}};
  while (!stack.empty()) {
    const auto [pointer, value] = stack.back();
    stack.pop_back();
    if (value->is_number()) numbers.push_back(pointer);
    if (value->is_object())
      for (const auto& [key, child] : value->items()) {
        keys.push_back(pointer / key);
        stack.push_back({pointer / key, &child});
      }
    if (value->is_array())
      for (size_t i = 0; i < value->size(); ++i) stack.push_back({pointer / i, &(*value)[i]});
  }
  GltfBuilder b;
  int loaded = 0, rejected = 0;
  auto attempt = [&](const json& doc, const std::string& what) {
    const std::string path = b.writeText("mutated.gltf", doc.dump());
    try {
      loadGltfScene(path);
      ++loaded;
    } catch (const InputError& e) {
      ++rejected;
      EXPECT_NE(std::string(e.what()).find("mutated.gltf"), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not an InputError: " << e.what();
    }
  };
  for (const auto& pointer : numbers)
    for (double value : {-1.0, 0.0, 3.0, 0.5, 1e9, 4294967296.0}) {
      json doc = original;
      doc[pointer] = value;
      attempt(doc, pointer.to_string() + " = " + std::to_string(value));
    }
  for (const auto& pointer : numbers)
    for (int64_t value : {int64_t(-1), int64_t(2147483648), int64_t(4294967296)}) {
      json doc = original;
      doc[pointer] = value;
      attempt(doc, pointer.to_string() + " = " + std::to_string(value));
    }
  for (const auto& pointer : keys) {
    json doc = original;
    doc[pointer.parent_pointer()].erase(pointer.back());
    attempt(doc, "without " + pointer.to_string());
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace penumbra
