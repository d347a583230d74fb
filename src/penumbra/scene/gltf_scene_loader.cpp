// glTF 2.0 scenes (.gltf, .glb) -> Penumbra's Scene (DESIGN.md §4). docs/gltf.md is the user-facing
// version of this comment; keep them in step.
//
// Mapping
// - Scene: the file's default `scene` (else scenes[0]); with no scenes, every root node. Only nodes
//   in that scene's subtrees are loaded.
// - Objects: one SceneObject per node with a mesh whose primitives yield triangles, in node index
//   order, named after the node ("node N" when unnamed; duplicates get " (2)", " (3)", ...). A mesh
//   used by several nodes is copied into each. Primitives of mode TRIANGLES, TRIANGLE_STRIP and
//   TRIANGLE_FAN become triangles (strips and fans converted as the spec's §3.7.2.1 says) in the
//   node's local space; POINTS and LINE* primitives have no area and are ignored. Indexed or not.
//   POSITION must be a VEC3 of FLOAT, or of (normalized) BYTE/SHORT when KHR_mesh_quantization is
//   used. A zero-area triangle is an error naming mesh, primitive and triangle, except in strips
//   and fans where triangles with a repeated *index* are the standard way of stitching strips and
//   are skipped. Other attributes, morph targets and skins are ignored (meshes load in their base
//   pose, placed by their node). Required extensions other than KHR_mesh_quantization,
//   KHR_materials_*, KHR_texture_* and EXT_texture_* (Draco, meshopt, instancing: they change the
//   geometry) are errors.
// - Transforms: a node's world transform is the product of its ancestors' local transforms (matrix
//   or TRS). A static object keeps it as a TrsPose when it is exactly translate·rotate·scale
//   (non-uniform and negative scale included); otherwise (shear: a non-uniform scale above a
//   rotated child) the transform is baked into the vertices and the pose is the identity. Baking a
//   mirroring transform reverses the winding, because glTF keeps the front of mirrored triangles
//   where it was.
// - Materials: every glTF material, in order, then "default" when some primitive has none.
//   reflectance = pbrMetallicRoughness.baseColorFactor rgb, clamped to kMaxGltfReflectance (glTF's
//   default white would make a lossless surface); emission = emissiveFactor ×
//   KHR_materials_emissive_strength.emissiveStrength (1 when absent), read directly as the radiant
//   exitance M in W/m² per channel. Metallic, roughness, textures, alpha and doubleSided are
//   ignored (Penumbra's surfaces are opaque Lambertian and receive on their front side).
// - Animation: all animations play together from t = 0. Channels on translation, rotation and
//   scale of loaded nodes (or their ancestors) are used with LINEAR (slerp for rotation), STEP or
//   CUBICSPLINE interpolation; "weights" channels are ignored. A node property animated by two
//   channels is an error. The animation is sampled at integer frames f = 0..F, t = f /
//   kGltfFramesPerSecond, F = ceil(last key time × fps); each sample of an animated node's (or
//   descendant's) world transform becomes a Keyframe, so an object is dynamic when its node or an
//   ancestor is animated. A world transform with shear or zero scale at some frame is an error.
//   Scene::frames = F + 1 (1 without animation).
// - Camera: the first scene node (index order) with a perspective camera, posed at t = 0: eye at
//   its world origin, looking along its -Z, up +Y, yfov -> fovYDegrees, height 480 and width
//   480 × aspectRatio (640 × 480 without one).
//
// Errors are InputError("file: /json/path", problem). tinygltf (Debian ships it as a shared
// library with the implementation, so no TINYGLTF_IMPLEMENTATION here) parses the JSON and the
// containers, but reports its errors without JSON paths, wraps large indices into int and drops
// malformed optional sizes silently; so syntax, index and size properties and buffer files are
// checked on the JSON before it runs, and everything read from the model is checked here.

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// glTF binary data is little-endian and is decoded here with memcpy.
static_assert(std::endian::native == std::endian::little);

// glTF's default base colour is white; reflectance 1 would be a lossless surface, which the
// radiosity solvers cannot converge with and validateScene rejects.
constexpr double kMaxGltfReflectance = 0.99;
// Matrix columns count as orthogonal (no shear) for animated objects when their cosine is below
// this: float32 data carries about 1e-7 relative noise, and a keyframe must be a TrsPose.
constexpr double kAnimatedShearTolerance = 1e-6;
// A static object keeps a TrsPose only when it reproduces the world matrix this closely
// (relative); otherwise baking is exact and costs nothing.
constexpr double kStaticTrsTolerance = 1e-12;
// Key times are float32: 1/3 s is stored as 0.33333334. A sample time this close (relative) to a
// key uses the key, so keyed frames are exact and STEP does not switch one frame late.
constexpr double kTimeSnapTolerance = 1e-6;
// One hour at 24 fps; every dynamic object stores one keyframe per frame.
constexpr long long kMaxGltfFrames = 24LL * 3600;
// Accessors without a bufferView are zeros (plus sparse values) and cost memory, not file size.
constexpr size_t kMaxElementsWithoutBufferView = size_t(1) << 22;
constexpr int kDefaultCameraHeight = 480;
constexpr int kMaxCameraWidth = 16384;

std::string indexPath(const std::string& base, size_t index) {
  return base + "/" + std::to_string(index);
}

std::string describeNumber(double value) {
  std::ostringstream out;
  out.precision(9);
  out << value;
  return out.str();
}

// tinygltf's messages may quote whole data URIs; keep what it says readable.
std::string summarizeTinyGltfError(const std::string& err) {
  std::string out;
  std::istringstream lines(err);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    if (line.size() > 200) line = line.substr(0, 200) + "...";
    if (!out.empty()) out += "; ";
    out += line;
  }
  return out.empty() ? "unknown error" : out;
}

// The URI decoding tinygltf applies to buffer URIs (dlib's urldecode), so that the pre-check
// looks for the file tinygltf will open.
std::string urlDecode(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      out += char((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

uint32_t readLittleEndian32(const std::vector<unsigned char>& bytes, size_t at) {
  return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
         uint32_t(bytes[at + 3]) << 24;
}

int componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not glTF 2.0 accessor types
  }
}

std::string componentTypeName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    default:
      return std::to_string(componentType);
  }
}

int typeComponentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;  // matrices: never read here
  }
}

std::string typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return std::to_string(type);
  }
}

