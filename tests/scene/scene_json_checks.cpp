#include "scene_json_checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

namespace penumbra::scene_checks {
namespace {

using nlohmann::json;

// Touching solids may interpenetrate by this much (metres): coordinates are written with 6
// decimals, and rotations add rounding of their own.
constexpr double kTouch = 1e-6;
// A light must keep at least this clear of every solid.
constexpr double kLightClearance = 1e-4;

void requireKeys(const json& j, std::initializer_list<const char*> allowed,
                 const std::string& where) {
  if (!j.is_object()) throw std::runtime_error(where + ": expected an object");
  for (const auto& [key, value] : j.items()) {
    if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }) ==
        allowed.end())
      throw std::runtime_error(where + ": unknown key \"" + key + "\"");
  }
}

Vec3 toVec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error(where + ": expected [x, y, z]");
  Vec3 v{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  if (!v.isFinite()) throw std::runtime_error(where + ": not finite");
  return v;
}

TrsPose toPose(const json& j, const std::string& where) {
  TrsPose pose;
  if (j.contains("translate")) pose.translate = toVec3(j["translate"], where + ".translate");
  if (j.contains("scale")) pose.scale = toVec3(j["scale"], where + ".scale");
  if (j.contains("rotate")) {
    const json& r = j["rotate"];
    requireKeys(r, {"axis", "degrees"}, where + ".rotate");
    pose.rotate = Quaternion::fromAxisAngle(normalize(toVec3(r["axis"], where + ".rotate.axis")),
                                            r["degrees"].get<double>() * std::numbers::pi / 180);
  }
  return pose;
}

using VertexKey = std::array<long long, 3>;
VertexKey keyOf(const Vec3& v) {
  return {std::llround(v.x * 1e7), std::llround(v.y * 1e7), std::llround(v.z * 1e7)};
}

// Directed-edge closure: every edge a->b appears once and b->a appears once.
std::vector<std::string> closureProblems(const std::vector<Polygon3>& polygons,
                                         const std::string& what) {
  std::map<std::pair<VertexKey, VertexKey>, int> edges;
  for (const Polygon3& p : polygons)
    for (size_t i = 0; i < p.size(); ++i) ++edges[{keyOf(p[i]), keyOf(p[(i + 1) % p.size()])}];
  std::vector<std::string> problems;
  for (const auto& [edge, count] : edges) {
    const auto reverse = edges.find({edge.second, edge.first});
    const int back = reverse == edges.end() ? 0 : reverse->second;
    if (count != 1 || back != 1) {
      std::ostringstream out;
      out << what << ": edge from (" << edge.first[0] * 1e-7 << ", " << edge.first[1] * 1e-7 << ", "
          << edge.first[2] * 1e-7 << ") to (" << edge.second[0] * 1e-7 << ", "
          << edge.second[1] * 1e-7 << ", " << edge.second[2] * 1e-7 << ") appears " << count
          << " times, reversed " << back << " times (want 1 and 1)";
      problems.push_back(out.str());
      if (problems.size() >= 5) break;
    }
  }
  return problems;
}

