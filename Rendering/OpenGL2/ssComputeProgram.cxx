#include "ssComputeProgram.h"

#include <algorithm>

namespace ss
{
namespace
{
std::string InfoLog(GLuint obj, bool shader)
{
  GLint len = 0;
  shader ? glGetShaderiv(obj, GL_INFO_LOG_LENGTH, &len) : glGetProgramiv(obj, GL_INFO_LOG_LENGTH, &len);
  std::string s(static_cast<std::size_t>(std::max(len, 1)), '\0');
  shader ? glGetShaderInfoLog(obj, len, nullptr, &s[0]) : glGetProgramInfoLog(obj, len, nullptr, &s[0]);
  return s;
}
}

GLuint CompileComputeProgram(const std::string& source, std::string& error)
{
  const char* text = source.c_str();
  const GLuint sh = glCreateShader(GL_COMPUTE_SHADER);
  glShaderSource(sh, 1, &text, nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok)
  {
    error = "does not compile: " + InfoLog(sh, true);
    glDeleteShader(sh);
    return 0;
  }
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, sh);
  glLinkProgram(prog);
  glDeleteShader(sh);
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok)
  {
    error = "does not link: " + InfoLog(prog, false);
    glDeleteProgram(prog);
    return 0;
  }
  return prog;
}
}
