#include "penumbra/render/ply_writer.h"

#include <bit>
#include <cstring>
#include <ostream>
#include <stdexcept>

#include "penumbra/base/output_file.h"
#include "penumbra/render/tone_mapping.h"

namespace penumbra {

namespace {

static_assert(std::endian::native == std::endian::little, "PLY output assumes little-endian");

template <typename T>
void put(std::ostream& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.write(bytes, sizeof(T));
}

}  // namespace

void writeIrradiancePly(const IrradianceMesh& mesh, double exposure,
                        const std::filesystem::path& path) {
  // Whole or not at all: a temporary file beside the destination, checked, then renamed.
  writeOutputFile(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\n"
        << "comment penumbra exact direct irradiance (W/m^2) on the discontinuity mesh\n"
        << "element vertex " << mesh.positions.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "property float irradiance_r\nproperty float irradiance_g\nproperty float irradiance_b\n"
        << "element face " << mesh.indices.size() / 3 << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3& p = mesh.positions[i];
      const Rgb& e = mesh.irradiance[i];
      put(out, float(p.x));
      put(out, float(p.y));
      put(out, float(p.z));
      put(out, srgb8(e.r * exposure));
      put(out, srgb8(e.g * exposure));
      put(out, srgb8(e.b * exposure));
      put(out, float(e.r));
      put(out, float(e.g));
      put(out, float(e.b));
    }
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      put(out, std::uint8_t(3));
      for (int k = 0; k < 3; ++k) put(out, std::int32_t(mesh.indices[t + k]));
    }
  });
}

}  // namespace penumbra