// The polygons of an object grouped into solids: connected through shared vertices.
std::vector<std::vector<int>> solidsOf(const JsonObject& object) {
  const int n = int(object.polygons.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::map<VertexKey, int> owner;
  for (int i = 0; i < n; ++i)
    for (const Vec3& v : object.polygons[i]) {
      const auto [it, inserted] = owner.emplace(keyOf(v), i);
      if (!inserted) parent[find(i)] = find(it->second);
    }
  std::map<int, std::vector<int>> groups;
  for (int i = 0; i < n; ++i) groups[find(i)].push_back(i);
  std::vector<std::vector<int>> out;
  for (auto& [root, members] : groups) out.push_back(std::move(members));
  return out;
}

Polygon3 transformed(const Polygon3& p, const Transform& t) {
  Polygon3 out;
  for (const Vec3& v : p) out.push_back(t.applyToPoint(v));
  return out;
}

// A convex solid (or a flat convex polygon) for separating-axis tests.
struct Piece {
  std::string name;  // "object/solid index"
  int object = 0;
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;  // candidate axes of its own
  std::vector<Vec3> edges;    // unit edge directions, one per parallel class
  Box3 box;
};

void addDirection(std::vector<Vec3>& list, const Vec3& v) {
  const double len = length(v);
  if (len < 1e-12) return;
  const Vec3 u = v / len;
  for (const Vec3& w : list)
    if (length(cross(u, w)) < 1e-9) return;
  list.push_back(u);
}

Piece makePiece(const std::vector<Polygon3>& faces, bool flat) {
  Piece piece;
  std::set<VertexKey> seen;
  for (const Polygon3& f : faces) {
    const Vec3 n = newellNormal(f);
    addDirection(piece.normals, n);
    for (size_t i = 0; i < f.size(); ++i) {
      const Vec3 e = f[(i + 1) % f.size()] - f[i];
      addDirection(piece.edges, e);
      // A flat polygon's separating planes include those through its edges, across its plane.
      if (flat) addDirection(piece.normals, cross(n, e));
      if (seen.insert(keyOf(f[i])).second) {
        piece.vertices.push_back(f[i]);
        piece.box.extend(f[i]);
      }
    }
  }
  return piece;
}

// The largest gap between the projections of `a` (swept by `sweep`) and `b` over the candidate
// separating axes: positive means separated by at least that much, zero touching, negative
// overlapping (for convex pieces the separating-axis theorem makes this exact in sign).
double separation(const Piece& a, const Piece& b, const Vec3& sweep) {
  std::vector<Vec3> axes = a.normals;
  axes.insert(axes.end(), b.normals.begin(), b.normals.end());
  for (const Vec3& ea : a.edges)
    for (const Vec3& eb : b.edges) axes.push_back(cross(ea, eb));
  const bool moving = squaredLength(sweep) > 0;
  if (moving) {
    // The swept solid is a's Minkowski sum with the segment: its faces add sweep x edge.
    for (const Vec3& e : a.edges) axes.push_back(cross(sweep, e));
    for (const Vec3& e : b.edges) axes.push_back(cross(sweep, e));
  }
  double best = -std::numeric_limits<double>::infinity();
  for (Vec3 axis : axes) {
    const double len = length(axis);
    if (len < 1e-9) continue;
    axis = axis / len;
    double minA = std::numeric_limits<double>::infinity(), maxA = -minA;
    for (const Vec3& v : a.vertices) {
      const double s = dot(v, axis);
      minA = std::min(minA, s);
      maxA = std::max(maxA, s);
      if (moving) {
        minA = std::min(minA, s + dot(sweep, axis));
        maxA = std::max(maxA, s + dot(sweep, axis));
      }
    }
    double minB = std::numeric_limits<double>::infinity(), maxB = -minB;
    for (const Vec3& v : b.vertices) {
      const double s = dot(v, axis);
      minB = std::min(minB, s);
      maxB = std::max(maxB, s);
    }
    best = std::max({best, minB - maxA, minA - maxB});
  }
  return best;
}

Box3 sweptBox(const Box3& b, const Vec3& sweep) {
  Box3 r = b;
  r.extend(b.min + sweep);
  r.extend(b.max + sweep);
  return r;
}

// Separation of two boxes along the coordinate axes (the cheap necessary test first).
double boxSeparation(const Box3& a, const Box3& b) {
  return std::max({b.min.x - a.max.x, a.min.x - b.max.x, b.min.y - a.max.y, a.min.y - b.max.y,
                   b.min.z - a.max.z, a.min.z - b.max.z});
}

bool isRoom(const JsonObject& o) {
  return o.room;
}
bool isSolidObject(const JsonObject& o) {
  return !o.room && !o.emitter;
}

Box3 roomBox(const JsonScene& scene) {
  Box3 box;
  for (const JsonObject& o : scene.objects)
    if (isRoom(o))
      for (const Polygon3& p : o.polygons)
        for (const Vec3& v : transformed(p, o.placement.toTransform())) box.extend(v);
  return box;
}

// All solids of the scene at a frame, with the solid structure computed once per object.
class Pieces {
 public:
  explicit Pieces(const JsonScene& scene) : scene_(scene) {
    for (size_t i = 0; i < scene.objects.size(); ++i)
      solids_.push_back(isSolidObject(scene.objects[i]) ? solidsOf(scene.objects[i])
                                                        : std::vector<std::vector<int>>{});
  }
  std::vector<Piece> at(double frame) const {
    std::vector<Piece> out;
    for (size_t i = 0; i < scene_.objects.size(); ++i) {
      const JsonObject& o = scene_.objects[i];
      const Transform t = o.poseAt(frame).toTransform();
      for (size_t k = 0; k < solids_[i].size(); ++k) {
        std::vector<Polygon3> faces;
        for (int f : solids_[i][k]) faces.push_back(transformed(o.polygons[f], t));
        Piece p = makePiece(faces, false);
        p.name = o.name + " solid " + std::to_string(k);
        p.object = int(i);
        out.push_back(std::move(p));
      }
    }
    return out;
  }

 private:
  const JsonScene& scene_;
  std::vector<std::vector<std::vector<int>>> solids_;
};

bool translationOnly(const JsonObject& o, int frame) {
  const TrsPose a = o.poseAt(frame), b = o.poseAt(frame + 1);
  return a.rotate.w == b.rotate.w && a.rotate.x == b.rotate.x && a.rotate.y == b.rotate.y &&
         a.rotate.z == b.rotate.z && a.scale == b.scale;
}

std::string describeBox(const Box3& b) {
  std::ostringstream out;
  out << b.min << " - " << b.max;
  return out.str();
}

}  // namespace

