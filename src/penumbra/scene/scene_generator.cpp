#include "penumbra/scene/scene_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/base/check.h"
#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/box.h"
#include "penumbra/geometry/polygon.h"

namespace penumbra {
namespace {

constexpr double kRoomHeight = 3.0;
constexpr double kCellSize = 1.8;    // floor cells, one piece of furniture (or a set) each
constexpr double kCellMargin = 0.1;  // keeps aisles between the cells' furniture
constexpr double kBoard = 0.02;      // shelf boards and sides
constexpr int kPolygonsPerUnit = 6;  // budgets are counted in boxes
constexpr double kBoxSize = 0.15;    // the floating boxes
constexpr int kMaxMovingBoxes = 4;

// SplitMix64 (base/split_mix.h), with our own conversions: std::mt19937_64 is portable but the
// std:: distributions are not, and a seed must give the same scene everywhere.
class Random {
 public:
  explicit Random(std::uint64_t seed) : bits_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * bits_.uniform(); }
  // Integer in [lo, hi].
  int integer(int lo, int hi) { return lo + int(bits_.next() % std::uint64_t(hi - lo + 1)); }
  // A length snapped to millimetres, so that coordinates derived from several of them agree
  // exactly after the output rounding (touching solids must touch, not overlap by 1e-16).
  double length(double lo, double hi) { return std::round(uniform(lo, hi) * 1000) / 1000; }

 private:
  SplitMix bits_;
};

using Solid = std::vector<Polygon3>;

Polygon3 orientedAlong(Polygon3 loop, const Vec3& outward) {
  if (dot(newellNormal(loop), outward) < 0) std::reverse(loop.begin(), loop.end());
  return loop;
}

// A vertical prism over a convex loop of (x, z) points, from height y0 to y1; faces outward.
Solid prism(const std::vector<Vec2>& base, double y0, double y1) {
  Solid solid;
  Polygon3 bottom, top;
  Vec2 centre;
  for (const Vec2& p : base) {
    bottom.push_back({p.x, y0, p.y});
    top.push_back({p.x, y1, p.y});
    centre = centre + p * (1.0 / base.size());
  }
  solid.push_back(orientedAlong(bottom, {0, -1, 0}));
  solid.push_back(orientedAlong(top, {0, 1, 0}));
  for (size_t i = 0; i < base.size(); ++i) {
    const Vec2& a = base[i];
    const Vec2& b = base[(i + 1) % base.size()];
    const Vec2 mid = (a + b) * 0.5 - centre;
    solid.push_back(orientedAlong({{a.x, y0, a.y}, {b.x, y0, b.y}, {b.x, y1, b.y}, {a.x, y1, a.y}},
                                  {mid.x, 0, mid.y}));
  }
  return solid;
}

Solid box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return prism({{x0, z0}, {x1, z0}, {x1, z1}, {x0, z1}}, y0, y1);
}

Solid ngonPrism(double cx, double cz, double radius, int sides, double y0, double y1,
                double phase = 0) {
  std::vector<Vec2> base;
  for (int i = 0; i < sides; ++i) {
    const double a = phase + 2 * std::numbers::pi * i / sides;
    base.push_back({cx + radius * std::cos(a), cz + radius * std::sin(a)});
  }
  return prism(base, y0, y1);
}

struct Rect {
  double x0, z0, x1, z1;
  double width() const { return x1 - x0; }
  double depth() const { return z1 - z0; }
};

struct Object {
  std::string name;
  std::string material;
  std::vector<Solid> solids;
  std::vector<Vec3> path;  // keyframe translations; empty for static objects

  int polygonCount() const {
    int n = 0;
    for (const Solid& s : solids) n += int(s.size());
    return n;
  }
  Box3 bounds() const {
    Box3 b;
    for (const Solid& s : solids)
      for (const Polygon3& p : s)
        for (const Vec3& v : p) b.extend(v);
    return b;
  }
};

bool interiorsOverlap(const Box3& a, const Box3& b) {
  constexpr double kEps = 1e-9;
  return a.min.x < b.max.x - kEps && b.min.x < a.max.x - kEps && a.min.y < b.max.y - kEps &&
         b.min.y < a.max.y - kEps && a.min.z < b.max.z - kEps && b.min.z < a.max.z - kEps;
}

