#pragma once
// An offscreen render target: a floating-point colour texture plus a 24-bit depth / 8-bit stencil
// renderbuffer. Headless contexts have no default framebuffer, so every image is drawn into one of
// these; float colour keeps images radiometric (no clamping to [0, 1], no 8-bit banding when
// passes are accumulated).

#include "penumbra/base/rgb.h"
#include "penumbra/render/image.h"

namespace penumbra {

enum class ColorFormat {
  kRgba16F,  // half floats: enough for accumulating jittered passes, half the bandwidth
  kRgba32F,  // full floats: what a radiometric image read-back should use
};

class Framebuffer {
 public:
  // Precondition: a GL context is current; width, height > 0. Throws RenderError when the driver
  // cannot make a complete framebuffer of this size and format.
  Framebuffer(int width, int height, ColorFormat format = ColorFormat::kRgba32F);
  ~Framebuffer();
  Framebuffer(Framebuffer&& other) noexcept;
  Framebuffer& operator=(Framebuffer&& other) noexcept;
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  // Makes this the draw and read framebuffer and sets the viewport to cover it.
  void bind() const;
  // Precondition: bound. Colour to (background, 1), depth to 1, stencil to 0.
  void clear(const Rgb& background) const;
  // The colour attachment as an Image, row 0 at the top (GL's row 0 is the bottom one).
  // Precondition: the context that made this framebuffer is current. Leaves it bound.
  Image readColor() const;

  int width() const { return width_; }
  int height() const { return height_; }
  ColorFormat format() const { return format_; }
  unsigned int id() const { return framebuffer_; }
  unsigned int colorTexture() const { return colorTexture_; }

 private:
  void release() noexcept;

  int width_ = 0;
  int height_ = 0;
  ColorFormat format_ = ColorFormat::kRgba32F;
  unsigned int framebuffer_ = 0;
  unsigned int colorTexture_ = 0;
  unsigned int depthStencil_ = 0;
};

}  // namespace penumbra
