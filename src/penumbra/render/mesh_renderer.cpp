#include "penumbra/render/mesh_renderer.h"

#include <optional>

#include "penumbra/base/check.h"
#include "penumbra/render/framebuffer.h"
#include "penumbra/render/gl_errors.h"
#include "penumbra/render/shader_program.h"

namespace penumbra {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;  // relative to the eye
layout(location = 1) in vec3 radiance;
uniform mat4 viewProjection;
out vec3 vertexRadiance;
void main() {
  vertexRadiance = radiance;
  gl_Position = viewProjection * vec4(position, 1.0);
}
)";

// Perspective-correct interpolation (the GLSL default) is linear interpolation on the surface,
// which is what radiance at mesh vertices means.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 vertexRadiance;
uniform float radianceScale;  // 0 draws back sides unlit (Options::unlitBackFaces)
layout(location = 0) out vec4 color;
void main() { color = vec4(vertexRadiance * radianceScale, 1.0); }
)";

constexpr GLuint kPositionAttribute = 0;
constexpr GLuint kRadianceAttribute = 1;

// Float vertex data relative to the eye: single precision is then spent where the viewer is,
// instead of on the distance of the whole scene from the world origin.
void appendRelative(std::vector<float>& out, const Vec3& p, const Vec3& origin) {
  const Vec3 d = p - origin;
  out.push_back(static_cast<float>(d.x));
  out.push_back(static_cast<float>(d.y));
  out.push_back(static_cast<float>(d.z));
}

void appendColor(std::vector<float>& out, const Rgb& c) {
  out.push_back(static_cast<float>(c.r));
  out.push_back(static_cast<float>(c.g));
  out.push_back(static_cast<float>(c.b));
}

// A vertex array with a position and a radiance buffer (and optionally an index buffer).
struct VertexArray {
  GLuint vao = 0, positions = 0, radiances = 0, indices = 0;

  explicit VertexArray(bool indexed) {
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &positions);
    glGenBuffers(1, &radiances);
    if (indexed) glGenBuffers(1, &indices);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glEnableVertexAttribArray(kPositionAttribute);
    glVertexAttribPointer(kPositionAttribute, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, radiances);
    glEnableVertexAttribArray(kRadianceAttribute);
    glVertexAttribPointer(kRadianceAttribute, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    // The element buffer binding is part of the vertex array state.
    if (indexed) glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }
  ~VertexArray() {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &positions);
    glDeleteBuffers(1, &radiances);
    if (indices != 0) glDeleteBuffers(1, &indices);
  }
  VertexArray(const VertexArray&) = delete;
  VertexArray& operator=(const VertexArray&) = delete;

  void upload(const std::vector<float>& positionData, const std::vector<float>& radianceData) {
    // Orphan and refill: frames of a dynamic scene replace the whole mesh.
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positionData.size() * sizeof(float)),
                 positionData.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, radiances);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(radianceData.size() * sizeof(float)),
                 radianceData.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }
  void uploadIndices(const std::vector<std::uint32_t>& indexData) {
    glBindVertexArray(vao);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(indexData.size() * sizeof(std::uint32_t)),
                 indexData.data(), GL_STREAM_DRAW);
    glBindVertexArray(0);
  }
};

void checkMesh(const ColoredMesh& mesh) {
  CHECK_EQ(mesh.colors.size(), mesh.positions.size());
  CHECK_EQ(mesh.indices.size() % 3, 0u);
  for (std::uint32_t index : mesh.indices) CHECK_LT(index, mesh.positions.size());
}

}  // namespace

Box3 ColoredMesh::bounds() const {
  Box3 box;
  for (const Vec3& p : positions) box.extend(p);
  return box;
}

struct MeshRenderer::GlState {
  ShaderProgram program{"mesh radiance", kVertexShader, kFragmentShader};
  VertexArray mesh{true};
  VertexArray lines{false};
  std::optional<Framebuffer> framebuffer;
};

MeshRenderer::MeshRenderer() : MeshRenderer(Options{}) {}

MeshRenderer::MeshRenderer(const Options& options)
    : options_(options), gl_(std::make_unique<GlState>()) {
  throwOnGlError("creating the mesh renderer");
}

MeshRenderer::~MeshRenderer() = default;

