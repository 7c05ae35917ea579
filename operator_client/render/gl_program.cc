#include "operator_client/render/gl_program.h"

#include <vector>

namespace mostar::render {

namespace {

GLuint Compile(GLenum kind, const char* source, std::string* error) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(std::max(length, 1)));
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    *error =
        std::string(kind == GL_VERTEX_SHADER ? "vertex" : "fragment") + " shader: " + log.data();
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

}  // namespace

GlProgram::~GlProgram() {
  if (id_ != 0) glDeleteProgram(id_);
}

bool GlProgram::Build(const char* vertex_source, const char* fragment_source, std::string* error) {
  const GLuint vs = Compile(GL_VERTEX_SHADER, vertex_source, error);
  if (vs == 0) return false;
  const GLuint fs = Compile(GL_FRAGMENT_SHADER, fragment_source, error);
  if (fs == 0) {
    glDeleteShader(vs);
    return false;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  glLinkProgram(id_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = {0};
    glGetProgramInfoLog(id_, sizeof(log), nullptr, log);
    *error = std::string("link: ") + log;
    glDeleteProgram(id_);
    id_ = 0;
    return false;
  }
  return true;
}

}  // namespace mostar::render