// Reserved volumes, hashed on a floor grid so that large rooms stay linear-time.
class Occupancy {
 public:
  bool isFree(const Box3& b) const {
    bool free = true;
    forCells(b, [&](std::int64_t key) {
      const auto it = grid_.find(key);
      if (it == grid_.end()) return;
      for (int i : it->second)
        if (interiorsOverlap(boxes_[i], b)) free = false;
    });
    return free;
  }
  void reserve(const Box3& b) {
    const int index = int(boxes_.size());
    boxes_.push_back(b);
    forCells(b, [&](std::int64_t key) { grid_[key].push_back(index); });
  }

 private:
  static constexpr double kCell = 1.0;
  template <typename F>
  static void forCells(const Box3& b, F&& f) {
    const int i0 = int(std::floor(b.min.x / kCell)), i1 = int(std::floor(b.max.x / kCell));
    const int k0 = int(std::floor(b.min.z / kCell)), k1 = int(std::floor(b.max.z / kCell));
    for (int i = i0; i <= i1; ++i)
      for (int k = k0; k <= k1; ++k) f((std::int64_t(i) << 32) ^ std::int64_t(std::uint32_t(k)));
  }
  std::vector<Box3> boxes_;
  std::unordered_map<std::int64_t, std::vector<int>> grid_;
};

// Where books may stand: the space above one shelf board.
struct ShelfSlot {
  bool alongX;    // books are lined up along x (else along z)
  double y;       // top of the board
  double a0, a1;  // free range along the line
  double c0, c1;  // range across (front to back) that books may occupy
  double maxHeight;
  double next;  // first free position along the line
};

class Generator {
 public:
  explicit Generator(const SceneGeneratorOptions& options)
      : options_(options), rng_(options.seed ^ 0x5EED5CE7E5ull) {}

  std::string run();

 private:
  // Module builders: each fills `area` with furniture worth at most `units` boxes (6 polygons
  // each) and returns the units it used; what it cannot use goes to the next cell.
  int buildBookshelf(const Rect& area, int units);
  int buildTable(const Rect& area, int units);
  int buildDeskSet(const Rect& area, int units);
  int buildCabinet(const Rect& area, int units);
  int buildCrates(const Rect& area, int units);
  int buildModule(const Rect& area, int units);

  // Piles of boxes (papers, boxes, crates) on a horizontal surface: at most `units` boxes, at
  // most `maxHeight` tall, item heights in [hLo, hHi]. Each item's footprint lies strictly
  // inside the one below it, so no two solids share a vertex.
  int addPiles(std::vector<Solid>& out, const Rect& surface, double y, double maxHeight, int units,
               double pile, double hLo, double hHi);
  // Places a footprint of the given size at a random spot inside `area`.
  Rect placeIn(const Rect& area, double width, double depth);
  std::string nextName(const std::string& kind) {
    return kind + "-" + std::to_string(++count_[kind]);
  }
  // Adds the objects if none overlaps anything placed so far.
  bool commit(std::vector<Object> objects);

  SceneGeneratorOptions options_;
  Random rng_;
  Occupancy occupancy_;
  std::vector<Object> objects_;
  std::unordered_map<std::string, int> count_;
};

Rect Generator::placeIn(const Rect& area, double width, double depth) {
  const double x0 = area.x0 + rng_.length(0, std::max(0.0, area.width() - width));
  const double z0 = area.z0 + rng_.length(0, std::max(0.0, area.depth() - depth));
  return {x0, z0, x0 + width, z0 + depth};
}

bool Generator::commit(std::vector<Object> objects) {
  for (const Object& o : objects)
    if (!occupancy_.isFree(o.bounds())) return false;
  for (size_t i = 0; i < objects.size(); ++i)
    for (size_t j = i + 1; j < objects.size(); ++j)
      if (interiorsOverlap(objects[i].bounds(), objects[j].bounds())) return false;
  for (Object& o : objects) {
    occupancy_.reserve(o.bounds());
    objects_.push_back(std::move(o));
  }
  return true;
}