Image MeshRenderer::render(const ColoredMesh& mesh, const Camera& camera, int width, int height) {
  return render(mesh, {}, camera, width, height);
}

Image MeshRenderer::render(const ColoredMesh& mesh, const std::vector<LineSet>& overlays,
                           const Camera& camera, int width, int height) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  checkMesh(mesh);
  for (const LineSet& lines : overlays) CHECK_EQ(lines.endpoints.size() % 2, 0u);

  ClipRange clip;
  if (options_.clip) {
    clip = *options_.clip;
  } else {
    Box3 bounds = mesh.bounds();
    for (const LineSet& lines : overlays) {
      for (const Vec3& p : lines.endpoints) bounds.extend(p);
    }
    clip = clipRangeFor(camera, bounds);
  }
  Camera eyeAtOrigin = camera;
  eyeAtOrigin.eye = {0, 0, 0};
  eyeAtOrigin.target = camera.target - camera.eye;
  const Mat4 transform = viewProjection(eyeAtOrigin, width, height, clip).combined();

  std::vector<float> positions, radiances;
  positions.reserve(mesh.positions.size() * 3);
  radiances.reserve(mesh.positions.size() * 3);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    appendRelative(positions, mesh.positions[i], camera.eye);
    appendColor(radiances, mesh.colors[i]);
  }
  gl_->mesh.upload(positions, radiances);
  gl_->mesh.uploadIndices(mesh.indices);

  positions.clear();
  radiances.clear();
  std::vector<std::pair<GLint, GLsizei>> lineRanges;
  for (const LineSet& lines : overlays) {
    lineRanges.emplace_back(static_cast<GLint>(positions.size() / 3),
                            static_cast<GLsizei>(lines.endpoints.size()));
    for (const Vec3& p : lines.endpoints) {
      appendRelative(positions, p, camera.eye);
      appendColor(radiances, lines.color);
    }
  }
  if (!positions.empty()) gl_->lines.upload(positions, radiances);
  throwOnGlError("uploading a mesh");

  if (!gl_->framebuffer || gl_->framebuffer->width() != width ||
      gl_->framebuffer->height() != height) {
    gl_->framebuffer.reset();  // free the old one before allocating the new one
    gl_->framebuffer.emplace(width, height, ColorFormat::kRgba32F);
  }
  const Framebuffer& target = *gl_->framebuffer;
  target.bind();
  target.clear(options_.background);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_STENCIL_TEST);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  // Without a far plane, points far away can round to depth >= 1 and be clipped; clamp instead.
  if (clip.infiniteFar) {
    glEnable(GL_DEPTH_CLAMP);
  } else {
    glDisable(GL_DEPTH_CLAMP);
  }
  gl_->program.use();
  gl_->program.setMat4("viewProjection", transform);

  if (!mesh.indices.empty()) {
    // Pushes the surfaces back a little so that overlay lines drawn on them win the depth test.
    if (!overlays.empty()) {
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(1.0f, 1.0f);
    }
    glBindVertexArray(gl_->mesh.vao);
    const auto count = static_cast<GLsizei>(mesh.indices.size());
    glUniform1f(gl_->program.uniformLocation("radianceScale"), 1.0f);
    if (!options_.unlitBackFaces) {
      glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    } else {
      // Front sides as they are; then back sides black and pushed further back, so that where a
      // back side ties in depth with a front side (along every crease of a solid) the front wins.
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
      glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
      glCullFace(GL_FRONT);
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(2.0f, 4.0f);
      glUniform1f(gl_->program.uniformLocation("radianceScale"), 0.0f);
      glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
      glUniform1f(gl_->program.uniformLocation("radianceScale"), 1.0f);
      glDisable(GL_CULL_FACE);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
  }
  if (!lineRanges.empty()) {
    glUniform1f(gl_->program.uniformLocation("radianceScale"), 1.0f);
    glDepthFunc(GL_LEQUAL);
    glBindVertexArray(gl_->lines.vao);
    for (const auto& [first, count] : lineRanges) {
      if (count > 0) glDrawArrays(GL_LINES, first, count);
    }
    glDepthFunc(GL_LESS);
  }
  glBindVertexArray(0);
  throwOnGlError("drawing a mesh");

  Image image = target.readColor();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return image;
}

}  // namespace penumbra
