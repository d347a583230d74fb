#include "penumbra/render/framebuffer.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/base/check.h"
#include "penumbra/render/gl_errors.h"
#include "penumbra/render/render_error.h"

namespace penumbra {

static_assert(sizeof(GLuint) == sizeof(unsigned int), "ids are stored as unsigned int");

Framebuffer::Framebuffer(int width, int height, ColorFormat format)
    : width_(width), height_(height), format_(format) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  throwOnGlError("before creating a framebuffer");

  glGenTextures(1, &colorTexture_);
  glBindTexture(GL_TEXTURE_2D, colorTexture_);
  const GLint internalFormat = format == ColorFormat::kRgba32F ? GL_RGBA32F : GL_RGBA16F;
  glTexImage2D(GL_TEXTURE_2D, 0, internalFormat, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
  // Sampled later (accumulation, display) one texel per pixel: no filtering, no mipmaps.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);

  glGenRenderbuffers(1, &depthStencil_);
  glBindRenderbuffer(GL_RENDERBUFFER, depthStencil_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);

  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colorTexture_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                            depthStencil_);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  try {
    throwOnGlError("creating a framebuffer");
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(status));
      throw RenderError("framebuffer " + std::to_string(width) + "x" + std::to_string(height) +
                        " is incomplete (status " + code + ")");
    }
  } catch (...) {
    release();
    throw;
  }
}

Framebuffer::~Framebuffer() {
  release();
}

void Framebuffer::release() noexcept {
  if (framebuffer_ != 0) glDeleteFramebuffers(1, &framebuffer_);
  if (depthStencil_ != 0) glDeleteRenderbuffers(1, &depthStencil_);
  if (colorTexture_ != 0) glDeleteTextures(1, &colorTexture_);
  framebuffer_ = depthStencil_ = colorTexture_ = 0;
}

Framebuffer::Framebuffer(Framebuffer&& other) noexcept
    : width_(other.width_),
      height_(other.height_),
      format_(other.format_),
      framebuffer_(std::exchange(other.framebuffer_, 0)),
      colorTexture_(std::exchange(other.colorTexture_, 0)),
      depthStencil_(std::exchange(other.depthStencil_, 0)) {}

Framebuffer& Framebuffer::operator=(Framebuffer&& other) noexcept {
  if (this != &other) {
    release();
    width_ = other.width_;
    height_ = other.height_;
    format_ = other.format_;
    framebuffer_ = std::exchange(other.framebuffer_, 0);
    colorTexture_ = std::exchange(other.colorTexture_, 0);
    depthStencil_ = std::exchange(other.depthStencil_, 0);
  }
  return *this;
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width_, height_);
}

void Framebuffer::clear(const Rgb& background) const {
  glClearColor(static_cast<float>(background.r), static_cast<float>(background.g),
               static_cast<float>(background.b), 1.0f);
  glClearDepth(1.0);
  glClearStencil(0);
  // Clears obey the write masks; a previous pass may have left them off.
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xFF);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

Image Framebuffer::readColor() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);  // float rows are always 4-byte aligned
  std::vector<float> rgba(static_cast<std::size_t>(width_) * height_ * 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
  throwOnGlError("reading back a framebuffer");
  Image image(width_, height_);
  for (int y = 0; y < height_; ++y) {
    const float* row = rgba.data() + static_cast<std::size_t>(height_ - 1 - y) * width_ * 4;
    for (int x = 0; x < width_; ++x) {
      image.at(x, y) = Rgb(row[4 * x], row[4 * x + 1], row[4 * x + 2]);
    }
  }
  return image;
}

}  // namespace penumbra
