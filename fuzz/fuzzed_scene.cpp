#include "fuzzed_scene.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>

namespace penumbra::fuzz {

namespace {

constexpr double kPi = std::numbers::pi;

// A plane frame: corners are origin + u x + v y with u, v orthonormal.
struct Frame {
  Vec3 origin, u, v;
  Vec3 at(double x, double y) const { return origin + u * x + v * y; }
};

Polygon3 makeLight(FuzzInput& in) {
  const double h = kLightHeight;
  switch (in.integer(0, 3)) {
    case 0:  // a unit square, the common case
      return {{-0.5, -0.5, h}, {-0.5, 0.5, h}, {0.5, 0.5, h}, {0.5, -0.5, h}};
    case 1:  // a triangle: no edge parallel to another
      return {{-0.6, -0.4, h}, {0.1, 0.6, h}, {0.5, -0.3, h}};
    case 2:  // a long thin strip: nearly a linear light
      return {{-1, -0.01, h}, {-1, 0.01, h}, {1, 0.01, h}, {1, -0.01, h}};
    default: {  // the square turned by 30 degrees about the x axis, still facing down
      const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
      Polygon3 light;
      for (const auto& [x, y] : {std::pair{-0.5, -0.5}, {-0.5, 0.5}, {0.5, 0.5}, {0.5, -0.5}})
        light.push_back({x, y * c, h + y * s});
      return light;
    }
  }
}

// x or y of a centre: free, or in line with the light's corners and centre (EV events then
// pass exactly through occluder corners).
double centreCoordinate(FuzzInput& in) {
  switch (in.integer(0, 4)) {
    case 0:
      return -0.5;
    case 1:
      return 0.5;
    case 2:
      return 0;
    default:
      return in.between(-1.5, 1.5);
  }
}

double polygonSize(FuzzInput& in) {
  return in.pick({1e-9, 1e-6, 1e-3, 0.05, 0.2, 0.5, 0.5, 1.0, 1.0, 3.0});
}

Vec3 unitVector(FuzzInput& in) {
  const double theta = in.between(0, kPi), phi = in.between(0, 2 * kPi);
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// An orthonormal frame of the plane with normal n (unit) through `origin`.
Frame frameWithNormal(const Vec3& origin, const Vec3& n) {
  const Vec3 helper = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalize(cross(helper, n));
  return {origin, u, cross(n, u)};
}

// A loop in a plane's 2D coordinates, about the origin, `size` across.
std::vector<Vec2> makeOutline(FuzzInput& in, double size) {
  std::vector<Vec2> outline;
  switch (in.integer(0, 2)) {
    case 0: {  // star-shaped about the origin: simple in exact arithmetic
      const int n = in.integer(3, kMaxCorners);
      std::vector<double> angles;
      for (int i = 0; i < n; ++i) angles.push_back(in.fraction() * 2 * kPi);
      std::sort(angles.begin(), angles.end());
      for (double a : angles) {
        const double r = in.between(0.2, 1) * size / 2;
        outline.push_back({r * std::cos(a), r * std::sin(a)});
      }
      break;
    }
    case 1: {  // a rectangle: edges parallel to the frame's axes (and often to the light's)
      const double w = in.between(0.1, 1) * size / 2, h = in.between(0.1, 1) * size / 2;
      outline = {{-w, -h}, {w, -h}, {w, h}, {-w, h}};
      break;
    }
    default: {  // anything: validation rejects what is not simple
      const int n = in.integer(3, kMaxCorners);
      for (int i = 0; i < n; ++i)
        outline.push_back({in.between(-0.5, 0.5) * size, in.between(-0.5, 0.5) * size});
      break;
    }
  }
  return outline;
}

// Repeated corners, collinear corners and tiny nudges, within kMaxCorners corners.
std::vector<Vec2> editOutline(FuzzInput& in, std::vector<Vec2> outline, double size) {
  std::vector<Vec2> edited;
  for (size_t i = 0; i < outline.size(); ++i) {
    Vec2 p = outline[i];
    const int room = kMaxCorners - int(edited.size() + outline.size() - i);
    const int edit = in.integer(0, 7);
    if (edit == 7) {  // nudged off its place by a rounding-sized amount
      const double nudge = in.pick({1e-15, 1e-12, 1e-9}) * size;
      // Bytes read one statement at a time: the order of a call's arguments (or of an
      // expression's operands) is the compiler's, and an input must make the same scene in the
      // clang fuzz build and the GCC replays (it did not: session 15). Here C++17's order for
      // `a += b` (b first), as before.
      const bool up = in.flag();
      const bool alongX = in.flag();
      (alongX ? p.x : p.y) += up ? nudge : -nudge;
    }
    edited.push_back(p);
    if (edit == 5 && room > 0) edited.push_back(p);  // repeated corner
    if (edit == 6 && room > 0) {                     // a corner on the edge to the next one
      const Vec2& q = outline[(i + 1) % outline.size()];
      const double t = in.pick({0.5, 0.25, 1e-9});
      edited.push_back({p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t});
    }
  }
  // A loop closed by repeating its first corner, as some exporters write it.
  if (in.integer(0, 7) == 0 && !edited.empty()) edited.push_back(edited.front());
  return edited;
}

// The lowest corner moved onto the floor (z = 0), the others kept above it.
void restOnFloor(Polygon3& polygon) {
  double lowest = polygon.front().z;
  for (const Vec3& p : polygon) lowest = std::min(lowest, p.z);
  for (Vec3& p : polygon) p.z -= lowest;
}

// An occluder whose first two corners are those of an edge of `other` (exactly the same
// coordinates: the two touch along it), the rest on one side of it in a plane through the edge.
Polygon3 sharingAnEdge(FuzzInput& in, const Polygon3& other) {
  const size_t i = in.byte() % other.size();
  const Vec3 a = other[i], b = other[(i + 1) % other.size()];
  const double length = distance(a, b);
  // A repeated corner (validation removes it later) has no edge to share: the same polygon again,
  // coincident with the first, is a degenerate configuration worth having too.
  if (!(length > 0)) return other;
  const Vec3 along = (b - a) / length;
  // The plane through the edge: coplanar with `other` (either side), or turned about the edge.
  Vec3 side = unitVector(in);
  if (in.flag()) side = cross(newellNormal(other), along) * (in.flag() ? 1.0 : -1.0);
  side = side - along * dot(side, along);
  if (!(squaredLength(side) > 1e-6)) side = Vec3{0, 0, 1} - along * along.z;
  if (!(squaredLength(side) > 1e-6)) side = Vec3{1, 0, 0} - along * along.x;
  side = normalize(side);
  Polygon3 polygon = {b, a};
  const int extra = in.integer(1, kMaxCorners - 2);
  std::vector<double> xs;
  for (int k = 0; k < extra; ++k) xs.push_back(in.between(-0.2, 1.2) * length);
  std::sort(xs.begin(), xs.end());  // from a's end towards b's: a loop b, a, then back to b
  for (double x : xs) polygon.push_back(a + along * x + side * (in.between(0.1, 1) * length));
  return polygon;
}

Polygon3 makeOccluder(FuzzInput& in, const std::vector<Polygon3>& previous,
                      std::vector<Frame>& frames) {
  const double size = polygonSize(in);
  const Vec3 centre{centreCoordinate(in), centreCoordinate(in), 0};
  Frame frame;
  bool rest = false;
  switch (in.integer(0, 4)) {
    case 0: {  // horizontal: on the floor, a rounding above it, in between, in the light's plane
      const double height = in.pick({0.0, 1e-12, 1e-6, 0.25, 0.5, 1.0, 1.5, 2 - 1e-9, 2.0, -1.0});
      const double turn = in.pick({0.0, 0.0, kPi / 4, -1.0});
      const double a = turn >= 0 ? turn : in.between(0, kPi);
      frame = {{centre.x, centre.y, height >= 0 ? height : in.between(0, kLightHeight)},
               {std::cos(a), std::sin(a), 0},
               {-std::sin(a), std::cos(a), 0}};
      break;
    }
    case 1: {  // vertical, standing on the floor (or a little above it)
      const double a = in.pick({0.0, kPi / 2, -1.0});
      const double angle = a >= 0 ? a : in.between(0, kPi);
      frame = {centre, {std::cos(angle), std::sin(angle), 0}, {0, 0, 1}};
      rest = true;
      break;
    }
    case 2: {                                        // any plane
      const double height = in.between(0.05, 1.95);  // first, as clang read the arguments
      frame = frameWithNormal({centre.x, centre.y, height}, unitVector(in));
      rest = in.integer(0, 3) == 0;
      break;
    }
    case 3: {  // in the plane of an earlier occluder (or of the floor when there is none)
      if (frames.empty()) {
        frame = {centre, {1, 0, 0}, {0, 1, 0}};
      } else {
        frame = frames[in.byte() % frames.size()];
        const double u = in.between(-1, 1) * size;  // u before v, as clang read them
        const double v = in.between(-1, 1) * size;
        frame.origin = frame.at(u, v);
      }
      break;
    }
    default: {
      if (!previous.empty()) {
        Polygon3 polygon = sharingAnEdge(in, previous[in.byte() % previous.size()]);
        if (in.flag()) std::reverse(polygon.begin(), polygon.end());
        frames.push_back(frameWithNormal(polygon[0], normalize(newellNormal(polygon))));
        return polygon;
      }
      frame = {{centre.x, centre.y, 1}, {1, 0, 0}, {0, 1, 0}};
      break;
    }
  }
  frames.push_back(frame);
  Polygon3 polygon;
  for (const Vec2& q : editOutline(in, makeOutline(in, size), size))
    polygon.push_back(frame.at(q.x, q.y));
  if (rest || in.integer(0, 5) == 0) {
    const double lift = in.pick({0.0, 0.0, 1e-9, 0.3});
    restOnFloor(polygon);
    for (Vec3& p : polygon) p.z += lift;
  }
  // Occluders are opaque from both sides; their front decides only where they receive light.
  if (in.flag()) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

}  // namespace

FuzzedScene makeFuzzedScene(FuzzInput& in) {
  FuzzedScene fuzzed;
  Scene& scene = fuzzed.scene;
  scene.sourcePath = "fuzzed scene";
  scene.materials = {{"white", {0.5, 0.5, 0.5}, {}, false}, {"lamp", {0, 0, 0}, {10, 5, 1}, false}};
  const auto addObject = [&](const std::string& name, Polygon3 polygon, int material) {
    SceneObject object;
    object.name = name;
    object.polygons.push_back(std::move(polygon));
    object.polygonMaterial.push_back(material);
    object.polygonOrigin.push_back("fuzzed scene: " + name);
    scene.objects.push_back(std::move(object));
  };
  const double f = kFloorHalfSize;
  addObject("light", makeLight(in), 1);
  addObject("floor", {{-f, -f, 0}, {f, -f, 0}, {f, f, 0}, {-f, f, 0}}, 0);
  const int occluders = in.integer(1, kMaxOccluders);
  std::vector<Polygon3> placed;
  std::vector<Frame> frames;
  for (int k = 0; k < occluders; ++k) {
    placed.push_back(makeOccluder(in, placed, frames));
    addObject("occluder " + std::to_string(k), placed.back(), 0);
  }
  // Floor points: free, under the light's corners and centre.
  const int points = in.integer(1, 4);
  for (int k = 0; k < points; ++k) {
    const double margin = f * (1 - 1e-3);
    fuzzed.floorPoints.push_back({std::clamp(centreCoordinate(in), -margin, margin),
                                  std::clamp(centreCoordinate(in), -margin, margin), 0});
  }

  // Magnitudes: the whole scene scaled and moved, baked into the corners or as transforms.
  const double scale = in.pick({1.0, 1.0, 1.0, 1e-6, 1e-3, 1e3, 1e6, 0.1, 0x1p-20});
  const double offsets[] = {0, 0, 0, 1, 1e3, 1e6, -1e6};
  Vec3 offset;
  for (int axis = 0; axis < 3; ++axis) offset[axis] = offsets[in.byte() % std::size(offsets)];
  const bool baked = in.flag();
  for (SceneObject& object : scene.objects) {
    if (baked) {
      for (Polygon3& polygon : object.polygons)
        for (Vec3& p : polygon) p = p * scale + offset;
    } else {
      object.transform.translate = offset;
      object.transform.scale = {scale, scale, scale};
    }
  }
  if (baked)
    for (Vec3& p : fuzzed.floorPoints) p = p * scale + offset;

  // A move of the last occluder at frame 1: a slide, and perhaps a turn about the vertical.
  fuzzed.moves = in.flag();
  if (fuzzed.moves) {
    SceneObject& mover = scene.objects.back();
    Keyframe first{0, mover.transform}, second{1, mover.transform};
    const Vec3 slide{in.between(-0.5, 0.5), in.between(-0.5, 0.5), in.between(-0.3, 0.3)};
    second.pose.translate += slide * scale;
    if (in.flag()) second.pose.rotate = Quaternion::fromAxisAngle({0, 0, 1}, in.between(-0.5, 0.5));
    mover.motion = Motion({first, second});
    scene.frames = 2;
  }
  return fuzzed;
}

}  // namespace penumbra::fuzz