int Generator::addPiles(std::vector<Solid>& out, const Rect& surface, double y, double maxHeight,
                        int units, double pile, double hLo, double hHi) {
  struct Pile {
    Rect top;  // footprint of the topmost item
    double height;
    bool full;
  };
  const int nx = std::max(1, int(surface.width() / pile));
  const int nz = std::max(1, int(surface.depth() / pile));
  const double cw = surface.width() / nx, cd = surface.depth() / nz;
  if (cw < 0.06 || cd < 0.06) return 0;
  std::vector<Pile> piles;
  for (int i = 0; i < nx; ++i)
    for (int k = 0; k < nz; ++k) {
      const double x0 = surface.x0 + i * cw, z0 = surface.z0 + k * cd;
      // The first item's footprint: the sub-cell less a random margin (>= 5 mm, so that items
      // of neighbouring piles never touch and the pile never shares the surface's vertices).
      piles.push_back({{x0 + rng_.length(0.005, 0.02), z0 + rng_.length(0.005, 0.02),
                        x0 + cw - rng_.length(0.005, 0.02), z0 + cd - rng_.length(0.005, 0.02)},
                       0,
                       false});
    }
  int used = 0;
  bool progress = true;
  while (used < units && progress) {
    progress = false;
    for (Pile& p : piles) {
      if (used == units) break;
      if (p.full) continue;
      Rect f = p.top;
      if (p.height > 0) {  // shrink strictly inside the item below
        f = {f.x0 + rng_.length(0.003, 0.02), f.z0 + rng_.length(0.003, 0.02),
             f.x1 - rng_.length(0.003, 0.02), f.z1 - rng_.length(0.003, 0.02)};
      }
      const double h = rng_.length(hLo, hHi);
      if (f.width() < 0.04 || f.depth() < 0.04 || p.height + h > maxHeight) {
        p.full = true;
        continue;
      }
      out.push_back(box(f.x0, y + p.height, f.z0, f.x1, y + p.height + h, f.z1));
      p.top = f;
      p.height += h;
      ++used;
      progress = true;
    }
  }
  return used;
}

// A chair is several solids; this helper returns them (seat, four legs, back panel).
std::vector<Solid> chairSolids(double x0, double z0, double width, double depth, bool backAtHighZ) {
  const double seatY = 0.45, seatT = 0.04, leg = 0.04;
  const double x1 = x0 + width, z1 = z0 + depth;
  std::vector<Solid> solids{box(x0, seatY - seatT, z0, x1, seatY, z1)};
  for (double lx : {x0 + 0.01, x1 - 0.01 - leg})
    for (double lz : {z0 + 0.01, z1 - 0.01 - leg})
      solids.push_back(box(lx, 0, lz, lx + leg, seatY - seatT, lz + leg));
  if (backAtHighZ)
    solids.push_back(box(x0 + 0.01, seatY, z1 - 0.04, x1 - 0.01, seatY + 0.45, z1 - 0.005));
  else
    solids.push_back(box(x0 + 0.01, seatY, z0 + 0.005, x1 - 0.01, seatY + 0.45, z0 + 0.04));
  return solids;
}

// Top plus four legs inset from the corners (a leg never shares a vertex with the top).
std::vector<Solid> tableSolids(const Rect& r, double height, double top = 0.03, double leg = 0.05) {
  std::vector<Solid> solids{box(r.x0, height - top, r.z0, r.x1, height, r.z1)};
  for (double lx : {r.x0 + 0.02, r.x1 - 0.02 - leg})
    for (double lz : {r.z0 + 0.02, r.z1 - 0.02 - leg})
      solids.push_back(box(lx, 0, lz, lx + leg, height - top, lz + leg));
  return solids;
}