double decodeComponent(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Whether `count` elements of `elementSize` bytes, `stride` apart, starting at `offset`, lie
// within `length` bytes; written so that hostile sizes cannot overflow.
bool elementsFit(size_t offset, size_t count, size_t stride, size_t elementSize, size_t length) {
  if (count == 0) return offset <= length;
  if (offset > length || elementSize > length - offset) return false;
  return count - 1 <= (length - offset - elementSize) / stride;
}

// What an accessor is read as; decides the legal type and component types.
enum class AccessorRole { kPosition, kIndices, kTime, kTranslation, kRotation, kScale };

struct AccessorValues {
  size_t count = 0;
  int components = 0;
  std::vector<double> values;

  double at(size_t element, int component) const {
    return values[element * size_t(components) + size_t(component)];
  }
};

enum class Interpolation { kStep, kLinear, kCubicSpline };
enum class Property { kTranslation = 0, kRotation = 1, kScale = 2 };
constexpr int kPropertyCount = 3;

struct Channel {
  std::string path;  // "/animations/a/channels/c", for errors
  Property property = Property::kTranslation;
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<double> times;
  AccessorValues output;  // one element per key (three for CUBICSPLINE: in-tangent, value, out)
};

struct TrsValues {
  Vec3 translation;
  Quaternion rotation;
  Vec3 scale{1, 1, 1};
};

struct NodeInfo {
  int parent = -1;
  bool hasMatrix = false;
  Transform matrix;
  TrsValues trs;
  bool inScene = false;
  bool relevant = false;     // a loaded object or the camera depends on its transform
  bool timeVarying = false;  // it or an ancestor has a used animation channel
  std::array<const Channel*, kPropertyCount> channels{};
};

enum class DecompositionResult { kOk, kShear, kSingular };

struct Decomposition {
  DecompositionResult result = DecompositionResult::kOk;
  TrsPose pose;
};

Quaternion quaternionFromRotationMatrix(const Mat3& r) {
  // Shepherd's method: divide by the largest of the four candidates for stability.
  const double trace = r.m[0][0] + r.m[1][1] + r.m[2][2];
  Quaternion q;
  if (trace > 0) {
    const double s = std::sqrt(trace + 1) * 2;
    q = {s / 4, (r.m[2][1] - r.m[1][2]) / s, (r.m[0][2] - r.m[2][0]) / s,
         (r.m[1][0] - r.m[0][1]) / s};
  } else if (r.m[0][0] > r.m[1][1] && r.m[0][0] > r.m[2][2]) {
    const double s = std::sqrt(1 + r.m[0][0] - r.m[1][1] - r.m[2][2]) * 2;
    q = {(r.m[2][1] - r.m[1][2]) / s, s / 4, (r.m[0][1] + r.m[1][0]) / s,
         (r.m[0][2] + r.m[2][0]) / s};
  } else if (r.m[1][1] > r.m[2][2]) {
    const double s = std::sqrt(1 + r.m[1][1] - r.m[0][0] - r.m[2][2]) * 2;
    q = {(r.m[0][2] - r.m[2][0]) / s, (r.m[0][1] + r.m[1][0]) / s, s / 4,
         (r.m[1][2] + r.m[2][1]) / s};
  } else {
    const double s = std::sqrt(1 + r.m[2][2] - r.m[0][0] - r.m[1][1]) * 2;
    q = {(r.m[1][0] - r.m[0][1]) / s, (r.m[0][2] + r.m[2][0]) / s, (r.m[1][2] + r.m[2][1]) / s,
         s / 4};
  }
  return q.normalized();
}

// Writes `transform` as translate·rotate·scale when its linear part has orthogonal columns (cosine
// below `shearTolerance`); a mirroring transform gets a negative x scale.
Decomposition decompose(const Transform& transform, double shearTolerance) {
  const Mat3& m = transform.linear;
  std::array<Vec3, 3> columns;
  std::array<double, 3> lengths;
  for (int j = 0; j < 3; ++j) {
    columns[j] = {m.m[0][j], m.m[1][j], m.m[2][j]};
    lengths[j] = length(columns[j]);
  }
  const double det = m.determinant();
  if (!(std::abs(det) > 1e-12 * lengths[0] * lengths[1] * lengths[2]) || !std::isfinite(det))
    return {DecompositionResult::kSingular, {}};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (std::abs(dot(columns[i], columns[j])) > shearTolerance * lengths[i] * lengths[j])
        return {DecompositionResult::kShear, {}};
  Vec3 scale{lengths[0], lengths[1], lengths[2]};
  if (det < 0) {
    scale.x = -scale.x;
    columns[0] = -columns[0];
  }
  // Rotation: the columns divided by their lengths.
  const Mat3 rotation =
      Mat3::fromRows(columns[0] / lengths[0], columns[1] / lengths[1], columns[2] / lengths[2])
          .transposed();
  return {DecompositionResult::kOk,
          TrsPose{transform.translation, quaternionFromRotationMatrix(rotation), scale}};
}

bool reproduces(const TrsPose& pose, const Transform& transform, double tolerance) {
  const Transform back = pose.toTransform();
  double size = 0, error = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      size = std::max(size, std::abs(transform.linear.m[i][j]));
      error = std::max(error, std::abs(back.linear.m[i][j] - transform.linear.m[i][j]));
    }
  return error <= tolerance * size && back.translation == transform.translation;
}

bool nearTime(double t, double key) {
  return std::abs(t - key) <= kTimeSnapTolerance * std::max(1.0, std::abs(key));
}

// The value of an animation channel at time t (glTF spec, Appendix C), as 3 or 4 numbers.
std::array<double, 4> sample(const Channel& channel, double t) {
  const int n = channel.output.components;
  const bool cubic = channel.interpolation == Interpolation::kCubicSpline;
  auto element = [&](size_t e) {
    std::array<double, 4> v{};
    for (int c = 0; c < n; ++c) v[c] = channel.output.at(e, c);
    return v;
  };
  auto keyValue = [&](size_t k) { return element(cubic ? 3 * k + 1 : k); };
  const std::vector<double>& times = channel.times;
  const size_t last = times.size() - 1;
  if (t <= times[0] || nearTime(t, times[0])) return keyValue(0);
  if (t >= times[last] || nearTime(t, times[last])) return keyValue(last);
  const size_t k = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  if (nearTime(t, times[k])) return keyValue(k);
  if (nearTime(t, times[k + 1])) return keyValue(k + 1);
  const double dt = times[k + 1] - times[k];
  const double u = (t - times[k]) / dt;
  const bool rotation = channel.property == Property::kRotation;
  std::array<double, 4> result{};
  switch (channel.interpolation) {
    case Interpolation::kStep:
      return keyValue(k);
    case Interpolation::kLinear: {
      const std::array<double, 4> a = keyValue(k), b = keyValue(k + 1);
      if (rotation) {
        const Quaternion q = slerp(Quaternion{a[3], a[0], a[1], a[2]}.normalized(),
                                   Quaternion{b[3], b[0], b[1], b[2]}.normalized(), u);
        return {q.x, q.y, q.z, q.w};
      }
      for (int c = 0; c < n; ++c) result[c] = a[c] + (b[c] - a[c]) * u;
      return result;
    }
    case Interpolation::kCubicSpline: {
      const std::array<double, 4> v0 = element(3 * k + 1), out0 = element(3 * k + 2);
      const std::array<double, 4> in1 = element(3 * (k + 1)), v1 = element(3 * (k + 1) + 1);
      const double u2 = u * u, u3 = u2 * u;
      for (int c = 0; c < n; ++c)
        result[c] = (2 * u3 - 3 * u2 + 1) * v0[c] + dt * (u3 - 2 * u2 + u) * out0[c] +
                    (-2 * u3 + 3 * u2) * v1[c] + dt * (u3 - u2) * in1[c];
      return result;  // rotations are normalized by the caller
    }
  }
  return result;
}

class GltfSceneReader {
 public:
  explicit GltfSceneReader(std::string path) : path_(std::move(path)) {}

  Scene read() {
    loadModel();
    checkRequiredExtensions();
    buildHierarchy();
    selectSceneNodes();
    chooseCamera();
    markRelevantNodes();
    loadAnimations();
    Scene scene;
    scene.sourcePath = path_;
    scene.materials = convertMaterials();
    buildObjects(scene);
    if (scene.polygonCount() == 0)
      fail(scenePath_,
           "no polygons: no node of the scene has a mesh with triangles (points and "
           "lines have no area and are ignored)");
    scene.frames = int(frameCount_);
    if (cameraNode_ >= 0) scene.camera = convertCamera();
    return scene;
  }

 private:
  [[noreturn]] void fail(const std::string& jsonPath, const std::string& problem) const {
    throw InputError(jsonPath.empty() ? path_ : path_ + ": " + jsonPath, problem);
  }

  // ---- Container, JSON and tinygltf -------------------------------------------------------

