#include "vscan/gl/gl_program.h"

#include <string>

namespace vscan::gl {
namespace {

StatusOr<GLuint> Compile(GLenum type, const char* source, const std::string& name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  char log[2048] = {};
  glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
  glDeleteShader(shader);
  return Internal(name + " shader does not compile: " + log);
}

}  // namespace

StatusOr<GLuint> BuildProgram(const char* vertex_source, const char* fragment_source, const char* name) {
  ASSIGN_OR_RETURN(const GLuint vertex, Compile(GL_VERTEX_SHADER, vertex_source, std::string(name) + " vertex"));
  auto fragment = Compile(GL_FRAGMENT_SHADER, fragment_source, std::string(name) + " fragment");
  if (!fragment.ok()) {
    glDeleteShader(vertex);
    return fragment.status();
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, *fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(*fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_TRUE) return program;
  char log[2048] = {};
  glGetProgramInfoLog(program, sizeof(log), nullptr, log);
  glDeleteProgram(program);
  return Internal(std::string(name) + " program does not link: " + log);
}

}  // namespace vscan::gl
