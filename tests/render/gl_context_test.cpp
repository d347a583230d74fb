#include "penumbra/render/gl_context.h"

#include <gtest/gtest.h>

#include "penumbra/render/framebuffer.h"

namespace penumbra {
namespace {

// No skipping: CI has neither a display nor a GPU, and headless EGL on llvmpipe must work there.
TEST(GlContext, HeadlessContextIsGl33CoreOnLlvmpipe) {
  const std::unique_ptr<GlContext> context = GlContext::createHeadless();
  ASSERT_NE(context, nullptr);
  EXPECT_TRUE(context->majorVersion() > 3 ||
              (context->majorVersion() == 3 && context->minorVersion() >= 3))
      << context->versionString();
  EXPECT_TRUE(context->isCoreProfile());
  EXPECT_NE(context->versionString().find("Core Profile"), std::string::npos)
      << context->versionString();
  EXPECT_NE(context->rendererString().find("llvmpipe"), std::string::npos)
      << context->rendererString();
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
