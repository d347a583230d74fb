// Penumbra's JSON scene format (DESIGN.md §4). Every value is checked for type and range, every
// unknown key is an error (a typo must not be silently ignored), and errors are located by the
// file and the JSON path of the offending value.

#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "penumbra/base/input_error.h"
#include "penumbra/base/input_file.h"
#include "penumbra/scene/obj_mesh_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {

namespace {

// The largest keyframe number: a frame count is walked frame by frame by the front ends (probe,
// shadows), so it must stay a count one can iterate.
constexpr int kMaxFrame = 1'000'000;

using Json = nlohmann::json;

// A JSON value with its location, so that every error can say where it is.
class Node {
 public:
  Node(const Json& value, std::string file, std::string path)
      : value_(value), file_(std::move(file)), path_(std::move(path)) {}

  const Json& value() const { return value_; }
  const std::string& path() const { return path_; }
  std::string location() const { return file_ + ": " + (path_.empty() ? "/" : path_); }
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(location(), problem);
  }

  Node child(const std::string& key) const { return {value_.at(key), file_, path_ + "/" + key}; }
  Node child(size_t index) const {
    return {value_.at(index), file_, path_ + "/" + std::to_string(index)};
  }
  bool has(const std::string& key) const { return value_.contains(key); }

  void requireObject(const std::set<std::string>& allowedKeys) const {
    if (!value_.is_object()) fail("expected an object");
    for (const auto& [key, unused] : value_.items())
      if (!allowedKeys.count(key)) {
        std::string allowed;
        for (const std::string& k : allowedKeys) allowed += (allowed.empty() ? "" : ", ") + k;
        fail("unknown key '" + key + "' (allowed: " + allowed + ")");
      }
  }
  void requireArray() const {
    if (!value_.is_array()) fail("expected an array");
  }
  double number() const {
    if (!value_.is_number()) fail("expected a number");
    const double v = value_.get<double>();
    if (!std::isfinite(v)) fail("number is not finite");
    return v;
  }
  // An integer that fits an int (a larger one would wrap: 4294967297 read as 1).
  int integer() const {
    if (!value_.is_number_integer()) fail("expected an integer");
    const bool fits =
        value_.is_number_unsigned()
            ? value_.get<std::uint64_t>() <= std::uint64_t(INT_MAX)
            : value_.get<std::int64_t>() >= INT_MIN && value_.get<std::int64_t>() <= INT_MAX;
    if (!fits) fail("integer out of range");
    return value_.get<int>();
  }
  std::string string() const {
    if (!value_.is_string()) fail("expected a string");
    return value_.get<std::string>();
  }
  bool boolean() const {
    if (!value_.is_boolean()) fail("expected true or false");
    return value_.get<bool>();
  }
  Vec3 vec3() const {
    if (!value_.is_array() || value_.size() != 3) fail("expected an array of 3 numbers");
    return {child(size_t{0}).number(), child(1).number(), child(2).number()};
  }
  Rgb rgb() const {
    const Vec3 v = vec3();
    return {v.x, v.y, v.z};
  }

