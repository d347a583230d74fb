#include "penumbra/render/shadow_volume_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <numbers>
#include <optional>
#include <vector>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/render/framebuffer.h"
#include "penumbra/render/gl_errors.h"
#include "penumbra/render/shader_program.h"
#include "penumbra/render/view_projection.h"
#include "penumbra/volumes/mirror_planes.h"

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
uniform vec4 clipPlane;  // relative to the eye; in effect where GL_CLIP_DISTANCE0 is enabled
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
  gl_ClipDistance[0] = dot(clipPlane, vec4(position, 1.0));
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
uniform vec3 tint;           // a mirror's reflectance in its reflection pass, else 1
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
    color = vec4(irradianceOnly != 0 ? vec3(0.0) : tint * surfaceEmission / kPi, 1.0);
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
  color = vec4(tint * (irradianceOnly != 0 ? e : surfaceReflectance * e / kPi), 0.0);
}
)";

constexpr const char* kVolumeVertexShader = R"(#version 330 core
layout(location = 0) in vec4 position;  // homogeneous, relative to the eye; w = 0 at infinity
uniform mat4 viewProjection;
uniform vec4 clipPlane;  // relative to the eye; in effect where GL_CLIP_DISTANCE0 is enabled
invariant gl_Position;
void main() {
  gl_Position = viewProjection * position;
  gl_ClipDistance[0] = dot(clipPlane, position);
}
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

// Stencil bits (see the header): which pass owns a pixel, and the shadow-volume count.
constexpr GLuint kMirrorDone = 0x80;
constexpr GLuint kMirrorCurrent = 0x40;
constexpr GLuint kOwnerBits = kMirrorDone | kMirrorCurrent;
constexpr GLuint kCountBits = 0x3F;
// Relative to the scene's size: well above the float rounding of eye-relative positions (~1e-7).
constexpr double kVolumeClip = 1e-5;

// Appends the triangles of `polygon` under `place` (winding reversed when it mirrors), each vertex
// relative to the eye with its normal, reflectance and emission.
void pushPolygon(std::vector<float>& out, const WorldPolygon& polygon, const Material& material,
                 const Transform& place, const Vec3& eye, Box3& bounds) {
  Polygon3 placed;
  for (const Vec3& v : polygon.vertices) placed.push_back(place.applyToPoint(v));
  const Vec3 normal = normalize(place.applyToNormal(polygon.plane.normal));
  const bool flip = place.isReflection();
  for (const auto& t : triangulate(polygon.vertices)) {
    const std::array<int, 3> order = flip ? std::array<int, 3>{t[0], t[2], t[1]} : t;
    for (int i : order) {
      push3(out, placed[i] - eye);
      push3(out, normal);
      push3(out, Vec3{material.reflectance.r, material.reflectance.g, material.reflectance.b});
      push3(out, Vec3{material.emission.r, material.emission.g, material.emission.b});
    }
  }
  for (const Vec3& v : placed) bounds.extend(v);
}

// A range of triangles in the scene buffer (in vertices).
struct Range {
  GLint first = 0;
  GLsizei count = 0;
};

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

// One scene drawn into the pixels whose owner bits equal `owner`: the scene itself, or its
// reflection in one mirror group.
struct ShadowVolumeRenderer::Pass {
  Transform place;  // applied to the scene, the light samples and the volumes
  bool reflected = false;
  Range triangles;   // its scene triangles in the scene buffer
  GLuint owner = 0;  // stencil owner bits of its pixels
  Rgb tint{1, 1, 1};
  bool clipped = false;  // keep only what lies behind the mirror plane
  float clipPlane[4] = {0, 0, 0, 0};
  // The volumes are clipped a little further (see render()).
  float volumeClipPlane[4] = {0, 0, 0, 0};
  Mat4 viewProjection;
  Vec3 eye;
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

void ShadowVolumeRenderer::drawPass(const PosedScene& scene, ShadowVolumeEngine& engine,
                                    const Pass& pass, const ShadowVolumeRenderOptions& options) {
  const Vec3& eye = pass.eye;
  auto useScene = [&](int lightPass) {
    gl_->scene.use();
    glUniform1i(gl_->scene.uniformLocation("lightPass"), lightPass);
    glBindVertexArray(gl_->sceneBuffer.vao);
    if (pass.clipped) glEnable(GL_CLIP_DISTANCE0);
  };
  auto drawScene = [&] {
    glDrawArrays(GL_TRIANGLES, pass.triangles.first, pass.triangles.count);
    glDisable(GL_CLIP_DISTANCE0);
  };
  gl_->scene.use();
  gl_->scene.setMat4("viewProjection", pass.viewProjection);
  glUniform4fv(gl_->scene.uniformLocation("clipPlane"), 1, pass.clipPlane);
  gl_->scene.setVec3("tint", pass.tint);
  glUniform1i(gl_->scene.uniformLocation("irradianceOnly"),
              options.output == ShadowVolumeRenderOptions::Output::kIrradiance ? 1 : 0);

  // Depth and emission in the pixels this pass owns. LEQUAL: with mirrors the scene's own depth
  // was laid down already by the same (invariant) triangles.
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0);
  glStencilFunc(GL_EQUAL, pass.owner, kOwnerBits);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthFunc(GL_LEQUAL);
  useScene(0);
  drawScene();