int JsonScene::polygonCount() const {
  int n = 0;
  for (const JsonObject& o : objects) n += int(o.polygons.size());
  return n;
}

JsonScene parseScene(const json& j) {
  requireKeys(j, {"penumbra", "materials", "objects", "camera", "frames"}, "scene");
  if (j.at("penumbra").get<int>() != 1) throw std::runtime_error("scene: \"penumbra\" must be 1");
  std::map<std::string, bool> emitting;
  for (const auto& [name, m] : j.at("materials").items()) {
    requireKeys(m, {"reflectance", "emission", "mirror"}, "materials." + name);
    const Vec3 r = toVec3(m.at("reflectance"), "materials." + name + ".reflectance");
    if (std::max({r.x, r.y, r.z}) >= 1 || std::min({r.x, r.y, r.z}) < 0)
      throw std::runtime_error("materials." + name + ": reflectance outside [0, 1)");
    bool emits = false;
    if (m.contains("emission")) {
      const Vec3 e = toVec3(m["emission"], "materials." + name + ".emission");
      emits = e.x > 0 || e.y > 0 || e.z > 0;
    }
    emitting[name] = emits;
  }
  JsonScene scene;
  int lastKeyframe = 0;
  for (size_t i = 0; i < j.at("objects").size(); ++i) {
    const json& o = j["objects"][i];
    const std::string where = "objects[" + std::to_string(i) + "]";
    requireKeys(o, {"name", "material", "polygons", "transform", "motion"}, where);
    JsonObject object;
    object.name = o.at("name").get<std::string>();
    object.room = object.name == "room" || object.name.rfind("room-", 0) == 0;
    const std::string material = o.at("material").get<std::string>();
    if (!emitting.contains(material)) throw std::runtime_error(where + ": unknown material");
    object.emitter = emitting[material];
    for (const json& p : o.at("polygons")) {
      Polygon3 polygon;
      for (const json& v : p) polygon.push_back(toVec3(v, where + ".polygons"));
      object.polygons.push_back(std::move(polygon));
    }
    if (o.contains("transform")) {
      requireKeys(o["transform"], {"translate", "rotate", "scale"}, where + ".transform");
      object.placement = toPose(o["transform"], where + ".transform");
    }
    if (o.contains("motion")) {
      std::vector<Keyframe> keys;
      for (const json& k : o["motion"]) {
        requireKeys(k, {"frame", "translate", "rotate", "scale"}, where + ".motion");
        keys.push_back({k.at("frame").get<int>(), toPose(k, where + ".motion")});
        if (keys.size() > 1 && keys.back().frame <= keys[keys.size() - 2].frame)
          throw std::runtime_error(where + ".motion: frames must increase");
        lastKeyframe = std::max(lastKeyframe, keys.back().frame);
      }
      object.motion = Motion(std::move(keys));
    }
    scene.objects.push_back(std::move(object));
  }
  scene.frames = j.contains("frames") ? j["frames"].get<int>() : lastKeyframe + 1;
  const json& c = j.at("camera");
  requireKeys(c, {"eye", "target", "up", "fov_y_degrees", "width", "height"}, "camera");
  scene.eye = toVec3(c.at("eye"), "camera.eye");
  scene.target = toVec3(c.at("target"), "camera.target");
  scene.up = toVec3(c.at("up"), "camera.up");
  scene.fovYDegrees = c.at("fov_y_degrees").get<double>();
  scene.width = c.at("width").get<int>();
  scene.height = c.at("height").get<int>();
  return scene;
}

