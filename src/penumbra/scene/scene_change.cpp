#include "penumbra/scene/scene_change.h"

namespace penumbra {

bool isSameTransform(const Transform& a, const Transform& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.linear.m[i][j] != b.linear.m[i][j]) return false;
  return a.translation == b.translation;
}

}  // namespace penumbra