  void loadModel() {
    std::error_code ec;
    if (!fs::exists(path_, ec)) fail("", "file not found");
    if (!fs::is_regular_file(path_, ec)) fail("", "not a regular file");
    std::ifstream in(path_, std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) fail("", "cannot read the file");
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
      fail("", "file larger than 4 GiB (tinygltf's limit)");
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    fs::path baseDir = fs::path(path_).parent_path();
    if (baseDir.empty()) baseDir = ".";
    precheckJson(binary
                     ? glbJsonChunk(bytes)
                     : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                 baseDir);

    tinygltf::TinyGLTF loader;
    // Textures are not used; skip decoding them (and failing on formats stb cannot read).
    loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int,
                             const unsigned char*, int, void*) { return true; },
                          nullptr);
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(),
                                                         static_cast<unsigned int>(bytes.size()),
                                                         baseDir.string())
                           : loader.LoadASCIIFromString(
                                 &model_, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                 static_cast<unsigned int>(bytes.size()), baseDir.string());
    if (!ok) fail("", "invalid glTF: " + summarizeTinyGltfError(err));
  }

  std::string_view glbJsonChunk(const std::vector<unsigned char>& bytes) const {
    // GLB: 12-byte header (magic, version, length), then chunks (length, type, data); the first
    // chunk is the JSON.
    if (bytes.size() < 20) fail("", "not a valid GLB file: shorter than its headers");
    const uint32_t version = readLittleEndian32(bytes, 4);
    if (version != 2) fail("", "GLB container version " + std::to_string(version) + ", expected 2");
    const uint32_t chunkLength = readLittleEndian32(bytes, 12);
    const uint32_t chunkType = readLittleEndian32(bytes, 16);
    if (chunkType != 0x4E4F534Au) fail("", "not a valid GLB file: the first chunk is not JSON");
    if (chunkLength > bytes.size() - 20)
      fail("", "not a valid GLB file: the JSON chunk runs past the end of the file");
    return {reinterpret_cast<const char*>(bytes.data()) + 20, chunkLength};
  }

  // tinygltf reports syntax errors and missing buffer files without saying where; check them
  // first so the message names the JSON path.
  void precheckJson(std::string_view text, const fs::path& baseDir) const {
    nlohmann::json root;
    try {
      root = nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::exception& e) {
      fail("", std::string("malformed JSON: ") + e.what());
    }
    if (!root.is_object()) fail("", "malformed glTF: the JSON root is not an object");
    checkIndexProperties(root);
    const auto buffers = root.find("buffers");
    if (buffers == root.end() || !buffers->is_array()) return;
    for (size_t i = 0; i < buffers->size(); ++i) {
      const nlohmann::json& buffer = (*buffers)[i];
      if (!buffer.is_object()) continue;  // tinygltf explains
      const auto uri = buffer.find("uri");
      if (uri == buffer.end() || !uri->is_string()) continue;
      const std::string bufferPath = indexPath("/buffers", i);
      const auto byteLength = buffer.find("byteLength");
      const bool haveLength = byteLength != buffer.end() && byteLength->is_number_unsigned();
      const uint64_t declared = haveLength ? byteLength->get<uint64_t>() : 0;
      const std::string value = uri->get<std::string>();
      if (value.rfind("data:", 0) == 0) {
        static const std::array<std::string_view, 2> kPrefixes = {
            "data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"};
        std::string_view payload;
        bool known = false;
        for (std::string_view prefix : kPrefixes) {
          if (value.rfind(prefix, 0) != 0) continue;
          payload = std::string_view(value).substr(prefix.size());
          known = true;
        }
        if (!known)
          fail(bufferPath + "/uri",
               "unsupported data URI: buffers must be base64 'application/octet-stream' or "
               "'application/gltf-buffer' data");
        const size_t end = payload.find_last_not_of('=');
        const uint64_t decoded = end == std::string_view::npos ? 0 : (end + 1) * 3 / 4;
        if (haveLength && decoded != declared)
          fail(bufferPath, "the data URI holds " + std::to_string(decoded) +
                               " bytes, but byteLength is " + std::to_string(declared));
        continue;
      }
      const fs::path file = baseDir / urlDecode(value);
      std::error_code ec;
      if (!fs::is_regular_file(file, ec))
        fail(bufferPath + "/uri",
             "buffer file '" + value + "' not found (looked for " + file.string() + ")");
      const uint64_t size = fs::file_size(file, ec);
      if (ec) fail(bufferPath + "/uri", "cannot read buffer file '" + value + "'");
      if (haveLength && size != declared)
        fail(bufferPath, "buffer file '" + value + "' has " + std::to_string(size) +
                             " bytes, but byteLength is " + std::to_string(declared));
    }
  }

  enum class Need { kOptional, kRequired };

  // An index or byte size at `object[key]` must be an integer in [minimum, maximum]. tinygltf
  // would wrap large indices into int (4294967296 -> 0) and silently drop malformed optional
  // sizes, so these are checked on the JSON itself.
  void checkInteger(const nlohmann::json& object, const char* key, Need need,
                    const std::string& objectPath, int64_t minimum = 0,
                    int64_t maximum = std::numeric_limits<int>::max()) const {
    if (!object.is_object()) return;  // tinygltf explains
    const auto it = object.find(key);
    if (it == object.end()) {
      if (need == Need::kRequired)
        fail(objectPath, std::string("the required property '") + key + "' is missing");
      return;
    }
    const std::string where = objectPath + "/" + key;
    if (it->is_number_unsigned()) {
      if (it->get<uint64_t>() <= uint64_t(maximum) && int64_t(it->get<uint64_t>()) >= minimum)
        return;
    } else if (it->is_number_integer()) {
      if (it->get<int64_t>() >= minimum && it->get<int64_t>() <= maximum) return;
    }
    fail(where, "must be an integer from " + std::to_string(minimum) + " to " +
                    std::to_string(maximum) + ", not " + it->dump());
  }

  // Calls visit(element, path) for each element of object[key] when that is an array.
  template <typename Visit>
  static void forEach(const nlohmann::json& object, const char* key, const std::string& objectPath,
                      Visit visit) {
    if (!object.is_object()) return;
    const auto it = object.find(key);
    if (it == object.end() || !it->is_array()) return;
    for (size_t i = 0; i < it->size(); ++i) visit((*it)[i], indexPath(objectPath + "/" + key, i));
  }

  // object[key], when present, must be an array of `size` numbers.
  void checkNumberArray(const nlohmann::json& object, const char* key, const std::string& path,
                        size_t size) const {
    if (!object.is_object() || !object.contains(key)) return;
    const nlohmann::json& value = object[key];
    bool numbers = value.is_array() && value.size() == size;
    for (size_t i = 0; numbers && i < size; ++i) numbers = value[i].is_number();
    if (!numbers)
      fail(path + "/" + key,
           "must be an array of " + std::to_string(size) + " numbers, not " + value.dump());
  }

  void checkIndexArray(const nlohmann::json& object, const char* key,
                       const std::string& objectPath) const {
    forEach(object, key, objectPath, [&](const nlohmann::json& element, const std::string& path) {
      if (!element.is_number_integer() || element.get<int64_t>() < 0 ||
          element.get<int64_t>() > std::numeric_limits<int>::max())
        fail(path, "must be an index (an integer from 0), not " + element.dump());
    });
  }

  void checkIndexProperties(const nlohmann::json& root) const {
    constexpr int64_t kSize = std::numeric_limits<int64_t>::max();
    const Need opt = Need::kOptional, req = Need::kRequired;
    checkInteger(root, "scene", opt, "");
    forEach(root, "buffers", "", [&](const nlohmann::json& b, const std::string& path) {
      checkInteger(b, "byteLength", req, path, 1, kSize);
    });
    forEach(root, "bufferViews", "", [&](const nlohmann::json& v, const std::string& path) {
      checkInteger(v, "buffer", req, path);
      checkInteger(v, "byteOffset", opt, path, 0, kSize);
      checkInteger(v, "byteLength", req, path, 1, kSize);
      checkInteger(v, "byteStride", opt, path, 4, 252);
    });
    forEach(root, "accessors", "", [&](const nlohmann::json& a, const std::string& path) {
      checkInteger(a, "bufferView", opt, path);
      checkInteger(a, "byteOffset", opt, path, 0, kSize);
      checkInteger(a, "componentType", req, path);
      checkInteger(a, "count", req, path, 1, kSize);
      if (!a.is_object() || !a.contains("sparse")) return;
      const nlohmann::json& sparse = a["sparse"];
      const std::string sparsePath = path + "/sparse";
      checkInteger(sparse, "count", req, sparsePath, 1);
      for (const char* part : {"indices", "values"}) {
        if (!sparse.is_object() || !sparse.contains(part)) continue;
        checkInteger(sparse[part], "bufferView", req, sparsePath + "/" + part);
        checkInteger(sparse[part], "byteOffset", opt, sparsePath + "/" + part);
      }
    });
    forEach(root, "meshes", "", [&](const nlohmann::json& m, const std::string& path) {
      forEach(m, "primitives", path, [&](const nlohmann::json& p, const std::string& primitive) {
        checkInteger(p, "indices", opt, primitive);
        checkInteger(p, "material", opt, primitive);
        checkInteger(p, "mode", opt, primitive, 0, 6);
        if (!p.is_object() || !p.contains("attributes") || !p["attributes"].is_object()) return;
        for (const auto& [name, value] : p["attributes"].items())
          checkInteger(p["attributes"], name.c_str(), req, primitive + "/attributes");
      });
    });
    // "scene" names one of "scenes": tinygltf accepts a default scene when there are none.
    if (root.contains("scene")) {
      const auto scenes = root.find("scenes");
      const size_t count = scenes != root.end() && scenes->is_array() ? scenes->size() : 0;
      if (root["scene"].is_number_integer() && root["scene"].get<int64_t>() >= int64_t(count))
        fail("/scene", "scene " + root["scene"].dump() + " does not exist (" +
                           std::to_string(count) + " scenes)");
    }
    forEach(root, "nodes", "", [&](const nlohmann::json& n, const std::string& path) {
      checkInteger(n, "mesh", opt, path);
      checkInteger(n, "camera", opt, path);
      checkInteger(n, "skin", opt, path);
      checkIndexArray(n, "children", path);
      // tinygltf drops a transform property that is not an array of numbers (a string
      // "1 2 3"), and the node would silently sit at the origin.
      checkNumberArray(n, "translation", path, 3);
      checkNumberArray(n, "rotation", path, 4);
      checkNumberArray(n, "scale", path, 3);
      checkNumberArray(n, "matrix", path, 16);
    });
    forEach(root, "materials", "", [&](const nlohmann::json& m, const std::string& path) {
      // A baseColorFactor of 3 numbers (no alpha) would be read as the default white.
      if (m.is_object() && m.contains("pbrMetallicRoughness"))
        checkNumberArray(m["pbrMetallicRoughness"], "baseColorFactor",
                         path + "/pbrMetallicRoughness", 4);
      checkNumberArray(m, "emissiveFactor", path, 3);
    });
    forEach(root, "scenes", "", [&](const nlohmann::json& scene, const std::string& path) {
      checkIndexArray(scene, "nodes", path);
    });
    forEach(root, "animations", "", [&](const nlohmann::json& a, const std::string& path) {
      forEach(a, "samplers", path, [&](const nlohmann::json& sampler, const std::string& p) {
        checkInteger(sampler, "input", req, p);
        checkInteger(sampler, "output", req, p);
      });
      forEach(a, "channels", path, [&](const nlohmann::json& channel, const std::string& p) {
        checkInteger(channel, "sampler", req, p);
        if (channel.is_object() && channel.contains("target"))
          checkInteger(channel["target"], "node", opt, p + "/target");
      });
    });
  }

  void checkRequiredExtensions() {
    // Extensions that change geometry or its encoding must be understood; those about textures
    // and shading only change what Penumbra ignores anyway.
    for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
      const std::string& name = model_.extensionsRequired[i];
      const bool supported =
          name == "KHR_mesh_quantization" || name.rfind("KHR_materials_", 0) == 0 ||
          name.rfind("KHR_texture_", 0) == 0 || name.rfind("EXT_texture_", 0) == 0;
      if (!supported)
        fail(indexPath("/extensionsRequired", i),
             "required extension " + name + " is not supported");
    }
    for (const std::string& name : model_.extensionsUsed)
      if (name == "KHR_mesh_quantization") quantization_ = true;
  }

  // ---- Accessors ------------------------------------------------------------------------------

  bool componentTypeAllowed(AccessorRole role, int componentType, bool normalized) const {
    const bool smallInt = componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                          componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
                          componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    const bool isFloat = componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    switch (role) {
      case AccessorRole::kPosition:
      case AccessorRole::kTranslation:
      case AccessorRole::kScale:
        return (isFloat && !normalized) || (quantization_ && smallInt);
      case AccessorRole::kIndices:
        return !normalized && (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                               componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                               componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
      case AccessorRole::kTime:
        return isFloat && !normalized;
      case AccessorRole::kRotation:
        return (isFloat && !normalized) || (smallInt && normalized);
    }
    return false;
  }

  static int expectedType(AccessorRole role) {
    switch (role) {
      case AccessorRole::kIndices:
      case AccessorRole::kTime:
        return TINYGLTF_TYPE_SCALAR;
      case AccessorRole::kRotation:
        return TINYGLTF_TYPE_VEC4;
      default:
        return TINYGLTF_TYPE_VEC3;
    }
  }

  // A checked bufferView: its bytes lie inside its buffer.
  const tinygltf::BufferView& checkedView(int index, const std::string& referencePath) const {
    if (index < 0 || size_t(index) >= model_.bufferViews.size())
      fail(referencePath, "bufferView " + std::to_string(index) + " does not exist (the file has " +
                              std::to_string(model_.bufferViews.size()) + ")");
    const tinygltf::BufferView& view = model_.bufferViews[size_t(index)];
    const std::string viewPath = indexPath("/bufferViews", size_t(index));
    if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
      fail(viewPath + "/buffer", "buffer " + std::to_string(view.buffer) + " does not exist");
    const size_t size = model_.buffers[size_t(view.buffer)].data.size();
    if (view.byteLength > size || view.byteOffset > size - view.byteLength)
      fail(viewPath, "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                         std::to_string(view.byteLength) + " runs past the end of /buffers/" +
                         std::to_string(view.buffer) + ", which has " + std::to_string(size) +
                         " bytes");
    return view;
  }

  const unsigned char* viewData(const tinygltf::BufferView& view) const {
    return model_.buffers[size_t(view.buffer)].data.data() + view.byteOffset;
  }

  // Reads accessor `index`, used as `role` by the JSON property at `referencePath`, into doubles
  // (normalized integers converted), checking every range against the actual data.
  AccessorValues readAccessor(int index, AccessorRole role, const std::string& referencePath,
                              const std::string& roleName) const {
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail(referencePath, "accessor " + std::to_string(index) + " does not exist (the file has " +
                              std::to_string(model_.accessors.size()) + ")");
    const tinygltf::Accessor& accessor = model_.accessors[size_t(index)];
    const std::string accessorPath = indexPath("/accessors", size_t(index));
    const std::string usedAs = " (read as " + roleName + " for " + referencePath + ")";
    if (accessor.type != expectedType(role))
      fail(referencePath, roleName + " must be a " + typeName(expectedType(role)) +
                              " accessor, but " + accessorPath + " has type " +
                              typeName(accessor.type));
    if (!componentTypeAllowed(role, accessor.componentType, accessor.normalized))
      fail(referencePath,
           roleName + " cannot have component type " + (accessor.normalized ? "normalized " : "") +
               componentTypeName(accessor.componentType) + " (" + accessorPath + ")" +
               (role == AccessorRole::kPosition && !quantization_
                    ? "; only FLOAT is legal without KHR_mesh_quantization"
                    : ""));
    const int components = typeComponentCount(accessor.type);
    const size_t elementSize = size_t(components) * size_t(componentSize(accessor.componentType));
    AccessorValues out;
    out.count = accessor.count;
    out.components = components;
    if (accessor.bufferView < 0) {
      // No bufferView: zeros, to be replaced by sparse values.
      if (accessor.count > kMaxElementsWithoutBufferView)
        fail(accessorPath, "count " + std::to_string(accessor.count) +
                               " is implausible for an accessor without a bufferView" + usedAs);
      out.values.assign(accessor.count * size_t(components), 0.0);
    } else {
      const tinygltf::BufferView& view =
          checkedView(accessor.bufferView, accessorPath + "/bufferView");
      const size_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
      if (stride < elementSize)
        fail(indexPath("/bufferViews", size_t(accessor.bufferView)),
             "byteStride " + std::to_string(stride) + " is smaller than the " +
                 std::to_string(elementSize) + "-byte elements of " + accessorPath);
      if (!elementsFit(accessor.byteOffset, accessor.count, stride, elementSize, view.byteLength))
        fail(accessorPath, std::to_string(accessor.count) + " elements of " +
                               std::to_string(elementSize) + " bytes at byteOffset " +
                               std::to_string(accessor.byteOffset) + " (stride " +
                               std::to_string(stride) + ") run past the end of /bufferViews/" +
                               std::to_string(accessor.bufferView) + ", which has " +
                               std::to_string(view.byteLength) + " bytes" + usedAs);
      out.values.resize(accessor.count * size_t(components));
      const unsigned char* base = viewData(view) + accessor.byteOffset;
      const size_t size = size_t(componentSize(accessor.componentType));
      for (size_t e = 0; e < accessor.count; ++e)
        for (int c = 0; c < components; ++c)
          out.values[e * size_t(components) + size_t(c)] = decodeComponent(
              base + e * stride + size_t(c) * size, accessor.componentType, accessor.normalized);
    }
    if (accessor.sparse.isSparse) applySparse(accessor, accessorPath, usedAs, out);
    for (size_t i = 0; i < out.values.size(); ++i)
      if (!std::isfinite(out.values[i]))
        fail(referencePath, roleName + " element " + std::to_string(i / size_t(components)) + " (" +
                                accessorPath +
                                ") has a non-finite component: " + describeNumber(out.values[i]));
    return out;
  }

  void applySparse(const tinygltf::Accessor& accessor, const std::string& accessorPath,
                   const std::string& usedAs, AccessorValues& out) const {
    const auto& sparse = accessor.sparse;
    const std::string sparsePath = accessorPath + "/sparse";
    if (sparse.count < 1 || size_t(sparse.count) > accessor.count)
      fail(sparsePath + "/count", "count " + std::to_string(sparse.count) +
                                      " must be between 1 and the accessor's count " +
                                      std::to_string(accessor.count) + usedAs);
    const size_t count = size_t(sparse.count);
    const int indexType = sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(sparsePath + "/indices/componentType",
           "sparse indices must be unsigned integers, not " + componentTypeName(indexType));
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
      fail(sparsePath, "negative byteOffset");
    const size_t indexSize = size_t(componentSize(indexType));
    const tinygltf::BufferView& indexView =
        checkedView(sparse.indices.bufferView, sparsePath + "/indices/bufferView");
    if (!elementsFit(size_t(sparse.indices.byteOffset), count, indexSize, indexSize,
                     indexView.byteLength))
      fail(sparsePath + "/indices", "the indices run past the end of their bufferView" + usedAs);
    const size_t elementSize =
        size_t(out.components) * size_t(componentSize(accessor.componentType));
    const tinygltf::BufferView& valueView =
        checkedView(sparse.values.bufferView, sparsePath + "/values/bufferView");
    if (!elementsFit(size_t(sparse.values.byteOffset), count, elementSize, elementSize,
                     valueView.byteLength))
      fail(sparsePath + "/values", "the values run past the end of their bufferView" + usedAs);
    const unsigned char* indices = viewData(indexView) + sparse.indices.byteOffset;
    const unsigned char* values = viewData(valueView) + sparse.values.byteOffset;
    const size_t size = size_t(componentSize(accessor.componentType));
    double previous = -1;
    for (size_t k = 0; k < count; ++k) {
      const double target = decodeComponent(indices + k * indexSize, indexType, false);
      if (target <= previous || target >= double(accessor.count))
        fail(sparsePath + "/indices",
             "index " + std::to_string(k) + " is " + describeNumber(target) +
                 "; sparse indices must increase strictly and stay below " +
                 std::to_string(accessor.count) + usedAs);
      previous = target;
      for (int c = 0; c < out.components; ++c)
        out.values[size_t(target) * size_t(out.components) + size_t(c)] =
            decodeComponent(values + k * elementSize + size_t(c) * size, accessor.componentType,
                            accessor.normalized);
    }
  }

  // ---- Node hierarchy -------------------------------------------------------------------------

  static bool allFinite(const std::vector<double>& values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
  }

  void buildHierarchy() {
    const size_t count = model_.nodes.size();
    nodes_.assign(count, NodeInfo{});
    for (size_t i = 0; i < count; ++i) {
      const tinygltf::Node& node = model_.nodes[i];
      const std::string nodePath = indexPath("/nodes", i);
      for (size_t k = 0; k < node.children.size(); ++k) {
        const int child = node.children[k];
        const std::string childPath = indexPath(nodePath + "/children", k);
        if (child < 0 || size_t(child) >= count)
          fail(childPath, "node " + std::to_string(child) + " does not exist");
        if (size_t(child) == i) fail(childPath, "a node cannot be its own child");
        if (nodes_[size_t(child)].parent >= 0)
          fail(childPath, "node " + std::to_string(child) + " already has parent node " +
                              std::to_string(nodes_[size_t(child)].parent) +
                              "; glTF nodes form a forest");
        nodes_[size_t(child)].parent = int(i);
      }
      if (node.mesh >= 0 && size_t(node.mesh) >= model_.meshes.size())
        fail(nodePath + "/mesh", "mesh " + std::to_string(node.mesh) + " does not exist");
      if (node.camera >= 0 && size_t(node.camera) >= model_.cameras.size())
        fail(nodePath + "/camera", "camera " + std::to_string(node.camera) + " does not exist");
      readLocalTransform(i, nodePath);
    }
    // Parents before children; nodes never reached from a root lie on a cycle.
    std::vector<bool> visited(count, false);
    std::vector<int> stack;
    for (size_t i = 0; i < count; ++i)
      if (nodes_[i].parent < 0) stack.push_back(int(i));
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      visited[size_t(n)] = true;
      topologicalOrder_.push_back(n);
      for (int child : model_.nodes[size_t(n)].children) stack.push_back(child);
    }
    for (size_t i = 0; i < count; ++i)
      if (!visited[i])
        fail(indexPath("/nodes", i), "the node hierarchy has a cycle through this node");
  }

  void readLocalTransform(size_t index, const std::string& nodePath) {
    const tinygltf::Node& node = model_.nodes[index];
    NodeInfo& info = nodes_[index];
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16 || !allFinite(node.matrix))
        fail(nodePath + "/matrix", "matrix must be 16 finite numbers");
      const std::vector<double>& m = node.matrix;  // column-major
      if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1)
        fail(nodePath + "/matrix", "matrix is not affine: its last row must be (0, 0, 0, 1)");
      info.hasMatrix = true;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) info.matrix.linear.m[r][c] = m[size_t(c * 4 + r)];
      info.matrix.translation = {m[12], m[13], m[14]};
      return;
    }
    if (!node.translation.empty()) {
      if (node.translation.size() != 3 || !allFinite(node.translation))
        fail(nodePath + "/translation", "translation must be 3 finite numbers");
      info.trs.translation = {node.translation[0], node.translation[1], node.translation[2]};
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4 || !allFinite(node.rotation))
        fail(nodePath + "/rotation", "rotation must be 4 finite numbers (x, y, z, w)");
      info.trs.rotation = normalizedRotation(
          {node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]},
          nodePath + "/rotation");
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3 || !allFinite(node.scale))
        fail(nodePath + "/scale", "scale must be 3 finite numbers");
      info.trs.scale = {node.scale[0], node.scale[1], node.scale[2]};
    }
  }

  // glTF quaternions are (x, y, z, w) and should be unit; renormalize the float rounding away.
  Quaternion normalizedRotation(const std::array<double, 4>& xyzw, const std::string& where) const {
    const Quaternion q{xyzw[3], xyzw[0], xyzw[1], xyzw[2]};
    const double norm = std::sqrt(q.dotWith(q));
    if (!(norm > 1e-6) || !std::isfinite(norm))
      fail(where, "rotation quaternion has length " + describeNumber(norm) + ", not 1");
    return q.normalized();
  }

  void selectSceneNodes() {
    std::vector<int> roots;
    if (model_.scenes.empty()) {
      scenePath_ = "/nodes";
      for (size_t i = 0; i < nodes_.size(); ++i)
        if (nodes_[i].parent < 0) roots.push_back(int(i));
    } else {
      if (model_.defaultScene >= int(model_.scenes.size()))
        fail("/scene", "scene " + std::to_string(model_.defaultScene) + " does not exist");
      const size_t scene = model_.defaultScene >= 0 ? size_t(model_.defaultScene) : 0;
      scenePath_ = indexPath("/scenes", scene);
      const std::vector<int>& sceneNodes = model_.scenes[scene].nodes;
      for (size_t k = 0; k < sceneNodes.size(); ++k) {
        if (sceneNodes[k] < 0 || size_t(sceneNodes[k]) >= nodes_.size())
          fail(indexPath(scenePath_ + "/nodes", k),
               "node " + std::to_string(sceneNodes[k]) + " does not exist");
        roots.push_back(sceneNodes[k]);
      }
    }
    std::vector<int> stack = roots;
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      if (nodes_[size_t(n)].inScene) continue;  // a root listed twice, or below another root
      nodes_[size_t(n)].inScene = true;
      for (int child : model_.nodes[size_t(n)].children) stack.push_back(child);
    }
  }

  void chooseCamera() {
    for (size_t i = 0; i < nodes_.size(); ++i) {
      const int camera = model_.nodes[i].camera;
      if (nodes_[i].inScene && camera >= 0 &&
          model_.cameras[size_t(camera)].type == "perspective") {
        cameraNode_ = int(i);
        return;
      }
    }
  }

  void markRelevantNodes() {
    for (size_t i = 0; i < nodes_.size(); ++i) {
      if (!nodes_[i].inScene || (model_.nodes[i].mesh < 0 && int(i) != cameraNode_)) continue;
      for (int n = int(i); n >= 0 && !nodes_[size_t(n)].relevant; n = nodes_[size_t(n)].parent)
        nodes_[size_t(n)].relevant = true;
    }
  }

  // ---- Animation ------------------------------------------------------------------------------

  void loadAnimations() {
    double lastKeyTime = 0;
    std::string lastKeyPath;
    bool animated = false;
    for (size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& animation = model_.animations[a];
      const std::string animationPath = indexPath("/animations", a);
      for (size_t c = 0; c < animation.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = animation.channels[c];
        const std::string channelPath = indexPath(animationPath + "/channels", c);
        if (channel.target_node < 0) continue;  // no target: meant for an extension
        if (size_t(channel.target_node) >= nodes_.size())
          fail(channelPath + "/target/node",
               "node " + std::to_string(channel.target_node) + " does not exist");
        Property property;
        if (channel.target_path == "translation") {
          property = Property::kTranslation;
        } else if (channel.target_path == "rotation") {
          property = Property::kRotation;
        } else if (channel.target_path == "scale") {
          property = Property::kScale;
        } else if (channel.target_path == "weights") {
          continue;  // morph target weights: morph targets are ignored
        } else {
          fail(channelPath + "/target/path", "unknown animation path '" + channel.target_path +
                                                 "' (expected translation, rotation, scale or "
                                                 "weights)");
        }
        if (channel.sampler < 0 || size_t(channel.sampler) >= animation.samplers.size())
          fail(channelPath + "/sampler",
               "sampler " + std::to_string(channel.sampler) + " does not exist");
        NodeInfo& node = nodes_[size_t(channel.target_node)];
        if (!node.relevant) continue;  // moves nothing that is loaded
        if (node.hasMatrix)
          fail(channelPath, "animates node " + std::to_string(channel.target_node) +
                                ", which has a matrix; animated nodes must use translation, "
                                "rotation and scale");
        if (const Channel* other = node.channels[size_t(property)])
          fail(channelPath, "node " + std::to_string(channel.target_node) + "'s " +
                                channel.target_path + " is also animated by " + other->path +
                                "; Penumbra plays all animations at once, so each node property "
                                "may be animated by one channel only");
        channels_.push_back(std::make_unique<Channel>(
            readChannel(animation.samplers[size_t(channel.sampler)],
                        indexPath(animationPath + "/samplers", size_t(channel.sampler)),
                        channelPath, property)));
        node.channels[size_t(property)] = channels_.back().get();
        animated = true;
        if (channels_.back()->times.back() >= lastKeyTime) {
          lastKeyTime = channels_.back()->times.back();
          lastKeyPath = indexPath(animationPath + "/samplers", size_t(channel.sampler)) + "/input";
        }
      }
    }
    frameCount_ = 1;
    if (animated) {
      const double lastFrame = lastKeyTime * kGltfFramesPerSecond;
      const double rounded = std::round(lastFrame);
      const double frames =
          nearTime(lastKeyTime, rounded / kGltfFramesPerSecond) ? rounded : std::ceil(lastFrame);
      if (frames > double(kMaxGltfFrames))
        fail(lastKeyPath, "the animation lasts " + describeNumber(lastKeyTime) + " s; at most " +
                              std::to_string(kMaxGltfFrames) + " frames (" +
                              std::to_string(kMaxGltfFrames / kGltfFramesPerSecond) + " s at " +
                              std::to_string(kGltfFramesPerSecond) + " fps) are supported");
      frameCount_ = static_cast<long long>(frames) + 1;
    }
    for (int n : topologicalOrder_) {
      NodeInfo& node = nodes_[size_t(n)];
      const bool own = node.channels[0] || node.channels[1] || node.channels[2];
      node.timeVarying = own || (node.parent >= 0 && nodes_[size_t(node.parent)].timeVarying);
    }
  }

  Channel readChannel(const tinygltf::AnimationSampler& sampler, const std::string& samplerPath,
                      const std::string& channelPath, Property property) const {
    Channel channel;
    channel.path = channelPath;
    channel.property = property;
    if (sampler.interpolation.empty() || sampler.interpolation == "LINEAR") {
      channel.interpolation = Interpolation::kLinear;
    } else if (sampler.interpolation == "STEP") {
      channel.interpolation = Interpolation::kStep;
    } else if (sampler.interpolation == "CUBICSPLINE") {
      channel.interpolation = Interpolation::kCubicSpline;
    } else {
      fail(samplerPath + "/interpolation", "unknown interpolation '" + sampler.interpolation +
                                               "' (expected LINEAR, STEP or CUBICSPLINE)");
    }
    channel.times =
        readAccessor(sampler.input, AccessorRole::kTime, samplerPath + "/input", "key times")
            .values;
    if (channel.times.empty()) fail(samplerPath + "/input", "an animation sampler needs keys");
    for (size_t k = 0; k < channel.times.size(); ++k) {
      if (channel.times[k] < 0)
        fail(samplerPath + "/input",
             "key time " + std::to_string(k) + " is negative: " + describeNumber(channel.times[k]));
      if (k > 0 && !(channel.times[k] > channel.times[k - 1]))
        fail(samplerPath + "/input", "key times must increase strictly, but key " +
                                         std::to_string(k) + " is at " +
                                         describeNumber(channel.times[k]) + " s after " +
                                         describeNumber(channel.times[k - 1]) + " s");
    }
    const AccessorRole role = property == Property::kTranslation ? AccessorRole::kTranslation
                              : property == Property::kRotation  ? AccessorRole::kRotation
                                                                 : AccessorRole::kScale;
    channel.output =
        readAccessor(sampler.output, role, samplerPath + "/output",
                     "animated " + std::string(property == Property::kTranslation ? "translation"
                                               : property == Property::kRotation  ? "rotation"
                                                                                  : "scale"));
    const size_t perKey = channel.interpolation == Interpolation::kCubicSpline ? 3 : 1;
    if (channel.output.count != channel.times.size() * perKey)
      fail(samplerPath + "/output", "has " + std::to_string(channel.output.count) +
                                        " elements for " + std::to_string(channel.times.size()) +
                                        " keys; expected " +
                                        std::to_string(channel.times.size() * perKey));
    return channel;
  }

  Transform localTransformAt(size_t index, double time) const {
    const NodeInfo& node = nodes_[index];
    if (node.hasMatrix) return node.matrix;
    TrsValues trs = node.trs;
    if (const Channel* c = node.channels[size_t(Property::kTranslation)]) {
      const auto v = sample(*c, time);
      trs.translation = {v[0], v[1], v[2]};
    }
    if (const Channel* c = node.channels[size_t(Property::kRotation)])
      trs.rotation = normalizedRotation(sample(*c, time), c->path);
    if (const Channel* c = node.channels[size_t(Property::kScale)]) {
      const auto v = sample(*c, time);
      trs.scale = {v[0], v[1], v[2]};
    }
    return Transform::fromTrs(trs.translation, trs.rotation, trs.scale);
  }

  // World transforms of every node at `time` (animated nodes sampled; the rest unanimated).
  void computeWorldTransforms(double time, bool onlyTimeVarying,
                              std::vector<Transform>& world) const {
    world.resize(nodes_.size());
    for (int n : topologicalOrder_) {
      const NodeInfo& node = nodes_[size_t(n)];
      if (onlyTimeVarying && !(node.timeVarying && node.relevant)) continue;
      const Transform local = localTransformAt(size_t(n), time);
      world[size_t(n)] = node.parent >= 0 ? world[size_t(node.parent)] * local : local;
    }
  }

  // ---- Materials, meshes, objects, camera -----------------------------------------------------

  std::string uniqueName(const std::string& base, std::set<std::string>& used) const {
    std::string name = base;
    for (int k = 2; !used.insert(name).second; ++k) name = base + " (" + std::to_string(k) + ")";
    return name;
  }

  std::vector<Material> convertMaterials() {
    std::vector<Material> materials;
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& source = model_.materials[i];
      const std::string materialPath = indexPath("/materials", i);
      Material material;
      material.name = uniqueName(
          source.name.empty() ? "material " + std::to_string(i) : source.name, materialNames_);
      const std::vector<double>& base = source.pbrMetallicRoughness.baseColorFactor;
      if (base.size() != 4 || !allFinite(base) ||
          std::any_of(base.begin(), base.end(), [](double v) { return v < 0 || v > 1; }))
        fail(materialPath + "/pbrMetallicRoughness/baseColorFactor",
             "baseColorFactor must be 4 numbers in [0, 1]");
      material.reflectance = {std::min(base[0], kMaxGltfReflectance),
                              std::min(base[1], kMaxGltfReflectance),
                              std::min(base[2], kMaxGltfReflectance)};
      const std::vector<double>& emissive = source.emissiveFactor;
      if (emissive.size() != 3 || !allFinite(emissive) ||
          std::any_of(emissive.begin(), emissive.end(), [](double v) { return v < 0 || v > 1; }))
        fail(materialPath + "/emissiveFactor", "emissiveFactor must be 3 numbers in [0, 1]");
      double strength = 1;
      const auto extension = source.extensions.find("KHR_materials_emissive_strength");
      if (extension != source.extensions.end() && extension->second.Has("emissiveStrength")) {
        const tinygltf::Value& value = extension->second.Get("emissiveStrength");
        strength = value.IsNumber() ? value.GetNumberAsDouble() : -1;
        if (!(strength >= 0) || !std::isfinite(strength))
          fail(materialPath + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
               "emissiveStrength must be a finite number >= 0");
      }
      material.emission = Rgb{emissive[0], emissive[1], emissive[2]} * strength;
      materials.push_back(material);
    }
    return materials;
  }

  int defaultMaterial(std::vector<Material>& materials) {
    if (defaultMaterial_ < 0) {
      Material material;
      material.name = uniqueName("default", materialNames_);
      // glTF's default material is white (clamped like every base colour) and not emissive.
      material.reflectance = Rgb::gray(kMaxGltfReflectance);
      defaultMaterial_ = int(materials.size());
      materials.push_back(material);
    }
    return defaultMaterial_;
  }

  struct MeshTriangles {
    std::vector<Polygon3> polygons;
    std::vector<int> materials;
    std::vector<std::string> origins;
  };

  const MeshTriangles& meshTriangles(size_t meshIndex, std::vector<Material>& materials) {
    auto cached = meshCache_.find(meshIndex);
    if (cached != meshCache_.end()) return cached->second;
    MeshTriangles out;
    const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
    for (size_t p = 0; p < mesh.primitives.size(); ++p)
      appendPrimitive(mesh.primitives[p],
                      indexPath(indexPath("/meshes", meshIndex) + "/primitives", p), materials,
                      out);
    return meshCache_.emplace(meshIndex, std::move(out)).first->second;
  }

  void appendPrimitive(const tinygltf::Primitive& primitive, const std::string& primitivePath,
                       std::vector<Material>& materials, MeshTriangles& out) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE ||
        mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP)
      return;  // no area
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN)
      fail(primitivePath + "/mode", "unknown primitive mode " + std::to_string(mode));
    int material;
    if (primitive.material < 0) {
      material = defaultMaterial(materials);
    } else if (size_t(primitive.material) >= model_.materials.size()) {
      fail(primitivePath + "/material",
           "material " + std::to_string(primitive.material) + " does not exist");
    } else {
      material = primitive.material;
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end())
      fail(primitivePath + "/attributes", "triangle primitive has no POSITION attribute");
    const AccessorValues positions =
        readAccessor(position->second, AccessorRole::kPosition,
                     primitivePath + "/attributes/POSITION", "POSITION");
    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
      const AccessorValues values = readAccessor(primitive.indices, AccessorRole::kIndices,
                                                 primitivePath + "/indices", "indices");
      indices.reserve(values.count);
      for (size_t k = 0; k < values.count; ++k) {
        const double index = values.values[k];
        if (index >= double(positions.count))
          fail(primitivePath + "/indices", "index " + std::to_string(k) + " is " +
                                               describeNumber(index) + ", but POSITION has only " +
                                               std::to_string(positions.count) + " vertices");
        indices.push_back(uint32_t(index));
      }
    } else {
      if (positions.count > std::numeric_limits<uint32_t>::max())
        fail(primitivePath + "/attributes/POSITION", "too many vertices");
      indices.resize(positions.count);
      for (size_t k = 0; k < positions.count; ++k) indices[k] = uint32_t(k);
    }
    const size_t n = indices.size();
    if (mode == TINYGLTF_MODE_TRIANGLES && n % 3 != 0)
      fail(primitive.indices >= 0 ? primitivePath + "/indices"
                                  : primitivePath + "/attributes/POSITION",
           "a TRIANGLES primitive needs a multiple of 3 vertices, not " + std::to_string(n));
    const size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
    for (size_t t = 0; t < triangles; ++t) {
      std::array<uint32_t, 3> corner;
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        corner = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
      } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // Every other strip triangle is flipped to keep the winding (spec §3.7.2.1).
        corner = t % 2 == 0 ? std::array{indices[t], indices[t + 1], indices[t + 2]}
                            : std::array{indices[t], indices[t + 2], indices[t + 1]};
      } else {
        corner = {indices[t + 1], indices[t + 2], indices[0]};
      }
      // Strips and fans are stitched with repeated indices; such triangles are not geometry.
      if (mode != TINYGLTF_MODE_TRIANGLES &&
          (corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2]))
        continue;
      Polygon3 triangle;
      for (uint32_t v : corner)
        triangle.push_back({positions.at(v, 0), positions.at(v, 1), positions.at(v, 2)});
      if (const auto defect = findPolygonDefect(triangle))
        fail(primitivePath, "triangle " + std::to_string(t) + " (vertices " +
                                std::to_string(corner[0]) + ", " + std::to_string(corner[1]) +
                                ", " + std::to_string(corner[2]) + "): " + *defect);
      out.polygons.push_back(std::move(triangle));
      out.materials.push_back(material);
      out.origins.push_back(path_ + ": " + primitivePath + " triangle " + std::to_string(t));
    }
  }

  void buildObjects(Scene& scene) {
    std::set<std::string> objectNames;
    std::vector<Transform> world;
    computeWorldTransforms(0, false, world);
    std::vector<size_t> dynamicNodes;  // node of each dynamic object
    std::vector<size_t> dynamicObjects;
    for (size_t i = 0; i < nodes_.size(); ++i) {
      const tinygltf::Node& node = model_.nodes[i];
      if (!nodes_[i].inScene || node.mesh < 0) continue;
      const MeshTriangles& mesh = meshTriangles(size_t(node.mesh), scene.materials);
      if (mesh.polygons.empty()) continue;
      SceneObject object;
      object.name =
          uniqueName(node.name.empty() ? "node " + std::to_string(i) : node.name, objectNames);
      object.polygons = mesh.polygons;
      object.polygonMaterial = mesh.materials;
      object.polygonOrigin = mesh.origins;
      if (nodes_[i].timeVarying) {
        dynamicNodes.push_back(i);
        dynamicObjects.push_back(scene.objects.size());
      } else {
        placeStaticObject(object, world[i], indexPath("/nodes", i));
      }
      scene.objects.push_back(std::move(object));
    }
    if (dynamicNodes.empty()) return;
    std::vector<std::vector<Keyframe>> keyframes(dynamicNodes.size());
    for (auto& k : keyframes) k.reserve(size_t(frameCount_));
    for (long long f = 0; f < frameCount_; ++f) {
      const double time = double(f) / kGltfFramesPerSecond;
      computeWorldTransforms(time, true, world);
      for (size_t d = 0; d < dynamicNodes.size(); ++d) {
        const Decomposition decomposition =
            decompose(world[dynamicNodes[d]], kAnimatedShearTolerance);
        const std::string nodePath = indexPath("/nodes", dynamicNodes[d]);
        const std::string when =
            " at frame " + std::to_string(f) + " (t = " + describeNumber(time) + " s)";
        if (decomposition.result == DecompositionResult::kSingular)
          fail(nodePath, "the animated world transform is singular (a zero scale)" + when);
        if (decomposition.result == DecompositionResult::kShear)
          fail(nodePath, "the animated world transform has shear" + when +
                             " (a non-uniform scale above a rotated node); animated objects need "
                             "a translate·rotate·scale world transform");
        TrsPose pose = decomposition.pose;
        // q and -q are the same rotation; keep neighbours on the same side for tidy data.
        if (!keyframes[d].empty() && keyframes[d].back().pose.rotate.dotWith(pose.rotate) < 0)
          pose.rotate = {-pose.rotate.w, -pose.rotate.x, -pose.rotate.y, -pose.rotate.z};
        keyframes[d].push_back({int(f), pose});
      }
    }
    for (size_t d = 0; d < dynamicNodes.size(); ++d) {
      SceneObject& object = scene.objects[dynamicObjects[d]];
      object.transform = keyframes[d].front().pose;
      object.motion = Motion(std::move(keyframes[d]));
    }
  }

  void placeStaticObject(SceneObject& object, const Transform& world,
                         const std::string& nodePath) const {
    const Decomposition decomposition = decompose(world, kStaticTrsTolerance);
    if (decomposition.result == DecompositionResult::kSingular)
      fail(nodePath, "the world transform is singular (a zero scale), which flattens the mesh");
    if (decomposition.result == DecompositionResult::kOk &&
        reproduces(decomposition.pose, world, kStaticTrsTolerance)) {
      object.transform = decomposition.pose;
      return;
    }
    // Shear is not a TrsPose: bake the whole transform into the vertices.
    for (Polygon3& polygon : object.polygons) {
      for (Vec3& p : polygon) p = world.applyToPoint(p);
      if (world.isReflection()) std::reverse(polygon.begin(), polygon.end());
    }
    object.transform = TrsPose{};
  }

  Camera convertCamera() const {
    const size_t node = size_t(cameraNode_);
    const size_t cameraIndex = size_t(model_.nodes[node].camera);
    const tinygltf::PerspectiveCamera& source = model_.cameras[cameraIndex].perspective;
    const std::string cameraPath = indexPath("/cameras", cameraIndex) + "/perspective";
    std::vector<Transform> world;
    computeWorldTransforms(0, false, world);
    const Transform& pose = world[node];
    const Vec3 forward = pose.applyToVector({0, 0, -1});
    const Vec3 up = pose.applyToVector({0, 1, 0});
    if (!(length(forward) > 0) || !(length(up) > 0) || !forward.isFinite() || !up.isFinite())
      fail(indexPath("/nodes", node), "the camera node's world transform is singular");
    if (!std::isfinite(source.yfov) || !(source.yfov > 0) || !(source.yfov < std::numbers::pi))
      fail(cameraPath + "/yfov",
           "yfov must be between 0 and pi radians, not " + describeNumber(source.yfov));
    Camera camera;
    camera.eye = pose.translation;
    camera.target = camera.eye + normalize(forward);
    camera.up = normalize(up);
    camera.fovYDegrees = source.yfov * 180 / std::numbers::pi;
    if (source.aspectRatio != 0) {
      const double width = std::round(kDefaultCameraHeight * source.aspectRatio);
      if (!std::isfinite(source.aspectRatio) || !(width >= 1) || width > kMaxCameraWidth)
        fail(cameraPath + "/aspectRatio",
             "aspectRatio " + describeNumber(source.aspectRatio) + " gives an implausible width");
      camera.width = int(width);
      camera.height = kDefaultCameraHeight;
    }
    return camera;
  }

  std::string path_;
  tinygltf::Model model_;
  bool quantization_ = false;
  std::vector<NodeInfo> nodes_;
  std::vector<int> topologicalOrder_;
  std::string scenePath_;
  int cameraNode_ = -1;
  std::vector<std::unique_ptr<Channel>> channels_;
  long long frameCount_ = 1;
  std::set<std::string> materialNames_;
  int defaultMaterial_ = -1;
  std::map<size_t, MeshTriangles> meshCache_;
};

}  // namespace

Scene loadGltfScene(const std::string& path) {
  return GltfSceneReader(path).read();
}

}  // namespace penumbra