int Generator::buildBookshelf(const Rect& area, int units) {
  const int boards = std::clamp(3 + units / 40, 3, 6);
  const int frame = 2 + boards;
  if (units < frame + 1) return buildCrates(area, units);
  const bool alongX = rng_.integer(0, 1) == 1;
  const double length = rng_.length(0.8, std::min(1.6, alongX ? area.width() : area.depth()));
  const double depth = rng_.length(0.3, 0.4);
  const double minHeight = 0.06 + (boards - 1) * 0.33 + kBoard;
  const double height = rng_.length(minHeight, std::max(minHeight, 2.2));
  const Rect r = alongX ? placeIn(area, length, depth) : placeIn(area, depth, length);
  // Which way the open side faces: books stand near it.
  const bool frontHigh = rng_.integer(0, 1) == 1;

  std::vector<Solid> solids;
  std::vector<ShelfSlot> slots;
  std::vector<double> ys;
  for (int i = 0; i < boards; ++i) {
    ys.push_back(std::round((0.06 + i * (height - 0.06 - kBoard) / (boards - 1)) * 1000) / 1000);
  }
  if (alongX) {
    solids.push_back(box(r.x0, 0, r.z0, r.x0 + kBoard, height, r.z1));
    solids.push_back(box(r.x1 - kBoard, 0, r.z0, r.x1, height, r.z1));
    for (double y : ys)
      solids.push_back(
          box(r.x0 + kBoard, y, r.z0 + 0.005, r.x1 - kBoard, y + kBoard, r.z1 - 0.005));
  } else {
    solids.push_back(box(r.x0, 0, r.z0, r.x1, height, r.z0 + kBoard));
    solids.push_back(box(r.x0, 0, r.z1 - kBoard, r.x1, height, r.z1));
    for (double y : ys)
      solids.push_back(
          box(r.x0 + 0.005, y, r.z0 + kBoard, r.x1 - 0.005, y + kBoard, r.z1 - kBoard));
  }
  const double across0 = alongX ? r.z0 : r.x0, across1 = alongX ? r.z1 : r.x1;
  const double along0 = (alongX ? r.x0 : r.z0) + kBoard + 0.006;
  const double along1 = (alongX ? r.x1 : r.z1) - kBoard - 0.006;
  for (int i = 0; i + 1 < boards; ++i) {
    ShelfSlot s{alongX,
                ys[i] + kBoard,
                along0,
                along1,
                across0 + 0.015,
                across1 - 0.015,
                ys[i + 1] - ys[i] - kBoard - 0.02,
                along0};
    slots.push_back(s);
  }
  // Books go to the slots in turn so every shelf gets some; they stand flush with the front.
  int books = 0;
  size_t turn = 0;
  const int wanted = units - frame;
  while (books < wanted) {
    const double thick = rng_.length(0.015, 0.05);
    const double bookHeight = rng_.length(0.15, 0.3);
    const double bookDepth = rng_.length(0.12, 0.22);
    ShelfSlot* slot = nullptr;
    for (size_t k = 0; k < slots.size() && !slot; ++k) {
      ShelfSlot& s = slots[(turn + k) % slots.size()];
      if (s.next + thick <= s.a1) {
        slot = &s;
        turn = (turn + k + 1) % slots.size();
      }
    }
    if (!slot) break;
    const double h = std::min(bookHeight, slot->maxHeight);
    const double d = std::min(bookDepth, slot->c1 - slot->c0);
    const double c0 = frontHigh ? slot->c1 - d : slot->c0;
    const double a = slot->next;
    if (slot->alongX)
      solids.push_back(box(a, slot->y, c0, a + thick, slot->y + h, c0 + d));
    else
      solids.push_back(box(c0, slot->y, a, c0 + d, slot->y + h, a + thick));
    slot->next = a + thick + rng_.length(0.002, 0.006);
    ++books;
  }
  if (!commit({{nextName("bookshelf"), "wood", std::move(solids), {}}})) return 0;
  return frame + books;
}

int Generator::buildTable(const Rect& area, int units) {
  if (units < 6) return buildCrates(area, units);
  const double w = rng_.length(0.8, std::min(1.5, area.width()));
  const double d = rng_.length(0.6, std::min(1.0, area.depth()));
  const double height = rng_.length(0.68, 0.76);
  const Rect r = placeIn(area, w, d);
  std::vector<Solid> solids = tableSolids(r, height);
  const int clutter = addPiles(solids, {r.x0 + 0.03, r.z0 + 0.03, r.x1 - 0.03, r.z1 - 0.03}, height,
                               0.45, units - 5, rng_.length(0.22, 0.35), 0.02, 0.1);
  if (!commit({{nextName("table"), rng_.integer(0, 1) ? "wood" : "metal", std::move(solids), {}}}))
    return 0;
  return 5 + clutter;
}

