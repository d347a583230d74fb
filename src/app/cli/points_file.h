#pragma once
// The probe points file (DESIGN.md §6): one point per line, `x y z nx ny nz`; blank lines and `#`
// comments are ignored. Bad lines are InputErrors naming the file and the line.

#include <string>
#include <vector>

#include "penumbra/geometry/vec3.h"

namespace penumbra::cli {

struct ProbePoint {
  Vec3 position;
  Vec3 normal;     // unit length
  Vec3 rawNormal;  // as written in the file, echoed in the output
  int line = 0;
};

std::vector<ProbePoint> readPointsFile(const std::string& path);

}  // namespace penumbra::cli