  std::vector<float> nearCaps, rest;
  // The engine jitters each light over its samples and hands over the volumes of each.
  engine.forEachLightSample(
      options.lightSamples, options.seed, [&](int l, const Vec3& sample, int sampleCount) {
        const LightVolumes& light = engine.lights()[l];
        const Material& material = scene.materials[scene.polygons[light.polygon].material];
        const Vec3 lightNormal =
            normalize(pass.place.applyToNormal(newellNormal(light.worldPolygon)));
        const Vec3 powerPerSample =
            Vec3{material.emission.r, material.emission.g, material.emission.b} *
            (area(light.worldPolygon) / double(sampleCount));
        // --- the volumes of this sample, under the reflection if any ---
        nearCaps.clear();
        rest.clear();
        for (const ObjectVolume& original : light.objects) {
          std::optional<ObjectVolume> reflected;
          if (pass.reflected) reflected = reflectedVolume(original, pass.place);
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
        // --- stencil: z-fail, two-sided, in the count bits only (the owner bits stay) ---
        glStencilMask(kCountBits);
        glClear(GL_STENCIL_BUFFER_BIT);
        glStencilFunc(GL_EQUAL, pass.owner, kOwnerBits);
        glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
        glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
        glDepthMask(GL_FALSE);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthFunc(GL_LESS);
        gl_->volume.use();
        gl_->volume.setMat4("viewProjection", pass.viewProjection);
        glUniform4fv(gl_->volume.uniformLocation("clipPlane"), 1, pass.volumeClipPlane);
        if (pass.clipped) glEnable(GL_CLIP_DISTANCE0);
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
        glDisable(GL_CLIP_DISTANCE0);

        // --- light where this pass owns the pixel and the count is zero, adding into the buffer
        // ---
        glStencilMask(0);
        glStencilFunc(GL_EQUAL, pass.owner, kOwnerBits | kCountBits);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_EQUAL);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        useScene(1);
        gl_->scene.setVec3("lightPosition", pass.place.applyToPoint(sample) - eye);
        gl_->scene.setVec3("lightNormal", lightNormal);
        gl_->scene.setVec3("lightPower", powerPerSample);
        drawScene();
        glDisable(GL_BLEND);
        throwOnGlError("drawing shadow volumes");
      });
  glDisable(GL_STENCIL_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

Image ShadowVolumeRenderer::render(const PosedScene& scene, ShadowVolumeEngine& engine,
                                   const Camera& camera, int width, int height,
                                   const ShadowVolumeRenderOptions& options) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  CHECK_GE(options.lightSamples, 1);
  CHECK(!(options.mirrors && options.reflection));
  const Vec3 eye = camera.eye;

  // Mirrors seen from their front only: from behind, a mirror is an ordinary (unlit) back face.
  std::vector<MirrorPlane> mirrors;
  if (options.mirrors) {
    for (MirrorPlane& m : findMirrorPlanes(scene))
      if (m.plane.signedDistance(eye) > 0) mirrors.push_back(std::move(m));
  }

  // --- the scene buffer: the scene, then per mirror its polygons and its reflected scene ---
  std::vector<float> sceneData;
  Box3 bounds;
  const Transform place = options.reflection.value_or(Transform::identity());
  auto rangeSince = [&](std::size_t start) {
    return Range{GLint(start / 12), GLsizei((sceneData.size() - start) / 12)};
  };
  for (const WorldPolygon& polygon : scene.polygons)
    pushPolygon(sceneData, polygon, scene.materialOf(polygon), place, eye, bounds);
  const Range sceneRange = rangeSince(0);
  std::vector<Range> mirrorRanges, reflectedRanges;
  const double inPlaneTolerance = 1e-9 * scene.extent.diagonalLength();
  for (const MirrorPlane& mirror : mirrors) {
    std::size_t start = sceneData.size();
    Box3 ignored;
    for (PolygonId id : mirror.polygons)
      pushPolygon(sceneData, scene.polygons[id], scene.materialOf(scene.polygons[id]),
                  Transform::identity(), eye, ignored);
    mirrorRanges.push_back(rangeSince(start));
    start = sceneData.size();
    // Polygons in the mirror plane (the mirror itself, a wall around it) are their own images,
    // seen edge-on from behind the mirror: left out rather than left to the clip plane's rounding.
    for (const WorldPolygon& polygon : scene.polygons)
      if (!liesInPlane(polygon, mirror.plane, inPlaneTolerance))
        pushPolygon(sceneData, polygon, scene.materialOf(polygon), mirror.reflection, eye, bounds);
    reflectedRanges.push_back(rangeSince(start));
  }
  glBindBuffer(GL_ARRAY_BUFFER, gl_->sceneBuffer.vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sceneData.size() * sizeof(float)), sceneData.data(),
               GL_STREAM_DRAW);

