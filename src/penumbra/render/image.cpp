#include "penumbra/render/image.h"

namespace penumbra {

Image::Image(int w, int h, const Rgb& fill) : width(w), height(h) {
  CHECK_GE(w, 0);
  CHECK_GE(h, 0);
  pixels.assign(static_cast<std::size_t>(w) * h, fill);
}

}  // namespace penumbra
