#pragma once
// Pinhole camera of the scene file (DESIGN.md §4).

#include "penumbra/geometry/vec3.h"

namespace penumbra {

struct Camera {
  Vec3 eye{0, 0, 5};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fovYDegrees = 50;
  int width = 640;
  int height = 480;
};

}  // namespace penumbra
