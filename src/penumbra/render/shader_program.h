#pragma once
// A linked GLSL program (vertex + fragment, optionally geometry) owned RAII-style.
// Ids are plain unsigned ints (GLuint) so this header needs no GL header.

#include <string>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/vec3.h"
#include "penumbra/render/mat4.h"

namespace penumbra {

class ShaderProgram {
 public:
  // Precondition: a GL context is current. Compiles and links the stages; throws RenderError with
  // `name`, the stage and the driver's info log when compiling or linking fails.
  ShaderProgram(const std::string& name, const std::string& vertexSource,
                const std::string& fragmentSource, const std::string& geometrySource = {});
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const;
  unsigned int id() const { return id_; }

  // The location of an active uniform. Throws RenderError when the program has no such active
  // uniform, so a misspelt name fails loudly instead of silently setting nothing (note that GLSL
  // compilers remove uniforms that do not affect the output).
  int uniformLocation(const char* uniform) const;

  // Precondition for the setters: this program is in use (use()); GL 3.3 has no glProgramUniform.
  void setMat4(const char* uniform, const Mat4& value) const;
  void setVec3(const char* uniform, const Vec3& value) const;
  void setVec3(const char* uniform, const Rgb& value) const;

 private:
  std::string name_;
  unsigned int id_ = 0;
};

}  // namespace penumbra
