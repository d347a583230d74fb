#include "penumbra/render/shadow_volume_renderer.h"

#include <glad/gl.h>

#include <numbers>
#include <optional>
#include <vector>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/render/framebuffer.h"
#include "penumbra/render/gl_errors.h"
#include "penumbra/render/shader_program.h"
#include "penumbra/render/view_projection.h"
#include "penumbra/volumes/light_samples.h"

namespace penumbra {
namespace {

// `invariant` in both programs: the lighting pass tests depth with GL_EQUAL against the depth
// pass, and the volumes' near caps must rasterize at the depth of the surfaces they came from.
constexpr const char* kSceneVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;  // relative to the eye
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 reflectance;
layout(location = 3) in vec3 emission;
uniform mat4 viewProjection;
out vec3 surfacePoint;
out vec3 surfaceNormal;
out vec3 surfaceReflectance;
out vec3 surfaceEmission;
invariant gl_Position;
void main() {
  surfacePoint = position;
  surfaceNormal = normal;
  surfaceReflectance = reflectance;
  surfaceEmission = emission;
  gl_Position = viewProjection * vec4(position, 1.0);
}
)";

constexpr const char* kSceneFragmentShader = R"(#version 330 core
in vec3 surfacePoint;
in vec3 surfaceNormal;
in vec3 surfaceReflectance;
in vec3 surfaceEmission;
uniform int lightPass;       // 0: depth + emission, 1: one point light sample
uniform int irradianceOnly;  // 1: write E instead of radiance
uniform vec3 lightPosition;  // relative to the eye
uniform vec3 lightNormal;    // the light's front normal
uniform vec3 lightPower;     // M * A / N
layout(location = 0) out vec4 color;
const float kPi = 3.14159265358979;
void main() {
  vec3 n = normalize(surfaceNormal);
  // The eye is at the origin: surfaces seen from behind receive and emit nothing.
  if (dot(n, surfacePoint) >= 0.0) {
    color = vec4(0.0);
    return;
  }
  if (lightPass == 0) {
    color = vec4(irradianceOnly != 0 ? vec3(0.0) : surfaceEmission / kPi, 1.0);
    return;
  }
  vec3 d = lightPosition - surfacePoint;
  float r2 = dot(d, d);
  float r = sqrt(r2);
  float cosP = dot(n, d) / r;
  float cosY = -dot(lightNormal, d) / r;
  if (cosP <= 0.0 || cosY <= 0.0) {
    color = vec4(0.0);
    return;
  }
  vec3 e = lightPower * (cosP * cosY / (kPi * r2));
  color = vec4(irradianceOnly != 0 ? e : surfaceReflectance * e / kPi, 0.0);
}
)";

constexpr const char* kVolumeVertexShader = R"(#version 330 core
layout(location = 0) in vec4 position;  // homogeneous, relative to the eye; w = 0 at infinity
uniform mat4 viewProjection;
invariant gl_Position;
void main() { gl_Position = viewProjection * position; }
)";

constexpr const char* kVolumeFragmentShader = R"(#version 330 core
layout(location = 0) out vec4 color;
void main() { color = vec4(0.0); }
)";

void push3(std::vector<float>& out, const Vec3& v) {
  out.push_back(static_cast<float>(v.x));
  out.push_back(static_cast<float>(v.y));
  out.push_back(static_cast<float>(v.z));
}

void push4(std::vector<float>& out, const Vec3& v, double w) {
  push3(out, v);
  out.push_back(static_cast<float>(w));
}

struct Buffer {
  GLuint vao = 0, vbo = 0;
  Buffer() {
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
  }
  ~Buffer() {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &vbo);
  }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
};

}  // namespace

struct ShadowVolumeRenderer::GlState {
  ShaderProgram scene{"shadow-volume scene", kSceneVertexShader, kSceneFragmentShader};
  ShaderProgram volume{"shadow volume", kVolumeVertexShader, kVolumeFragmentShader};
  Buffer sceneBuffer;
  Buffer volumeBuffer;
  std::optional<Framebuffer> framebuffer;
};

