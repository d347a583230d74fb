#pragma once
// Writes a Scene built in code (the structure-aware target's) as a Penumbra JSON scene file
// (DESIGN.md §4), so that a finding reproduces with the command line: `penumbra probe` and
// `penumbra shadows` on the file. Numbers are written to round-trip; rotations go through an
// axis and degrees, so a turned pose may differ from the original by rounding.

#include <string>

#include "penumbra/scene/scene.h"

namespace penumbra::fuzz {

std::string sceneToJson(const Scene& scene);

}  // namespace penumbra::fuzz
