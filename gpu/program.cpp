#include "gpu/program.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cstring>
#include <vector>

#include "common/error.h"
#include "gpu/shader_sources.h"

namespace mrr::gpu {

const char* shaderSource(const std::string& name) {
  for (const ShaderFile& f : kShaderFiles)
    if (name == f.name) return f.text;
  throw MrrError("gpu: no shader named " + name);
}

namespace {
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// The info log of a shader or a program, on one line.
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
  GLint length = 0;
  getIv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<size_t>(std::max(length, 1)));
  getLog(object, length, nullptr, log.data());
  return oneLine(log.data());
}

GLuint compile(const std::string& stage, const std::string& name, const std::string& text, GLenum type) {
  const GLuint shader = glCreateShader(type);
  // GLSL 3.30 has no #include: paste common.glsl where a shader asks for it.
  std::string source = text;
  const std::string include = "#include \"common.glsl\"";
  if (const size_t at = source.find(include); at != std::string::npos)
    source.replace(at, include.size(), shaderSource("common.glsl"));
  const char* sourceText = source.c_str();
  glShaderSource(shader, 1, &sourceText, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw MrrError("gpu: stage " + stage + ": " + name + " does not compile: " + log);
  }
  return shader;
}
}  // namespace

unsigned compileProgram(const std::string& stage, const std::string& vertexName, const std::string& fragmentName) {
  return compileProgramFromSource(stage, vertexName, shaderSource(vertexName), fragmentName, shaderSource(fragmentName));
}

unsigned compileProgramFromSource(const std::string& stage, const std::string& vertexName, const std::string& vertexText,
                                  const std::string& fragmentName, const std::string& fragmentText) {
  const GLuint vs = compile(stage, vertexName, vertexText, GL_VERTEX_SHADER);
  GLuint fs = 0;
  try {
    fs = compile(stage, fragmentName, fragmentText, GL_FRAGMENT_SHADER);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw MrrError("gpu: stage " + stage + ": link failed: " + log);
  }
  return program;
}

void checkGl(const std::string& stage) {
  const GLenum e = glGetError();
  require(e == GL_NO_ERROR, "gpu: stage " + stage + ": GL error 0x" + [&] {
    char b[16];
    std::snprintf(b, sizeof b, "%04x", e);
    return std::string(b);
  }());
}

}  // namespace mrr::gpu