int Generator::buildDeskSet(const Rect& area, int units) {
  if (units < 14) return buildTable(area, units);
  const double w = rng_.length(1.1, std::min(1.5, area.width()));
  const double d = rng_.length(0.6, 0.75);
  const double chairGap = rng_.length(0.15, 0.3);
  const Rect set = placeIn(area, w, d + chairGap + 0.44);
  const bool chairAtHighZ = rng_.integer(0, 1) == 1;
  const Rect desk = chairAtHighZ ? Rect{set.x0, set.z0, set.x1, set.z0 + d}
                                 : Rect{set.x0, set.z1 - d, set.x1, set.z1};
  const double height = 0.75;
  std::vector<Solid> deskSolids = tableSolids(desk, height);
  // Monitor at the back of the right half (the side away from the chair), papers on the left.
  const double mx = desk.x0 + w * 0.7;
  const double mz = chairAtHighZ ? desk.z0 + 0.08 : desk.z1 - 0.12;
  deskSolids.push_back(box(mx - 0.22, height, mz, mx + 0.22, height + 0.3, mz + 0.04));
  const int clutter =
      addPiles(deskSolids, {desk.x0 + 0.04, desk.z0 + 0.04, desk.x0 + w * 0.45, desk.z1 - 0.04},
               height, 0.35, units - 12, 0.25, 0.01, 0.06);
  const double cx = desk.x0 + w * 0.5 - 0.22;
  const double cz = chairAtHighZ ? desk.z1 + chairGap : desk.z0 - chairGap - 0.44;
  std::vector<Object> set2{{nextName("desk"), "wood", std::move(deskSolids), {}},
                           {nextName("chair"),
                            rng_.integer(0, 1) ? "red" : "blue",
                            chairSolids(cx, cz, 0.44, 0.44, chairAtHighZ),
                            {}}};
  if (!commit(std::move(set2))) return 0;
  return 12 + clutter;
}

int Generator::buildCabinet(const Rect& area, int units) {
  if (units < 3) return buildCrates(area, units);
  const double w = rng_.length(0.5, std::min(1.2, area.width() - 0.1));
  const double d = rng_.length(0.4, 0.6);
  const double height = rng_.length(0.7, 1.3);
  const int rows = std::clamp(int(height / 0.2), 2, 6);
  const int cols = w > 0.9 ? 2 : 1;
  const int drawers = std::min(rows * cols, (units - 1) / 2);
  // The body sits back from the area's front so the drawer fronts and handles fit.
  const Rect outer = placeIn(area, w, d + 0.04);
  const bool frontHigh = rng_.integer(0, 1) == 1;
  const Rect body = frontHigh ? Rect{outer.x0, outer.z0, outer.x1, outer.z1 - 0.04}
                              : Rect{outer.x0, outer.z0 + 0.04, outer.x1, outer.z1};
  std::vector<Solid> solids{box(body.x0, 0, body.z0, body.x1, height, body.z1)};
  const double gap = 0.015;
  const double dh = (height - 0.05 - gap * (rows + 1)) / rows;
  const double dw = (w - gap * (cols + 1)) / cols;
  for (int n = 0; n < drawers; ++n) {
    const int row = n / cols, col = n % cols;
    const double y0 = 0.05 + gap + row * (dh + gap), y1 = y0 + dh, ym = (y0 + y1) / 2;
    const double x0 = body.x0 + gap + col * (dw + gap), x1 = x0 + dw, xm = (x0 + x1) / 2;
    if (frontHigh) {
      solids.push_back(box(x0, y0, body.z1, x1, y1, body.z1 + 0.02));
      solids.push_back(
          box(xm - 0.05, ym - 0.01, body.z1 + 0.02, xm + 0.05, ym + 0.01, body.z1 + 0.04));
    } else {
      solids.push_back(box(x0, y0, body.z0 - 0.02, x1, y1, body.z0));
      solids.push_back(
          box(xm - 0.05, ym - 0.01, body.z0 - 0.04, xm + 0.05, ym + 0.01, body.z0 - 0.02));
    }
  }
  const int clutter =
      addPiles(solids, {body.x0 + 0.02, body.z0 + 0.02, body.x1 - 0.02, body.z1 - 0.02}, height,
               0.4, units - 1 - 2 * drawers, 0.2, 0.02, 0.08);
  if (!commit({{nextName("cabinet"), "metal", std::move(solids), {}}})) return 0;
  return 1 + 2 * drawers + clutter;
}

