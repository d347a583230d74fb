#include "penumbra/render/gl_context.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "penumbra/render/framebuffer.h"

namespace penumbra {
namespace {

// No skipping: CI has neither a display nor a GPU, and headless EGL (Mesa's llvmpipe there) must
// work. Any driver that gives an OpenGL 3.3 core context passes: llvmpipe, a GPU's own driver.
// The version string's wording is the driver's ("4.5 (Core Profile) Mesa ...", "4.6.0 NVIDIA
// ..."), so the profile is asked of the context (GL_CONTEXT_PROFILE_MASK), not read from it.
TEST(GlContext, HeadlessContextIsGl33Core) {
  const std::unique_ptr<GlContext> context = GlContext::createHeadless();
  ASSERT_NE(context, nullptr);
  EXPECT_TRUE(context->majorVersion() > 3 ||
              (context->majorVersion() == 3 && context->minorVersion() >= 3))
      << context->versionString();
  EXPECT_TRUE(context->isCoreProfile()) << context->versionString();
  EXPECT_FALSE(context->versionString().empty());
  EXPECT_FALSE(context->rendererString().empty());
  std::printf("[ info     ] GL %s on %s\n", context->versionString().c_str(),
              context->rendererString().c_str());
  context->makeCurrent();
}

TEST(GlContext, TwoContextsCanLiveAndDieInAnyOrder) {
  auto first = GlContext::createHeadless();
  auto second = GlContext::createHeadless();
  first.reset();  // must not terminate the display the second one uses
  second->makeCurrent();
  Framebuffer framebuffer(4, 4);
  framebuffer.bind();
  framebuffer.clear({0.25, 0.5, 2});
  const Image image = framebuffer.readColor();
  EXPECT_EQ(image.at(3, 0), Rgb(0.25, 0.5, 2));
  second.reset();
  auto third = GlContext::createHeadless();
  EXPECT_FALSE(third->versionString().empty());
}

TEST(Framebuffer, HalfFloatTargetKeepsValuesAboveOne) {
  auto context = GlContext::createHeadless();
  Framebuffer framebuffer(3, 2, ColorFormat::kRgba16F);
  framebuffer.bind();
  framebuffer.clear({4, 0.5, 0});
  const Image image = framebuffer.readColor();
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  for (const Rgb& c : image.pixels) EXPECT_EQ(c, Rgb(4, 0.5, 0));
}

}  // namespace
}  // namespace penumbra