  // One projection for all passes (near plane before everything, reflections included).
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

  Pass direct;
  direct.place = place;
  direct.reflected = options.reflection.has_value();
  direct.triangles = sceneRange;
  direct.owner = 0;
  direct.viewProjection = transform;
  direct.eye = eye;

  if (!mirrors.empty()) {
    // The scene's own depth, so that only the visible parts of a mirror are marked.
    gl_->scene.use();
    gl_->scene.setMat4("viewProjection", transform);
    glUniform1i(gl_->scene.uniformLocation("lightPass"), 0);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthFunc(GL_LESS);
    glBindVertexArray(gl_->sceneBuffer.vao);
    glDrawArrays(GL_TRIANGLES, sceneRange.first, sceneRange.count);
  }
  for (std::size_t m = 0; m < mirrors.size(); ++m) {
    const MirrorPlane& mirror = mirrors[m];
    gl_->scene.use();
    gl_->scene.setMat4("viewProjection", transform);
    glUniform1i(gl_->scene.uniformLocation("lightPass"), 0);
    glBindVertexArray(gl_->sceneBuffer.vao);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnable(GL_STENCIL_TEST);
    // Mark: visible front faces of this mirror in pixels no earlier mirror has taken.
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glStencilMask(kMirrorCurrent);
    // Passes where the done bit is clear; the reference supplies the bit that REPLACE writes.
    glStencilFunc(GL_EQUAL, kMirrorCurrent, kMirrorDone);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    glDrawArrays(GL_TRIANGLES, mirrorRanges[m].first, mirrorRanges[m].count);
    glDisable(GL_CULL_FACE);
    // Reset depth to far there: the reflection lies behind the mirror's surface.
    glStencilMask(0);
    glStencilFunc(GL_EQUAL, kMirrorCurrent, kMirrorCurrent);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_ALWAYS);
    glDepthRange(1, 1);
    glDrawArrays(GL_TRIANGLES, mirrorRanges[m].first, mirrorRanges[m].count);
    glDepthRange(0, 1);

    Pass reflection;
    reflection.place = mirror.reflection;
    reflection.reflected = true;
    reflection.triangles = reflectedRanges[m];
    reflection.owner = kMirrorCurrent;
    reflection.tint = mirror.reflectance;
    reflection.clipped = true;
    // Keep n . x <= d (behind the mirror), x = position + eye.
    const Vec3 n = mirror.plane.normal;
    reflection.clipPlane[0] = float(-n.x);
    reflection.clipPlane[1] = float(-n.y);
    reflection.clipPlane[2] = float(-n.z);
    reflection.clipPlane[3] = float(-mirror.plane.signedDistance(eye));
    // Volumes lose what lies within kVolumeClip of the plane or in front of it. A z-fail count
    // only involves volume faces behind the visible surface, and in the mirror's pixels that
    // surface lies beyond the plane, so the counts stay exact for every surface further than
    // that from the plane; what goes is the caps lying in the plane (of the mirror itself), which
    // the near-cap polygon offset would otherwise push behind surfaces just beyond the mirror
    // (a line of false shadow along its borders).
    std::copy(reflection.clipPlane, reflection.clipPlane + 4, reflection.volumeClipPlane);
    reflection.volumeClipPlane[3] -= float(kVolumeClip * scene.extent.diagonalLength());
    reflection.viewProjection = transform;
    reflection.eye = eye;
    drawPass(scene, engine, reflection, options);

    // Hand the pixels over from "current" to "done" so later passes leave them alone.
    gl_->scene.use();
    glUniform1i(gl_->scene.uniformLocation("lightPass"), 0);
    glBindVertexArray(gl_->sceneBuffer.vao);
    glEnable(GL_STENCIL_TEST);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_ALWAYS);
    // Owner bits are "current, not done" there: inverting both makes them "done".
    glStencilMask(kOwnerBits);
    glStencilFunc(GL_EQUAL, kMirrorCurrent, kMirrorCurrent);
    glStencilOp(GL_KEEP, GL_KEEP, GL_INVERT);
    glDrawArrays(GL_TRIANGLES, mirrorRanges[m].first, mirrorRanges[m].count);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    throwOnGlError("marking a mirror");
  }

  drawPass(scene, engine, direct, options);
  glDisable(GL_DEPTH_CLAMP);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  Image image = target.readColor();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return image;
}

}  // namespace penumbra
