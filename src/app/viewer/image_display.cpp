#include "image_display.h"

#include <glad/gl.h>

#include <cstring>

#include "penumbra/base/check.h"
#include "penumbra/render/gl_errors.h"

namespace penumbra::viewer {
namespace {

// One triangle covering the viewport; positions from gl_VertexID, so no vertex buffer.
constexpr const char* kVertexShader = R"(#version 330 core
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
uniform sampler2D image;
uniform int framebufferHeight;
layout(location = 0) out vec4 color;
void main() {
  ivec2 size = textureSize(image, 0);
  // Window rows count from the bottom, image rows from the top.
  ivec2 p = ivec2(int(gl_FragCoord.x), framebufferHeight - 1 - int(gl_FragCoord.y));
  if (p.x >= size.x || p.y >= size.y) {
    color = vec4(0.12, 0.12, 0.13, 1.0);
    return;
  }
  color = vec4(texelFetch(image, p, 0).rgb, 1.0);
}
)";

}  // namespace

ImageDisplay::ImageDisplay() : program_("image display", kVertexShader, kFragmentShader) {
  glGenTextures(1, &texture_);
  glGenVertexArrays(1, &vao_);
  throwOnGlError("creating the image display");
}

ImageDisplay::~ImageDisplay() {
  glDeleteTextures(1, &texture_);
  glDeleteVertexArrays(1, &vao_);
}

void ImageDisplay::upload(const std::vector<std::uint8_t>& rgb, int width, int height) {
  CHECK_EQ(rgb.size(), std::size_t(width) * std::size_t(height) * 3);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows of 3 * width bytes are not 4-aligned
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  width_ = width;
  height_ = height;
  throwOnGlError("uploading the image");
}

void ImageDisplay::draw(int framebufferWidth, int framebufferHeight) const {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, framebufferWidth, framebufferHeight);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_FRAMEBUFFER_SRGB);  // the texels are display values already
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  program_.use();
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glUniform1i(program_.uniformLocation("image"), 0);
  glUniform1i(program_.uniformLocation("framebufferHeight"), framebufferHeight);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, 0);
  throwOnGlError("drawing the image");
}

std::vector<std::uint8_t> ImageDisplay::readBack(int width, int height, int framebufferHeight) {
  std::vector<std::uint8_t> rows(std::size_t(width) * std::size_t(height) * 3);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, framebufferHeight - height, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  throwOnGlError("reading the window back");
  // GL's row 0 is the bottom one.
  std::vector<std::uint8_t> image(rows.size());
  const std::size_t stride = std::size_t(width) * 3;
  for (int y = 0; y < height; ++y)
    std::memcpy(image.data() + std::size_t(y) * stride,
                rows.data() + std::size_t(height - 1 - y) * stride, stride);
  return image;
}

}  // namespace penumbra::viewer