JsonScene parseSceneText(const std::string& text) {
  return parseScene(json::parse(text));
}

JsonScene parseSceneFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  return parseScene(json::parse(in));
}

std::vector<std::string> findPolygonProblems(const JsonScene& scene) {
  std::vector<std::string> problems;
  for (const JsonObject& o : scene.objects) {
    const Transform t = o.poseAt(0).toTransform();
    for (size_t i = 0; i < o.polygons.size(); ++i)
      if (const auto defect = findPolygonDefect(transformed(o.polygons[i], t)))
        problems.push_back(o.name + " polygon " + std::to_string(i) + ": " + *defect);
  }
  return problems;
}

std::vector<std::string> findRoomProblems(const JsonScene& scene) {
  std::vector<Polygon3> shell;
  for (const JsonObject& o : scene.objects)
    if (isRoom(o))
      for (const Polygon3& p : o.polygons)
        shell.push_back(transformed(p, o.placement.toTransform()));
  if (shell.empty()) return {"no room objects (named \"room\" or \"room-*\")"};
  std::vector<std::string> problems = closureProblems(shell, "room shell");
  const Vec3 centre = roomBox(scene).center();
  for (size_t i = 0; i < shell.size(); ++i)
    if (dot(newellNormal(shell[i]), centre - centroid(shell[i])) <= 0)
      problems.push_back("room polygon " + std::to_string(i) + " faces away from the room");
  return problems;
}

std::vector<std::string> findSolidProblems(const JsonScene& scene) {
  std::vector<std::string> problems;
  for (const JsonObject& o : scene.objects) {
    if (!isSolidObject(o)) continue;
    const auto solids = solidsOf(o);
    for (size_t k = 0; k < solids.size(); ++k) {
      const std::string what = o.name + " solid " + std::to_string(k);
      std::vector<Polygon3> faces;
      for (int f : solids[k]) faces.push_back(o.polygons[f]);
      const auto open = closureProblems(faces, what);
      problems.insert(problems.end(), open.begin(), open.end());
      double volume = 0, size = 0;
      for (const Polygon3& f : faces) {
        volume += dot(f[0], newellNormal(f)) / 6;
        size = std::max(size, diameter(f));
      }
      if (!(volume > 0)) problems.push_back(what + ": faces point inward (volume <= 0)");
      for (const Polygon3& f : faces) {
        const Vec3 n = normalize(newellNormal(f));
        for (const Polygon3& g : faces)
          for (const Vec3& v : g)
            if (dot(n, v - f[0]) > 1e-7 * (1 + size)) {
              problems.push_back(what + ": not convex");
              goto nextSolid;
            }
      }
    nextSolid:;
    }
  }
  return problems;
}

