#pragma once
// Closed rooms full of coincidences, for radiosity's adversarial runs (docs/radiosity.md, session
// 32): a 2 m room (reflectance 0.3-0.9), a 0.5 m lamp 1 mm or 0.25 m under the ceiling facing
// down, and 1-5 occluders on a 1/8 m grid: boxes on the floor or floating, two-sided cards
// (horizontal or standing), thin slabs lying on the floor; a third pushed against a wall and some
// of those moved 1/64-1/256 m off it. With `insideOut`, the boxes' faces turn inwards (a model
// whose winding came out reversed: its bottom lies on the floor facing the same way). With
// `moving`, one occluder moves over three more frames by dyadic steps, a third of them into
// contact with a wall or the floor.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "polygon_json.h"

namespace penumbra::bench {

inline std::string degenerateRoomJson(std::uint64_t seed, bool insideOut, bool moving) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const auto dyadic = [&](double lo, double hi) { return std::round(uniform(lo, hi) * 8) / 8; };
  const auto text = [](const Corners& corners) { return cornersJson(corners, 17); };
  // The faces of a box, outward.
  const auto box = [](double x, double y, double z, double a, double b, double c) {
    std::vector<Corners> faces{
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
        {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
    for (Corners& face : faces)
      for (auto& v : face) v = {x + a * v[0], y + b * v[1], z + c * v[2]};
    return faces;
  };
  const double rho = std::array{0.3, 0.5, 0.7, 0.9}[rng() % 4];
  std::ostringstream json;
  json << R"({"penumbra": 1, "frames": )" << (moving ? 4 : 1) << R"(, "materials": {)"
       << R"("wall": {"reflectance": [)" << rho << ',' << 0.9 * rho << ',' << 0.8 * rho << "]},"
       << R"("grey": {"reflectance": [0.5, 0.5, 0.5]}, "dark": {"reflectance": [0.1, 0.2, 0.3]},)"
       << R"("lamp": {"reflectance": [0, 0, 0], "emission": [10, 10, 10]}}, "objects": [)";
  json << R"({"name": "room", "material": "wall", "polygons": [)";
  const std::vector<Corners> room = box(0, 0, 0, 2, 2, 2);
  for (size_t i = 0; i < room.size(); ++i) json << (i ? "," : "") << text(reversed(room[i]));
  const double lampY = uniform(0, 1) < 0.5 ? 2 - 1e-3 : 1.75;
  const double lx = dyadic(0.25, 1.25), lz = dyadic(0.25, 1.25);
  json << R"(]}, {"name": "lamp", "material": "lamp", "polygons": [)"
       << text({{lx, lampY, lz},
                {lx + 0.5, lampY, lz},
                {lx + 0.5, lampY, lz + 0.5},
                {lx, lampY, lz + 0.5}})
       << "]}";
  const int count = 1 + int(rng() % 5), mover = int(rng() % std::uint64_t(count));
  for (int k = 0; k < count; ++k) {
    const char* material = std::array{"grey", "dark", "wall"}[rng() % 3];
    const double a = dyadic(0.125, 0.75), b = dyadic(0.125, 1.0), c = dyadic(0.125, 0.75);
    double x = dyadic(0, 2 - a), z = dyadic(0, 2 - c);
    if (uniform(0, 1) < 0.3) x = uniform(0, 1) < 0.5 ? 0.0 : 2 - a;  // against a wall
    if (uniform(0, 1) < 0.3) z = uniform(0, 1) < 0.5 ? 0.0 : 2 - c;
    if (uniform(0, 1) < 0.2) x += std::array{1 / 64., 1 / 128., 1 / 256.}[rng() % 3];
    std::vector<Corners> polygons;
    bool isBox = false;
    switch (rng() % 6) {
      case 0:
      case 1:
      case 2:  // a box on the floor or floating
        polygons = box(x, uniform(0, 1) < 0.6 ? 0.0 : dyadic(0, 2 - b), z, a, b, c);
        isBox = true;
        break;
      case 3: {  // a horizontal two-sided card
        const double y = dyadic(0.125, 1.875);
        const Corners card{{x, y, z}, {x + a, y, z}, {x + a, y, z + c}, {x, y, z + c}};
        polygons = {card, reversed(card)};
        break;
      }
      case 4: {  // a standing two-sided card
        const double y = uniform(0, 1) < 0.5 ? 0.0 : dyadic(0, 2 - b);
        const Corners card{{x, y, z}, {x, y + b, z}, {x, y + b, z + c}, {x, y, z + c}};
        polygons = {card, reversed(card)};
        break;
      }
      default:  // a thin slab on the floor
        polygons = box(x, 0, z, a, std::array{1 / 64., 1 / 32., 0.125}[rng() % 3], c);
        isBox = true;
        break;
    }
    json << R"(, {"name": "o)" << k << R"(", "material": ")" << material << '"';
    if (moving && k == mover) {
      std::array<double, 3> low{9, 9, 9}, high{-9, -9, -9}, at{0, 0, 0};
      for (const Corners& p : polygons)
        for (const auto& v : p)
          for (int i = 0; i < 3; ++i) {
            low[i] = std::min(low[i], v[i]);
            high[i] = std::max(high[i], v[i]);
          }
      json << R"(, "motion": [{"frame": 0, "translate": [0, 0, 0]})";
      for (int frame = 1; frame < 4; ++frame) {
        const int axis = int(rng() % 3);
        if (uniform(0, 1) < 0.4)  // into contact with a wall or the floor
          at[size_t(axis)] =
              axis == 1 || uniform(0, 1) < 0.5 ? -low[size_t(axis)] : 2 - high[size_t(axis)];
        else
          at[size_t(axis)] =
              std::clamp(at[size_t(axis)] + std::array{-0.25, -0.125, 0.125, 0.25}[rng() % 4],
                         -low[size_t(axis)], 2 - high[size_t(axis)]);
        json << R"(, {"frame": )" << frame << R"(, "translate": [)" << at[0] << ',' << at[1] << ','
             << at[2] << "]}";
      }
      json << ']';
    }
    json << R"(, "polygons": [)";
    for (size_t i = 0; i < polygons.size(); ++i)
      json << (i ? "," : "") << text(isBox && insideOut ? reversed(polygons[i]) : polygons[i]);
    json << "]}";
  }
  json << "]}";
  return json.str();
}

}  // namespace penumbra::bench
