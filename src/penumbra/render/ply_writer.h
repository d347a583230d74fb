#pragma once
// PLY export of the exact-irradiance discontinuity mesh (dm/irradiance_mesh.h), for inspection in
// mesh viewers: binary little-endian, vertices with float x y z, uchar red green blue (the
// irradiance times `exposure`, sRGB-encoded like the PNG images) and float irradiance_r/g/b (raw
// W/m²), faces as lists of three vertex indices.

#include <filesystem>

#include "penumbra/dm/irradiance_mesh.h"

namespace penumbra {

// Throws std::runtime_error naming `path` when the file cannot be written.
void writeIrradiancePly(const IrradianceMesh& mesh, double exposure,
                        const std::filesystem::path& path);

}  // namespace penumbra