std::vector<std::string> findLightProblems(const JsonScene& scene) {
  std::vector<std::string> problems;
  const Box3 room = roomBox(scene);
  const Pieces pieces(scene);
  bool any = false;
  for (const JsonObject& o : scene.objects) {
    if (!o.emitter) continue;
    any = true;
    for (int frame = 0; frame < scene.frames; ++frame) {
      const Transform t = o.poseAt(frame).toTransform();
      const std::vector<Piece> solids = pieces.at(frame);
      for (size_t i = 0; i < o.polygons.size(); ++i) {
        const std::string what = o.name + " polygon " + std::to_string(i);
        const Polygon3 p = transformed(o.polygons[i], t);
        if (dot(newellNormal(p), room.center() - centroid(p)) <= 0)
          problems.push_back(what + ": faces away from the room");
        for (const Vec3& v : p)
          if (!room.contains(v)) problems.push_back(what + ": outside the room");
        const Piece light = makePiece({p}, true);
        for (const Piece& s : solids) {
          if (boxSeparation(light.box, s.box) > kLightClearance) continue;
          if (separation(light, s, {}) <= kLightClearance)
            problems.push_back(what + " touches " + s.name + " at frame " + std::to_string(frame));
        }
      }
    }
  }
  if (!any) problems.push_back("no light");
  return problems;
}

std::vector<std::string> findOverlapProblems(const JsonScene& scene, bool objectBoxes) {
  std::vector<std::string> problems;
  auto report = [&](const std::string& text) {
    if (problems.size() < 20) problems.push_back(text);
  };
  const Box3 room = roomBox(scene).expanded(kTouch);
  const Pieces pieces(scene);
  auto meet = [&](const Piece& a, const Piece& b, const Vec3& sweep) {
    if (boxSeparation(sweptBox(a.box, sweep), b.box) >= -kTouch) return false;
    return separation(a, b, sweep) < -kTouch;
  };
  auto dynamic = [&](const Piece& p) { return scene.objects[p.object].isDynamic(); };

  for (int frame = 0; frame < scene.frames; ++frame) {
    const std::vector<Piece> now = pieces.at(frame);
    const std::string at = " at frame " + std::to_string(frame);
    for (const Piece& p : now)
      if (!(room.contains(p.box.min) && room.contains(p.box.max)))
        report(p.name + " leaves the room" + at + ": " + describeBox(p.box));
    // Static pairs and pairs within one (rigid) object need checking once.
    for (size_t i = 0; i < now.size(); ++i)
      for (size_t k = i + 1; k < now.size(); ++k) {
        const bool sameObject = now[i].object == now[k].object;
        const bool moving = !sameObject && (dynamic(now[i]) || dynamic(now[k]));
        if ((frame > 0 && !moving) || !meet(now[i], now[k], {})) continue;
        report(now[i].name + " and " + now[k].name + " interpenetrate" + at);
      }
    if (objectBoxes) {
      std::vector<std::pair<int, Box3>> boxes;
      for (const Piece& p : now) {
        if (boxes.empty() || boxes.back().first != p.object) boxes.push_back({p.object, {}});
        boxes.back().second.extend(p.box);
      }
      for (size_t i = 0; i < boxes.size(); ++i)
        for (size_t k = i + 1; k < boxes.size(); ++k)
          if (boxSeparation(boxes[i].second, boxes[k].second) < -kTouch)
            report("bounding boxes of " + scene.objects[boxes[i].first].name + " and " +
                   scene.objects[boxes[k].first].name + " overlap" + at);
    }
    if (frame + 1 >= scene.frames) continue;

    // Between this frame and the next: exact swept tests where both objects only translate,
    // dense sampling otherwise.
    const std::vector<Piece> next = pieces.at(frame + 1);
    std::vector<std::vector<Piece>> samples;  // computed on first need
    for (size_t i = 0; i < now.size(); ++i)
      for (size_t k = 0; k < now.size(); ++k) {
        const Piece &a = now[i], &b = now[k];
        if (a.object == b.object || !dynamic(a) || (dynamic(b) && k < i)) continue;
        const JsonObject &oa = scene.objects[a.object], &ob = scene.objects[b.object];
        if (translationOnly(oa, frame) && translationOnly(ob, frame)) {
          const Vec3 sweep =
              (next[i].vertices[0] - a.vertices[0]) - (next[k].vertices[0] - b.vertices[0]);
          if (meet(a, b, sweep))
            report(a.name + " passes through " + b.name + " after frame " + std::to_string(frame));
        } else {
          if (samples.empty())
            for (int s = 1; s < 16; ++s) samples.push_back(pieces.at(frame + s / 16.0));
          for (const std::vector<Piece>& mid : samples) {
            if (meet(mid[i], mid[k], {})) {
              report(a.name + " passes through " + b.name + " after frame " +
                     std::to_string(frame));
              break;
            }
          }
        }
      }
    if (objectBoxes) {
      // A moving object's box over the whole step against every other object's box.
      std::map<int, Box3> swept, still;
      for (size_t i = 0; i < now.size(); ++i) {
        auto& target = dynamic(now[i]) ? swept[now[i].object] : still[now[i].object];
        target.extend(now[i].box);
        if (dynamic(now[i])) target.extend(next[i].box);
      }
      for (const auto& [m, mb] : swept)
        for (const auto& [s, sb] : still)
          if (boxSeparation(mb, sb) < -kTouch)
            report("path of " + scene.objects[m].name + " after frame " + std::to_string(frame) +
                   " crosses the bounding box of " + scene.objects[s].name);
    }
  }
  return problems;
}