int Generator::buildCrates(const Rect& area, int units) {
  if (units < 1) return 0;
  const double w = rng_.length(std::min(0.5, area.width()), area.width());
  const double d = rng_.length(std::min(0.5, area.depth()), area.depth());
  const Rect r = placeIn(area, w, d);
  std::vector<Solid> solids;
  const int used = addPiles(solids, r, 0, 1.6, units, rng_.length(0.35, 0.6), 0.12, 0.4);
  if (used == 0 ||
      !commit({{nextName("crates"), rng_.integer(0, 1) ? "wood" : "green", std::move(solids), {}}}))
    return 0;
  return used;
}

int Generator::buildModule(const Rect& area, int units) {
  const int pick = rng_.integer(0, 99);
  if (pick < 30) return buildBookshelf(area, units);
  if (pick < 50) return buildTable(area, units);
  if (pick < 70) return buildDeskSet(area, units);
  if (pick < 85) return buildCabinet(area, units);
  return buildCrates(area, units);
}

// Rounds to micrometres so that equal coordinates print equally and the text stays short.
double rounded(double v) {
  const double r = std::round(v * 1e6) / 1e6;
  return r == 0 ? 0.0 : r;  // no "-0"
}

nlohmann::ordered_json vec(const Vec3& v) {
  return nlohmann::ordered_json::array({rounded(v.x), rounded(v.y), rounded(v.z)});
}

