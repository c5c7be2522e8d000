#include "gpu/program.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <vector>

#include "common/error.h"
#include "common/shader_constants.h"
#include "gpu/faults.h"
#include "gpu/shader_sources.h"

namespace mrr::gpu {

const char* shaderSource(const std::string& name) {
  for (const ShaderFile& f : kShaderFiles)
    if (name == f.name) return f.text;
  throw MrrError("gpu: no shader named " + name);
}

std::string sharedConstantsGlsl() {
  std::string text;
  for (const ShaderConstant& k : kShaderConstants) {
    char line[96];
    std::snprintf(line, sizeof line, "const float %s = %.9g;\n", k.name, static_cast<double>(k.value));
    text += line;
  }
  return text;
}

namespace {
// Which stage each linked program was compiled for, to name it in errors.
std::map<unsigned, std::string>& programStages() {
  static std::map<unsigned, std::string> stages;
  return stages;
}
std::string programStage(unsigned program) {
  const auto it = programStages().find(program);
  return it == programStages().end() ? std::string("unknown stage") : "stage " + it->second;
}

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

GLuint compile(const std::string& stage, const std::string& name, const std::string& text, GLenum type,
               const std::string& defines) {
  const GLuint shader = glCreateShader(type);
  // GLSL 3.30 has no #include: paste gpu/shaders/<file> where a line starts with
  // #include "<file>" (common.glsl, shadowmap.glsl). Pasted text is not searched again.
  std::string source = text;
  const std::string include = "\n#include \"";
  for (size_t at = source.find(include); at != std::string::npos; at = source.find(include, at)) {
    const size_t start = at + 1, close = source.find('"', start + include.size() - 1);
    require(close != std::string::npos, "gpu: stage " + stage + ": " + name + ": unterminated #include");
    const std::string file = source.substr(start + include.size() - 1, close - start - include.size() + 1);
    const std::string pasted = applyPlantedFault(file, shaderSource(file));
    source.replace(start, close + 1 - start, pasted);
    at = start + pasted.size();
  }
  // Defines (one "#define X" line each) and the shared constants (common/shader_constants.h)
  // go right after the #version line.
  const size_t eol = source.find('\n');
  source.insert(eol == std::string::npos ? source.size() : eol + 1, defines + sharedConstantsGlsl() + "#line 2\n");  // driver logs keep the file's line numbers
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

unsigned compileProgram(const std::string& stage, const std::string& vertexName, const std::string& fragmentName,
                        const std::string& defines) {
  // A planted fault (MRR_GPU_FAULT, gpu/faults.h) patches the text here, and only here.
  return compileProgramFromSource(stage, vertexName, applyPlantedFault(vertexName, shaderSource(vertexName)),
                                  fragmentName, applyPlantedFault(fragmentName, shaderSource(fragmentName)), defines);
}

unsigned compileProgramFromSource(const std::string& stage, const std::string& vertexName,
                                  const std::string& vertexText, const std::string& fragmentName,
                                  const std::string& fragmentText, const std::string& defines) {
  const GLuint vs = compile(stage, vertexName, vertexText, GL_VERTEX_SHADER, defines);
  GLuint fs = 0;
  try {
    fs = compile(stage, fragmentName, fragmentText, GL_FRAGMENT_SHADER, defines);
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
  programStages()[program] = stage;
  return program;
}

int uniform(unsigned program, const char* name) {
  const GLint location = glGetUniformLocation(program, name);
  if (location < 0) {
    // A planted fault (gpu/faults.h) may delete the code that read a uniform: not a host bug.
    static const bool strict = [] {
      const char* s = std::getenv("MRR_STRICT_UNIFORMS");
      return s && std::string(s) == "1" && !plantedFault();
    }();
    require(!strict, "gpu: program " + std::to_string(program) + " (" + programStage(program) +
                         ") has no active uniform named " + name);
  }
  return location;
}

void bindTextures(unsigned program, std::initializer_list<std::pair<const char*, unsigned>> samplers, int firstUnit) {
  int unit = firstUnit;
  for (const auto& [name, texture] : samplers) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
    glBindTexture(GL_TEXTURE_2D, texture);
    glUniform1i(uniform(program, name), unit);
    ++unit;
  }
}

void setLevelUniforms(unsigned program, const View& view, const LevelConstants& level) {
  glUniform1i(uniform(program, "level"), level.index);
  glUniform1f(uniform(program, "invScale"), 1.0f / static_cast<float>(level.scale));
  glUniform3f(uniform(program, "camera"), view.focal, view.cx, view.cy);
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
