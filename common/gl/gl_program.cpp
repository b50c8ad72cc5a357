#include "common/gl/gl_program.h"

#include <glad/gl.h>

#include <algorithm>
#include <stdexcept>

namespace firstshot {

namespace {

/// The info log of a shader or program (full length, trailing line breaks dropped).
template <typename GetIv, typename GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
  GLint length = 0;
  getIv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  GLsizei written = 0;
  getLog(object, GLsizei(log.size()), &written, log.data());
  log.resize(size_t(std::clamp<GLsizei>(written, 0, GLsizei(log.size()))));
  while (!log.empty() && (log.back() == '\n' || log.back() == '\r' || log.back() == ' ')) log.pop_back();
  return log.empty() ? std::string("(no log)") : log;
}

}  // namespace

const char* shaderStageName(unsigned type) {
  switch (type) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_COMPUTE_SHADER: return "compute";
    case GL_GEOMETRY_SHADER: return "geometry";
    case GL_TESS_CONTROL_SHADER: return "tessellation control";
    case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation";
    default: return "unknown";
  }
}

unsigned linkProgram(const std::string& what, const std::vector<ShaderStage>& stages) {
  std::vector<GLuint> shaders;
  const auto deleteShaders = [&shaders] {
    for (GLuint s : shaders) glDeleteShader(s);  // attached ones are freed with their program
    shaders.clear();
  };
  for (const ShaderStage& stage : stages) {
    const GLuint s = glCreateShader(stage.type);
    if (s == 0) {
      deleteShaders();
      throw std::runtime_error(what + ": cannot create a " + shaderStageName(stage.type) + " shader");
    }
    shaders.push_back(s);
    glShaderSource(s, GLsizei(stage.parts.size()), stage.parts.data(), nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      const std::string log = infoLog(s, glGetShaderiv, glGetShaderInfoLog);
      deleteShaders();
      throw std::runtime_error(what + ": the " + shaderStageName(stage.type) + " shader does not compile: " + log);
    }
  }
  const GLuint program = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  deleteShaders();
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw std::runtime_error(what + ": the program does not link: " + log);
  }
  return program;
}

}  // namespace firstshot