std::string Generator::run() {
  const int movers = std::clamp(options_.movingBoxes, 1, kMaxMovingBoxes);
  const int target = std::max(options_.targetPolygons, 49 + 6 * (movers - 1));
  const int frames = std::max(options_.frames, 1);

  // Fixed part: room shell (6), light (1), floating boxes (6 each), central desk with monitor
  // (36), and a chair at it (36) when the budget allows.
  const bool centralChair = target >= 120 + 6 * (movers - 1);
  int remaining = target - 49 - 6 * (movers - 1) - (centralChair ? 36 : 0);
  // The remainder modulo 6 goes into one prism (a jar on the central desk): an n-gon prism
  // has n + 2 faces, so 5 faces is a triangular prism and 7..10 need one box less.
  int jarSides = 0;
  if (int r = remaining % 6; r == 5) {
    jarSides = 3;
  } else if (r > 0 && remaining >= 6 + r) {
    jarSides = r + 4;
  }
  if (jarSides > 0) remaining -= jarSides + 2;
  int units = std::max(remaining, 0) / kPolygonsPerUnit;

  // Floor plan: square cells; a 2 x 2 block in the middle holds the central desk. Budget per
  // cell grows slowly with the target (more books and clutter per piece: more detail).
  const double log10Target = std::log10(double(target));
  const int unitsPerCell = std::max(8, int(std::lround(20 + 10 * (log10Target - 3))));
  const int modules = (units + unitsPerCell - 1) / unitsPerCell;
  const int cells = modules + 4 + modules / 6 + 1;  // spare cells for what modules leave over
  const int gx = std::max(3, int(std::ceil(std::sqrt(double(cells)))));
  const int gz = std::max(2, (cells + gx - 1) / gx);
  const double width = gx * kCellSize, depth = gz * kCellSize;
  const int bx = (gx - 2) / 2, bz = (gz - 2) / 2;
  const Rect block{bx * kCellSize, bz * kCellSize, (bx + 2) * kCellSize, (bz + 2) * kCellSize};

  // Central desk, its monitor and chair, the floating box's path above the desk's front half.
  const double deskW = rng_.length(1.3, 1.5), deskD = 0.7, deskH = 0.75;
  const double cx = (block.x0 + block.x1) / 2;
  const Rect desk{cx - deskW / 2, block.z0 + 0.8, cx + deskW / 2, block.z0 + 0.8 + deskD};
  std::vector<Object> central{
      {"desk", "wood", tableSolids(desk, deskH), {}},
      {"monitor",
       "dark",
       {box(cx, deskH, desk.z0 + 0.08, cx + 0.5, deskH + 0.32, desk.z0 + 0.12)},
       {}}};
  if (jarSides > 0)
    central.push_back(
        {"jar",
         "red",
         {ngonPrism(desk.x0 + 0.12, desk.z0 + 0.12, 0.04, jarSides, deskH, deskH + 0.12)},
         {}});
  if (centralChair)
    central.push_back(
        {"chair", "red", chairSolids(cx - 0.22, desk.z1 + 0.25, 0.44, 0.44, true), {}});

  Object mover{"floating-box",
               "green",
               {box(-kBoxSize / 2, 0, -kBoxSize / 2, kBoxSize / 2, kBoxSize, kBoxSize / 2)},
               {}};
  const double pathZ = desk.z0 + 0.45;
  const double pathY = deskH + rng_.length(0.35, 0.45);
  Box3 swept;
  for (int k = 0; k < frames; ++k) {
    const double t = frames == 1 ? 0.5 : double(k) / (frames - 1);
    const Vec3 p{std::round((desk.x0 + 0.3 + t * (deskW - 0.6)) * 1000) / 1000, pathY,
                 std::round((pathZ + 0.05 * std::sin(2 * std::numbers::pi * t)) * 1000) / 1000};
    mover.path.push_back(p);
    swept.extend(p + Vec3{-kBoxSize / 2, 0, -kBoxSize / 2});
    swept.extend(p + Vec3{kBoxSize / 2, kBoxSize, kBoxSize / 2});
  }
  // More boxes above the first, each a box size and a half higher, every other one travelling the
  // other way: their paths cross the first's shadow and one another's in the light.
  std::vector<Object> moreMovers;
  for (int m = 1; m < movers; ++m) {
    Object extra{"floating-box-" + std::to_string(m + 1), "blue", mover.solids, {}};
    for (int k = 0; k < frames; ++k) {
      const int from = m % 2 == 1 ? frames - 1 - k : k;
      const Vec3 p = mover.path[size_t(from)] + Vec3{0, 1.5 * kBoxSize * m, 0.1 * (m % 2)};
      extra.path.push_back(p);
      swept.extend(p + Vec3{-kBoxSize / 2, 0, -kBoxSize / 2});
      swept.extend(p + Vec3{kBoxSize / 2, kBoxSize, kBoxSize / 2});
    }
    moreMovers.push_back(std::move(extra));
  }
  // The boxes' whole paths are reserved (the hull of two keyframe boxes lies in their bounds).
  occupancy_.reserve(swept);
  const bool placed = commit(std::move(central));
  CHECK(placed);  // the central block is empty but for the box's path, which clears the desk

  // Furniture cells, nearest to the central block first, so that small scenes stay compact.
  std::vector<std::pair<double, Rect>> free;
  for (int i = 0; i < gx; ++i)
    for (int k = 0; k < gz; ++k) {
      if (i >= bx && i < bx + 2 && k >= bz && k < bz + 2) continue;
      const Rect cell{i * kCellSize + kCellMargin, k * kCellSize + kCellMargin,
                      (i + 1) * kCellSize - kCellMargin, (k + 1) * kCellSize - kCellMargin};
      const double dx = (i + 0.5) * kCellSize - cx, dz = (k + 0.5) * kCellSize - desk.z1;
      free.push_back({dx * dx + dz * dz + rng_.uniform(0, 0.5), cell});
    }
  std::stable_sort(free.begin(), free.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  int left = units;
  for (size_t n = 0; n < free.size() && left > 0; ++n) {
    const int cellsLeft = std::max<int>(1, std::min<int>(modules - int(n), int(free.size() - n)));
    const int share = n < size_t(modules) ? (left + cellsLeft - 1) / cellsLeft : left;
    left -= buildModule(free[n].second, std::min(share, left));
  }

  // Output.
  nlohmann::ordered_json scene;
  scene["penumbra"] = 1;
  scene["frames"] = frames;
  auto& materials = scene["materials"];
  auto material = [&](const char* name, Vec3 reflectance) {
    materials[name]["reflectance"] = vec(reflectance);
  };
  material("white", {0.75, 0.75, 0.75});
  material("floor", {0.45, 0.38, 0.3});
  material("wood", {0.55, 0.4, 0.25});
  material("metal", {0.5, 0.5, 0.52});
  material("dark", {0.08, 0.08, 0.09});
  material("red", {0.6, 0.12, 0.1});
  material("blue", {0.12, 0.2, 0.55});
  material("green", {0.18, 0.45, 0.15});
  material("light", {0, 0, 0});
  // ~2.5 W/m^2 on the desk 2.2 m below the 0.36 m^2 panel: white at about unit exposure.
  materials["light"]["emission"] = vec({110, 105, 95});

  auto& out = scene["objects"];
  auto polygons = [](const std::vector<Solid>& solids) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const Solid& s : solids)
      for (const Polygon3& p : s) {
        nlohmann::ordered_json loop = nlohmann::ordered_json::array();
        for (const Vec3& v : p) loop.push_back(vec(v));
        list.push_back(std::move(loop));
      }
    return list;
  };
  // Room shell: six inward quads; the floor is its own object for its own material.
  const Vec3 lo{0, 0, 0}, hi{width, kRoomHeight, depth};
  const Vec3 centre = (lo + hi) * 0.5;
  std::vector<Polygon3> shell{
      {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}},
      {{lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}},
      {{lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {lo.x, lo.y, hi.z}},
      {{hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z}},
      {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}},
      {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}}};
  for (Polygon3& p : shell) {
    Vec3 c;
    for (const Vec3& v : p) c += v * 0.25;
    p = orientedAlong(p, centre - c);
  }
  out.push_back(
      {{"name", "room-floor"}, {"material", "floor"}, {"polygons", polygons({Solid{shell[0]}})}});
  out.push_back({{"name", "room-walls"},
                 {"material", "white"},
                 {"polygons", polygons({Solid(shell.begin() + 1, shell.end())})}});
  const double lightZ = desk.z0 + 1.0, half = 0.3, lightY = kRoomHeight - 0.01;
  const Polygon3 light = orientedAlong({{cx - half, lightY, lightZ - half},
                                        {cx + half, lightY, lightZ - half},
                                        {cx + half, lightY, lightZ + half},
                                        {cx - half, lightY, lightZ + half}},
                                       {0, -1, 0});
  out.push_back({{"name", "light"}, {"material", "light"}, {"polygons", polygons({Solid{light}})}});
  objects_.push_back(std::move(mover));
  for (Object& extra : moreMovers) objects_.push_back(std::move(extra));
  for (const Object& o : objects_) {
    nlohmann::ordered_json j{{"name", o.name}, {"material", o.material}};
    if (!o.path.empty()) {
      auto& motion = j["motion"];
      for (size_t k = 0; k < o.path.size(); ++k)
        motion.push_back({{"frame", int(k)}, {"translate", vec(o.path[k])}});
    }
    j["polygons"] = polygons(o.solids);
    out.push_back(std::move(j));
  }
  scene["camera"] = {{"eye", vec({cx + 1.3, 1.8, desk.z1 + 1.9})},
                     {"target", vec({cx - 0.1, 0.9, (desk.z0 + desk.z1) / 2})},
                     {"up", vec({0, 1, 0})},
                     {"fov_y_degrees", 50},
                     {"width", 640},
                     {"height", 480}};
  return scene.dump() + "\n";
}

}  // namespace

std::string generateSceneJson(const SceneGeneratorOptions& options) {
  return Generator(options).run();
}

}  // namespace penumbra