 private:
  const Json& value_;
  std::string file_;
  std::string path_;
};

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// nlohmann reports a byte offset; users want a line and column.
std::string lineAndColumn(const std::string& text, size_t byte) {
  int line = 1, column = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

Material parseMaterial(const Node& node, const std::string& name) {
  node.requireObject({"reflectance", "emission", "mirror"});
  Material m;
  m.name = name;
  if (node.has("reflectance")) m.reflectance = node.child("reflectance").rgb();
  if (node.has("emission")) m.emission = node.child("emission").rgb();
  if (node.has("mirror")) m.mirror = node.child("mirror").boolean();
  // Reflectance 1 (a lossless surface) is legal: MTL files write `Kd 1 1 1` for white. Above 1 a
  // surface would reflect more than it receives, which is an input error, not something to clamp.
  for (double c : {m.reflectance.r, m.reflectance.g, m.reflectance.b})
    if (c < 0 || c > 1)
      node.child("reflectance").fail("reflectance must lie in [0, 1] per channel");
  for (double c : {m.emission.r, m.emission.g, m.emission.b})
    if (c < 0) node.child("emission").fail("emission must be non-negative");
  return m;
}

Quaternion parseRotation(const Node& node) {
  node.requireObject({"axis", "degrees"});
  if (!node.has("axis") || !node.has("degrees")) node.fail("rotate needs 'axis' and 'degrees'");
  const Vec3 axis = node.child("axis").vec3();
  if (squaredLength(axis) == 0) node.child("axis").fail("rotation axis is the zero vector");
  return Quaternion::fromAxisAngle(axis, node.child("degrees").number() * std::numbers::pi / 180);
}

Vec3 parseScale(const Node& node) {
  const Vec3 s = node.vec3();
  if (s.x == 0 || s.y == 0 || s.z == 0) node.fail("scale factors must be non-zero");
  return s;
}

// Fields shared by "transform" and motion keyframes; missing fields are the identity.
TrsPose parsePose(const Node& node, const std::set<std::string>& allowedKeys) {
  node.requireObject(allowedKeys);
  TrsPose pose;
  if (node.has("translate")) pose.translate = node.child("translate").vec3();
  if (node.has("rotate")) pose.rotate = parseRotation(node.child("rotate"));
  if (node.has("scale")) pose.scale = parseScale(node.child("scale"));
  return pose;
}

Motion parseMotion(const Node& node) {
  node.requireArray();
  if (node.value().empty()) node.fail("motion needs at least one keyframe");
  std::vector<Keyframe> keyframes;
  for (size_t i = 0; i < node.value().size(); ++i) {
    const Node key = node.child(i);
    Keyframe k;
    k.pose = parsePose(key, {"frame", "translate", "rotate", "scale"});
    if (!key.has("frame")) key.fail("keyframe needs 'frame'");
    k.frame = key.child("frame").integer();
    if (k.frame < 0) key.child("frame").fail("frame must be >= 0");
    // The scene's frame count is the last keyframe + 1, and front ends walk every frame.
    if (k.frame > kMaxFrame)
      key.child("frame").fail("frame must be <= " + std::to_string(kMaxFrame));
    if (!keyframes.empty() && k.frame <= keyframes.back().frame)
      key.child("frame").fail("keyframes must have strictly increasing frames");
    keyframes.push_back(k);
  }
  return Motion(std::move(keyframes));
}

Camera parseCamera(const Node& node) {
  node.requireObject({"eye", "target", "up", "fov_y_degrees", "width", "height"});
  Camera c;
  if (node.has("eye")) c.eye = node.child("eye").vec3();
  if (node.has("target")) c.target = node.child("target").vec3();
  if (node.has("up")) c.up = node.child("up").vec3();
  if (node.has("fov_y_degrees")) c.fovYDegrees = node.child("fov_y_degrees").number();
  if (node.has("width")) c.width = node.child("width").integer();
  if (node.has("height")) c.height = node.child("height").integer();
  if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) node.fail("fov_y_degrees must lie in (0, 180)");
  if (c.width <= 0 || c.height <= 0 || c.width > 16384 || c.height > 16384)
    node.fail("width and height must lie in [1, 16384]");
  if (squaredLength(c.target - c.eye) == 0) node.fail("eye and target coincide");
  if (squaredLength(cross(c.target - c.eye, c.up)) == 0) node.fail("up is parallel to the view");
  return c;
}

class JsonSceneParser {
 public:
  explicit JsonSceneParser(std::string path) : path_(std::move(path)) {}

