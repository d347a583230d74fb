#include "penumbra/render/shader_program.h"

#include <utility>
#include <vector>

#include "penumbra/render/gl_errors.h"
#include "penumbra/render/render_error.h"

namespace penumbra {
namespace {

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log.data();
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log.data();
}

GLuint compile(const std::string& programName, GLenum stage, const char* stageName,
               const std::string& source) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = shaderLog(shader);
    glDeleteShader(shader);
    throw RenderError("shader program '" + programName + "': " + stageName +
                      " shader does not compile:\n" + log);
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::string& name, const std::string& vertexSource,
                             const std::string& fragmentSource, const std::string& geometrySource)
    : name_(name) {
  std::vector<GLuint> shaders;
  auto deleteShaders = [&shaders] {
    for (GLuint s : shaders) glDeleteShader(s);
  };
  try {
    shaders.push_back(compile(name_, GL_VERTEX_SHADER, "vertex", vertexSource));
    if (!geometrySource.empty()) {
      shaders.push_back(compile(name_, GL_GEOMETRY_SHADER, "geometry", geometrySource));
    }
    shaders.push_back(compile(name_, GL_FRAGMENT_SHADER, "fragment", fragmentSource));
  } catch (...) {
    deleteShaders();
    throw;
  }
  id_ = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(id_, s);
  glLinkProgram(id_);
  // Shaders are only flagged for deletion while attached; they go with the program.
  deleteShaders();
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = programLog(id_);
    glDeleteProgram(id_);
    id_ = 0;
    throw RenderError("shader program '" + name_ + "' does not link:\n" + log);
  }
  throwOnGlError(("shader program '" + name_ + "'").c_str());
}

ShaderProgram::~ShaderProgram() {
  if (id_ != 0) glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : name_(std::move(other.name_)), id_(std::exchange(other.id_, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteProgram(id_);
    name_ = std::move(other.name_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

void ShaderProgram::use() const {
  glUseProgram(id_);
}

int ShaderProgram::uniformLocation(const char* uniform) const {
  const GLint location = glGetUniformLocation(id_, uniform);
  if (location < 0) {
    throw RenderError("shader program '" + name_ + "' has no active uniform '" + uniform + "'");
  }
  return location;
}

void ShaderProgram::setMat4(const char* uniform, const Mat4& value) const {
  const std::array<float, 16> columns = value.columnMajorFloats();
  glUniformMatrix4fv(uniformLocation(uniform), 1, GL_FALSE, columns.data());
}

void ShaderProgram::setVec3(const char* uniform, const Vec3& value) const {
  glUniform3f(uniformLocation(uniform), static_cast<float>(value.x), static_cast<float>(value.y),
              static_cast<float>(value.z));
}

void ShaderProgram::setVec3(const char* uniform, const Rgb& value) const {
  glUniform3f(uniformLocation(uniform), static_cast<float>(value.r), static_cast<float>(value.g),
              static_cast<float>(value.b));
}

}  // namespace penumbra
