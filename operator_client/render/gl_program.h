// A linked GLSL program (RAII). Requires a current OpenGL 3.3 core context.
#pragma once

#include <string>

#include "operator_client/render/gl.h"

namespace mostar::render {

class GlProgram {
 public:
  GlProgram() = default;
  ~GlProgram();
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  // Compiles and links; false with the driver's log in `error`.
  bool Build(const char* vertex_source, const char* fragment_source, std::string* error);
  void Use() const { glUseProgram(id_); }
  GLint Uniform(const char* name) const { return glGetUniformLocation(id_, name); }
  GLuint id() const { return id_; }

 private:
  GLuint id_ = 0;
};

}  // namespace mostar::render
