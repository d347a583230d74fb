#pragma once
// Lambertian materials (DESIGN.md §4): reflectance per RGB channel, radiant exitance if emissive,
// and a mirror flag for planar reflectors (used by the shadow-volume engine's reflections).

#include <string>

#include "penumbra/base/rgb.h"

namespace penumbra {

struct Material {
  std::string name;
  Rgb reflectance{0.5, 0.5, 0.5};
  Rgb emission;  // radiant exitance M (W/m^2) of the front side; black for non-emitters
  bool mirror = false;

  bool isEmitter() const { return !emission.isBlack(); }
};

}  // namespace penumbra