std::vector<std::string> findCameraProblems(const JsonScene& scene) {
  std::vector<std::string> problems;
  const Box3 room = roomBox(scene);
  if (!room.contains(scene.eye)) problems.push_back("the eye is outside the room");
  const std::vector<Piece> now = Pieces(scene).at(0);
  for (const Piece& p : now)
    if (p.box.contains(scene.eye)) problems.push_back("the eye is inside " + p.name);
  const Vec3 forward = normalize(scene.target - scene.eye);
  const Vec3 right = normalize(cross(forward, scene.up));
  const Vec3 up = cross(right, forward);
  const double tanY = std::tan(scene.fovYDegrees * std::numbers::pi / 360);
  const double tanX = tanY * scene.width / scene.height;
  std::map<int, Box3> dynamicBoxes;
  for (const Piece& p : now)
    if (scene.objects[p.object].isDynamic()) dynamicBoxes[p.object].extend(p.box);
  for (const auto& [object, box] : dynamicBoxes) {
    const Vec3 d = box.center() - scene.eye;
    const double z = dot(d, forward);
    if (!(z > 0) || std::abs(dot(d, right) / z) > tanX || std::abs(dot(d, up) / z) > tanY)
      problems.push_back("dynamic object " + scene.objects[object].name + " is out of view");
  }
  return problems;
}

double closestApproach(const JsonScene& scene, const std::string& objectName) {
  double closest = std::numeric_limits<double>::infinity();
  const Pieces pieces(scene);
  for (int frame = 0; frame < scene.frames; ++frame) {
    const std::vector<Piece> now = pieces.at(frame);
    for (const Piece& a : now) {
      if (scene.objects[a.object].name != objectName) continue;
      for (const Piece& b : now)
        if (b.object != a.object) closest = std::min(closest, separation(a, b, {}));
    }
  }
  return closest;
}

}  // namespace penumbra::scene_checks