ShadowVolumeRenderer::ShadowVolumeRenderer() : gl_(std::make_unique<GlState>()) {
  glBindVertexArray(gl_->sceneBuffer.vao);
  glBindBuffer(GL_ARRAY_BUFFER, gl_->sceneBuffer.vbo);
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, 12 * sizeof(float),
                          reinterpret_cast<const void*>(std::size_t(a) * 3 * sizeof(float)));
  }
  glBindVertexArray(gl_->volumeBuffer.vao);
  glBindBuffer(GL_ARRAY_BUFFER, gl_->volumeBuffer.vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  throwOnGlError("creating the shadow-volume renderer");
}

ShadowVolumeRenderer::~ShadowVolumeRenderer() = default;

Image ShadowVolumeRenderer::render(const PosedScene& scene, ShadowVolumeEngine& engine,
                                   const Camera& camera, int width, int height,
                                   const ShadowVolumeRenderOptions& options) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  CHECK_GE(options.lightSamples, 1);
  const Transform place = options.reflection.value_or(Transform::identity());
  const bool flip = place.isReflection();
  const Vec3 eye = camera.eye;

  // --- the scene: triangles with normal, reflectance and emission, relative to the eye ---
  std::vector<float> sceneData;
  Box3 bounds;
  for (const WorldPolygon& polygon : scene.polygons) {
    const Material& material = scene.materialOf(polygon);
    Polygon3 placed;
    for (const Vec3& v : polygon.vertices) placed.push_back(place.applyToPoint(v));
    const Vec3 normal = normalize(place.applyToNormal(polygon.plane.normal));
    for (const auto& t : triangulate(polygon.vertices)) {
      const std::array<int, 3> order = flip ? std::array<int, 3>{t[0], t[2], t[1]} : t;
      for (int i : order) {
        push3(sceneData, placed[i] - eye);
        push3(sceneData, normal);
        push3(sceneData,
              Vec3{material.reflectance.r, material.reflectance.g, material.reflectance.b});
        push3(sceneData, Vec3{material.emission.r, material.emission.g, material.emission.b});
      }
    }
    for (const Vec3& v : placed) bounds.extend(v);
  }
  const GLsizei sceneVertices = GLsizei(sceneData.size() / 12);
  glBindBuffer(GL_ARRAY_BUFFER, gl_->sceneBuffer.vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sceneData.size() * sizeof(float)), sceneData.data(),
               GL_STREAM_DRAW);

  ClipRange clip = clipRangeFor(camera, bounds);
  clip.infiniteFar = true;
  Camera eyeAtOrigin = camera;
  eyeAtOrigin.eye = {0, 0, 0};
  eyeAtOrigin.target = camera.target - camera.eye;
  const Mat4 transform = viewProjection(eyeAtOrigin, width, height, clip).combined();

  if (!gl_->framebuffer || gl_->framebuffer->width() != width ||
      gl_->framebuffer->height() != height) {
    gl_->framebuffer.reset();
    gl_->framebuffer.emplace(width, height, ColorFormat::kRgba32F);
  }
  const Framebuffer& target = *gl_->framebuffer;
  target.bind();
  glStencilMask(0xFF);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  target.clear({0, 0, 0});
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_DEPTH_CLAMP);  // caps at infinity must not be clipped by depth rounding
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_STENCIL_TEST);

  // Pass 0: depth and emission.
  gl_->scene.use();
  gl_->scene.setMat4("viewProjection", transform);
  const bool irradianceOnly = options.output == ShadowVolumeRenderOptions::Output::kIrradiance;
  glUniform1i(gl_->scene.uniformLocation("irradianceOnly"), irradianceOnly ? 1 : 0);
  glUniform1i(gl_->scene.uniformLocation("lightPass"), 0);
  glDepthFunc(GL_LESS);
  glBindVertexArray(gl_->sceneBuffer.vao);
  glDrawArrays(GL_TRIANGLES, 0, sceneVertices);

  std::vector<float> nearCaps, rest;
  for (int l = 0; l < int(engine.lights().size()); ++l) {
    const LightVolumes& light = engine.lights()[l];
    const Material& material = scene.materials[scene.polygons[light.polygon].material];
    const double lightArea = area(light.worldPolygon);
    const Vec3 lightNormal = normalize(place.applyToNormal(newellNormal(light.worldPolygon)));
    const std::vector<Vec3> samples =
        stratifiedLightSamples(light.worldPolygon, options.lightSamples, options.seed + l);
    const Vec3 powerPerSample =
        Vec3{material.emission.r, material.emission.g, material.emission.b} *
        (lightArea / double(samples.size()));
    for (const Vec3& sample : samples) {
      engine.moveLight(l, sample);
      // --- the volumes of this sample, under the reflection if any ---
      nearCaps.clear();
      rest.clear();
      for (const ObjectVolume& original : light.objects) {
        std::optional<ObjectVolume> reflected;
        if (options.reflection) reflected = reflectedVolume(original, place);
        const ObjectVolume& v = reflected ? *reflected : original;
        const double w = v.baseW;
        auto nearAt = [&](int i) { return v.nearVertices[i] - eye; };
        auto baseAt = [&](int i) { return v.baseVertices[i] - eye * w; };
        for (const auto& t : v.capTriangles) {
          for (int i : t) push4(nearCaps, nearAt(i), 1);
          for (int k = 2; k >= 0; --k) push4(rest, baseAt(t[k]), w);
        }
        for (const auto& [a, b] : v.silhouetteEdges) {
          // Side quad (b, a, base a, base b), outward.
          push4(rest, nearAt(b), 1);
          push4(rest, nearAt(a), 1);
          push4(rest, baseAt(a), w);
          push4(rest, nearAt(b), 1);
          push4(rest, baseAt(a), w);
          push4(rest, baseAt(b), w);
        }
      }
      // --- stencil: z-fail, two-sided ---
      glClear(GL_STENCIL_BUFFER_BIT);
      glEnable(GL_STENCIL_TEST);
      glStencilFunc(GL_ALWAYS, 0, 0xFF);
      glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
      glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
      glDepthMask(GL_FALSE);
      glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      glDepthFunc(GL_LESS);
      gl_->volume.use();
      gl_->volume.setMat4("viewProjection", transform);
      glBindVertexArray(gl_->volumeBuffer.vao);
      glBindBuffer(GL_ARRAY_BUFFER, gl_->volumeBuffer.vbo);
      // Near caps are pushed back so that a lit surface counts its own cap as behind it.
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(1.0f, 2.0f);
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(nearCaps.size() * sizeof(float)), nearCaps.data(),
                   GL_STREAM_DRAW);
      glDrawArrays(GL_TRIANGLES, 0, GLsizei(nearCaps.size() / 4));
      glDisable(GL_POLYGON_OFFSET_FILL);
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(rest.size() * sizeof(float)), rest.data(),
                   GL_STREAM_DRAW);
      glDrawArrays(GL_TRIANGLES, 0, GLsizei(rest.size() / 4));

      // --- light where the count is zero, adding into the float buffer ---
      glStencilFunc(GL_EQUAL, 0, 0xFF);
      glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glDepthFunc(GL_EQUAL);
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      gl_->scene.use();
      glUniform1i(gl_->scene.uniformLocation("lightPass"), 1);
      gl_->scene.setVec3("lightPosition", place.applyToPoint(sample) - eye);
      gl_->scene.setVec3("lightNormal", lightNormal);
      gl_->scene.setVec3("lightPower", powerPerSample);
      glBindVertexArray(gl_->sceneBuffer.vao);
      glDrawArrays(GL_TRIANGLES, 0, sceneVertices);
      glDisable(GL_BLEND);
      glDisable(GL_STENCIL_TEST);
      throwOnGlError("drawing shadow volumes");
    }
    engine.moveLight(l, centroid(light.worldPolygon));
  }
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_CLAMP);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  Image image = target.readColor();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return image;
}

}  // namespace penumbra