  Scene parse() {
    std::ifstream in = openInputFile(path_, "scene file", std::ios::in | std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    Json json;
    try {
      json = Json::parse(text);
    } catch (const Json::parse_error& e) {
      throw InputError(path_ + ":" + lineAndColumn(text, e.byte > 0 ? e.byte - 1 : 0),
                       std::string("malformed JSON: ") + e.what());
    } catch (const Json::exception& e) {  // e.g. a number too large for a double
      throw InputError(path_, std::string("malformed JSON: ") + e.what());
    }
    const Node root(json, path_, "");
    root.requireObject({"penumbra", "materials", "objects", "camera", "frames"});
    if (!root.has("penumbra") || root.child("penumbra").integer() != 1)
      root.fail("expected \"penumbra\": 1 (the scene format version)");

    scene_.sourcePath = path_;
    if (root.has("materials")) parseMaterials(root.child("materials"));
    if (!root.has("objects")) root.fail("missing 'objects'");
    const Node objects = root.child("objects");
    objects.requireArray();
    for (size_t i = 0; i < objects.value().size(); ++i) parseObject(objects.child(i));
    if (scene_.polygonCount() == 0) objects.fail("the scene has no polygons");
    if (root.has("camera")) scene_.camera = parseCamera(root.child("camera"));

    int lastKeyframe = 0;
    for (const SceneObject& o : scene_.objects)
      lastKeyframe = std::max(lastKeyframe, o.motion.lastFrame());
    scene_.frames = lastKeyframe + 1;
    if (root.has("frames")) {
      scene_.frames = root.child("frames").integer();
      if (scene_.frames < 1 || scene_.frames > kMaxFrame + 1)
        root.child("frames").fail("frames must lie in 1.." + std::to_string(kMaxFrame + 1));
    }
    return std::move(scene_);
  }

 private:
  void parseMaterials(const Node& node) {
    if (!node.value().is_object()) node.fail("expected an object of named materials");
    for (const auto& [name, unused] : node.value().items()) {
      materialIndex_[name] = int(scene_.materials.size());
      scene_.materials.push_back(parseMaterial(node.child(name), name));
    }
  }

  // Resolves a material name: JSON materials first, then the OBJ's MTL (Kd, Ke). A Kd out of
  // range is reported at its MTL line, with `location` (where it is used) in the message.
  int resolveMaterial(const std::string& name, const ObjMesh* obj, const std::string& location) {
    if (auto it = materialIndex_.find(name); it != materialIndex_.end()) return it->second;
    if (obj) {
      for (const ObjMtlMaterial& m : obj->mtlMaterials) {
        if (m.name != name) continue;
        Material material{name, m.diffuse, m.emission, false};
        for (double c : {m.diffuse.r, m.diffuse.g, m.diffuse.b})
          if (!(c >= 0 && c <= 1)) {  // NaN too
            std::ostringstream kd;
            kd << m.diffuse.r << " " << m.diffuse.g << " " << m.diffuse.b;
            throw InputError(m.location, "MTL material '" + name + "': Kd " + kd.str() +
                                             " must lie in [0, 1] per channel (used at " +
                                             location + ")");
          }
        materialIndex_[name] = int(scene_.materials.size());
        scene_.materials.push_back(material);
        return materialIndex_[name];
      }
    }
    throw InputError(location, "unknown material '" + name + "'");
  }

  void parseObject(const Node& node) {
    node.requireObject({"name", "obj", "polygons", "material", "transform", "motion"});
    SceneObject object;
    object.name = node.has("name") ? node.child("name").string()
                                   : "object " + node.path().substr(node.path().rfind('/') + 1);
    const bool hasObj = node.has("obj"), hasPolygons = node.has("polygons");
    if (hasObj == hasPolygons) node.fail("an object needs exactly one of 'obj' or 'polygons'");
    std::optional<int> objectMaterial;
    std::string materialName;
    if (node.has("material")) materialName = node.child("material").string();
    if (node.has("transform"))
      object.transform = parsePose(node.child("transform"), {"translate", "rotate", "scale"});
    if (node.has("motion")) object.motion = parseMotion(node.child("motion"));

    if (hasPolygons) {
      if (!materialName.empty())
        objectMaterial = resolveMaterial(materialName, nullptr, node.child("material").location());
      const Node polygons = node.child("polygons");
      polygons.requireArray();
      for (size_t i = 0; i < polygons.value().size(); ++i) {
        const Node polygon = polygons.child(i);
        polygon.requireArray();
        Polygon3 vertices;
        for (size_t k = 0; k < polygon.value().size(); ++k)
          vertices.push_back(polygon.child(k).vec3());
        if (!objectMaterial) polygon.fail("polygon has no material (give the object 'material')");
        object.polygons.push_back(std::move(vertices));
        object.polygonMaterial.push_back(*objectMaterial);
        object.polygonOrigin.push_back(polygon.location());
      }
    } else {
      const Node objNode = node.child("obj");
      const std::string objPath = directoryOf(path_) + objNode.string();
      ObjMesh mesh;
      try {
        mesh = readObjMesh(objPath);
      } catch (const InputError& e) {
        throw InputError(objNode.location() + ": " + e.location(), e.problem());
      }
      if (!materialName.empty())
        objectMaterial = resolveMaterial(materialName, &mesh, node.child("material").location());
      for (ObjFace& face : mesh.faces) {
        const std::string where = objPath + ":" + std::to_string(face.line);
        int material;
        if (!face.materialName.empty())
          material = resolveMaterial(face.materialName, &mesh, where);
        else if (objectMaterial)
          material = *objectMaterial;
        else
          throw InputError(where, "face has no material (no usemtl, and the object in " +
                                      node.location() + " has no 'material')");
        object.polygons.push_back(std::move(face.vertices));
        object.polygonMaterial.push_back(material);
        object.polygonOrigin.push_back(where);
      }
    }
    scene_.objects.push_back(std::move(object));
  }

  std::string path_;
  Scene scene_;
  std::map<std::string, int> materialIndex_;
};

}  // namespace

Scene loadJsonScene(const std::string& path) {
  return JsonSceneParser(path).parse();
}

}  // namespace penumbra
