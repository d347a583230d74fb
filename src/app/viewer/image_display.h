#pragma once
// Shows an 8-bit sRGB image 1:1 in the window's default framebuffer and reads the window back
// (screenshots). Each window pixel fetches exactly one texel (texelFetch, no filtering, no
// blending), so what is on screen is the tone-mapped image byte for byte.

#include <cstdint>
#include <vector>

#include "penumbra/render/shader_program.h"

namespace penumbra::viewer {

class ImageDisplay {
 public:
  // Precondition: a GL context is current (and stays current for every call).
  ImageDisplay();
  ~ImageDisplay();
  ImageDisplay(const ImageDisplay&) = delete;
  ImageDisplay& operator=(const ImageDisplay&) = delete;

  // Interleaved 8-bit RGB, row 0 at the top. Precondition: rgb.size() == width * height * 3.
  void upload(const std::vector<std::uint8_t>& rgb, int width, int height);
  // Draws the image with its top-left corner at the top-left of the default framebuffer, whose
  // size is framebufferWidth x framebufferHeight; the rest is cleared to a dark grey.
  void draw(int framebufferWidth, int framebufferHeight) const;
  // The top-left width x height pixels of the default framebuffer's back buffer, row 0 at the
  // top, as interleaved 8-bit RGB. Call after drawing and before swapping.
  static std::vector<std::uint8_t> readBack(int width, int height, int framebufferHeight);

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  ShaderProgram program_;
  unsigned int texture_ = 0;
  unsigned int vao_ = 0;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace penumbra::viewer
