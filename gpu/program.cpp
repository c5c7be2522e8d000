#include "gpu/program.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "common/shader_constants.h"
#include "common/shader_contract.h"
#include "gpu/faults.h"
#include "gpu/shader_sources.h"

namespace mrr::gpu {

namespace {
const char* builtinSource(const std::string& name) {
  for (const ShaderFile& f : kShaderFiles)
    if (name == f.name) return f.text;
  throw MrrError("gpu: no shader named " + name);
}

// The user's shaders (--shaders DIR): file name → text, read once.
struct Overrides {
  std::string dir;
  std::map<std::string, std::string> texts;
};
Overrides& overrides() {
  static Overrides o;
  return o;
}
}  // namespace

std::vector<std::string> shaderFileNames() {
  std::vector<std::string> names;
  for (const ShaderFile& f : kShaderFiles) names.emplace_back(f.name);
  return names;
}

const char* shaderSource(const std::string& name) {
  const auto it = overrides().texts.find(name);
  if (it != overrides().texts.end()) return it->second.c_str();
  return builtinSource(name);
}

const char* builtinShaderSource(const std::string& name) { return builtinSource(name); }

bool shaderOverridden(const std::string& name) { return overrides().texts.count(name) != 0; }

std::string shaderPath(const std::string& name) {
  if (!shaderOverridden(name)) return "gpu/shaders/" + name;
  return (std::filesystem::path(overrides().dir) / name).string();
}

ShaderDirectory loadShaderDirectory(const std::string& dir) {
  std::error_code ec;
  require(std::filesystem::is_directory(dir, ec), "--shaders " + dir + ": no such folder");
  ShaderDirectory result;
  result.dir = dir;
  const std::vector<std::string> known = shaderFileNames();
  std::vector<std::filesystem::path> entries;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) entries.push_back(entry.path());
  require(!ec, "--shaders " + dir + ": cannot list the folder (" + ec.message() + ")");
  std::sort(entries.begin(), entries.end());
  Overrides loaded;
  loaded.dir = dir;
  for (const std::filesystem::path& path : entries) {
    const std::string name = path.filename().string();
    // `shaders export` writes README.md, and mrr's sampling as data into sampling/
    if (name.empty() || name[0] == '.' || name == "README.md" || name == "sampling") continue;
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      result.unknown.push_back(name);
      continue;
    }
    std::ifstream in(path, std::ios::binary);
    require(in.good() && std::filesystem::is_regular_file(path, ec), "--shaders " + path.string() + ": cannot read the file");
    std::ostringstream text;
    text << in.rdbuf();
    loaded.texts[name] = text.str();
    result.loaded.push_back(name);
  }
  overrides() = std::move(loaded);
  return result;
}


std::string locateShaderError(const std::string& log, const std::vector<std::string>& sourceFiles) {
  static const std::regex mesa(R"(^\s*(\d+):(\d+)\(\d+\): error: (.*)$)");
  static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\) : error \w*:? ?(.*)$)");
  static const std::regex other(R"(^\s*ERROR: (\d+):(\d+): (.*)$)");
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, mesa) || std::regex_match(line, m, nvidia) || std::regex_match(line, m, other)) {
      const size_t source = std::stoul(m[1].str());
      const std::string file = source < sourceFiles.size() ? shaderPath(sourceFiles[source]) : "source " + m[1].str();
      std::string message = m[3].str();
      while (!message.empty() && (message.back() == '\r' || message.back() == ' ')) message.pop_back();
      return file + ":" + m[2].str() + ": " + message;
    }
  }
  return {};
}

std::string sharedConstantsGlsl() {
  std::string text;
  for (const ShaderConstant& k : kShaderConstants) text += k.glslDeclaration() + "\n";
  return text;
}

namespace {
// Which stage each linked program was compiled for, to name it in errors, and its fragment file.
std::map<unsigned, ProgramName>& programNames() {
  static std::map<unsigned, ProgramName> names;
  return names;
}
// The programs made with a user's file (--shaders DIR): their uniforms are optional.
std::set<unsigned>& userPrograms() {
  static std::set<unsigned> programs;
  return programs;
}
std::string programStage(unsigned program) {
  const auto it = programNames().find(program);
  return it == programNames().end() ? std::string("unknown stage") : "stage " + it->second.stage;
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

// A shader's text as the driver sees it: the includes pasted, each preceded by `#line 1 k`
// (k: its source-string number) and followed by `#line n 0` back in the file, so a driver log's
// "k:line" names the file and its own line. `files[k]` is source string k.
struct Assembled {
  std::string text;
  std::vector<std::string> files;
};

using Lookup = std::string (*)(const std::string& name);
const std::string kBlocksVertex = "blocks.vert", kBlocksGeometry = "blocks.geom";
std::string lookupActive(const std::string& name) { return applyPlantedFault(name, shaderSource(name)); }
std::string lookupBuiltin(const std::string& name) { return builtinSource(name); }

Assembled assemble(const std::string& stage, const std::string& name, const std::string& text,
                   const std::string& defines, Lookup lookup) {
  // GLSL 3.30 has no #include: paste gpu/shaders/<file> where a line starts with
  // #include "<file>" (common.glsl, shadowmap.glsl). Pasted text is not searched again.
  Assembled a;
  a.files.push_back(name);
  const std::string include = "#include \"";
  size_t start = 0;
  for (int line = 1; start <= text.size(); ++line) {
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string content = text.substr(start, end - start);
    if (content.rfind(include, 0) == 0) {
      const size_t close = content.find('"', include.size());
      const std::string where = shaderPath(name) + ":" + std::to_string(line) + ": ";
      require(close != std::string::npos, where + "unterminated #include (stage " + stage + ")");
      const std::string file = content.substr(include.size(), close - include.size());
      const std::vector<std::string> known = shaderFileNames();
      require(std::find(known.begin(), known.end(), file) != known.end(),
              where + "#include \"" + file + "\": no such shader (stage " + stage + ")");
      a.text += "#line 1 " + std::to_string(a.files.size()) + "\n" + lookup(file) + "\n#line " +
                std::to_string(line + 1) + " 0";
      a.files.push_back(file);
    } else {
      a.text += content;
    }
    if (end == text.size()) break;
    a.text += '\n';
    start = end + 1;
  }
  // Defines (one "#define X" line each) and the shared constants (common/shader_constants.h)
  // go right after the #version line; `#line 2 0` keeps the file's own line numbers.
  const size_t eol = a.text.find('\n');
  a.text.insert(eol == std::string::npos ? a.text.size() : eol + 1, defines + sharedConstantsGlsl() + "#line 2 0\n");
  return a;
}

// "" for the default variant, else " (variant SHADOW_EDGES E_ONLY)": the #defines the host
// prepended, which is how a user tells the variants of one file apart (the program's cache key,
// `stage`, is internal).
std::string variantText(const std::string& defines) {
  std::string names;
  for (size_t at = defines.find("#define "); at != std::string::npos; at = defines.find("#define ", at + 8)) {
    const size_t start = at + 8, end = defines.find_first_of(" \n", start);
    names += (names.empty() ? "" : " ") + defines.substr(start, end - start);
  }
  return names.empty() ? "" : " (variant " + names + ")";
}

GLuint compile(const std::string& stage, const std::string& name, const std::string& text, GLenum type,
               const std::string& defines, Lookup lookup = lookupActive) {
  const GLuint shader = glCreateShader(type);
  const Assembled a = assemble(stage, name, text, defines, lookup);
  const char* sourceText = a.text.c_str();
  glShaderSource(shader, 1, &sourceText, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> raw(static_cast<size_t>(std::max(length, 1)));
    glGetShaderInfoLog(shader, length, nullptr, raw.data());
    glDeleteShader(shader);
    const std::string located = locateShaderError(raw.data(), a.files);
    if (!located.empty()) throw MrrError(located + " (" + name + variantText(defines) + " does not compile)");
    throw MrrError("gpu: " + shaderPath(name) + variantText(defines) + " does not compile: " + oneLine(raw.data()));
  }
  return shader;
}

GLuint link(const std::string& stage, GLuint vs, GLuint gs, GLuint fs, const std::string& blame) {
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  if (gs) glAttachShader(program, gs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  if (gs) glDeleteShader(gs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw MrrError((blame.empty() ? "gpu" : blame) + ": stage " + stage + ": link failed: " + log);
  }
  return program;
}

GLuint compileAndLink(const std::string& stage, const std::string& vertexName, const std::string& vertexText,
                      const std::string& fragmentName, const std::string& fragmentText, const std::string& defines,
                      Lookup lookup, const std::string& blame) {
  const GLuint vs = compile(stage, vertexName, vertexText, GL_VERTEX_SHADER, defines, lookup);
  GLuint gs = 0, fs = 0;
  try {
    // a pass drawn over a block map's runs: blocks.geom makes its rectangles (GpuScene::draw)
    if (vertexName == kBlocksVertex) gs = compile(stage, kBlocksGeometry, lookup(kBlocksGeometry), GL_GEOMETRY_SHADER, defines, lookup);
    fs = compile(stage, fragmentName, fragmentText, GL_FRAGMENT_SHADER, defines, lookup);
  } catch (...) {
    glDeleteShader(vs);
    if (gs) glDeleteShader(gs);
    throw;
  }
  return link(stage, vs, gs, fs, blame);
}

// The files a program is made of: its two shaders and what they include.
std::vector<std::string> programFiles(const std::string& vertexName, const std::string& vertexText,
                                      const std::string& fragmentName, const std::string& fragmentText) {
  std::vector<std::string> files = {fragmentName, vertexName};
  if (vertexName == kBlocksVertex) files.push_back(kBlocksGeometry);
  for (const std::string* text : {&fragmentText, &vertexText}) {
    static const std::regex include(R"re((^|\n)#include "([^"]+)")re");
    for (std::sregex_iterator it(text->begin(), text->end(), include), end; it != end; ++it) files.push_back((*it)[2]);
  }
  return files;
}

// A program made with a user's file (--shaders DIR) must give back what the stage's outputs
// need: every output the built-in program writes, at the same location (docs/shader-contract.md).
// Its uniforms are its own business: one it declares and never reads (the compiler drops it),
// or leaves out, the host skips (`uniform` gives -1 for it, which GL ignores). Checked against
// the built-in program of the same stage and defines; an error names the user's file and what
// is missing.
void checkAgainstBuiltin(GLuint program, const std::string& stage, const std::string& vertexName,
                         const std::string& fragmentName, const std::string& defines, const std::string& blame) {
  const GLuint reference = compileAndLink(stage, vertexName, builtinSource(vertexName), fragmentName,
                                          builtinSource(fragmentName), defines, lookupBuiltin, "");
  std::string missing;
  if (const ShaderContract* c = shaderContract(fragmentName); c && missing.empty())
    for (const ShaderVariable& out : c->outputs) {
      const std::string name(out.name);
      const GLint want = glGetFragDataLocation(reference, name.c_str());
      if (want < 0) continue;  // another variant's output
      const GLint got = glGetFragDataLocation(program, name.c_str());
      if (got != want) {
        missing = "lacks the output " + name + " at location " + std::to_string(want) + " (" + std::string(out.type) +
                  ": " + std::string(out.meaning) + ")" + (got >= 0 ? "; it is at location " + std::to_string(got) : "");
        break;
      }
    }
  glDeleteProgram(reference);
  if (!missing.empty()) {
    glDeleteProgram(program);
    throw MrrError(blame + ": stage " + stage + ": " + missing + " (docs/shader-contract.md)");
  }
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
  // The user's files among the program's (--shaders DIR), to name in errors.
  std::string blame;
  for (const std::string& f : programFiles(vertexName, vertexText, fragmentName, fragmentText))
    if (shaderOverridden(f) && blame.find(shaderPath(f)) == std::string::npos)
      blame += (blame.empty() ? "" : ", ") + shaderPath(f);
  const GLuint program =
      compileAndLink(stage, vertexName, vertexText, fragmentName, fragmentText, defines, lookupActive, blame);
  if (!blame.empty()) checkAgainstBuiltin(program, stage, vertexName, fragmentName, defines, blame);
  programNames()[program] = {stage, fragmentName};
  if (!blame.empty()) userPrograms().insert(program);
  else userPrograms().erase(program);
  return program;
}

ProgramName programName(unsigned program) {
  const auto it = programNames().find(program);
  return it == programNames().end() ? ProgramName() : it->second;
}

int uniform(unsigned program, const char* name) {
  const GLint location = glGetUniformLocation(program, name);
  if (location < 0) {
    // A planted fault (gpu/faults.h) may delete the code that read a uniform: not a host bug.
    static const bool strict = [] {
      const char* s = std::getenv("MRR_STRICT_UNIFORMS");
      return s && std::string(s) == "1" && !plantedFault();
    }();
    // a user's program (--shaders) may leave out, or never read, what the built-in one reads
    require(!strict || userPrograms().count(program) != 0, "gpu: program " + std::to_string(program) + " (" + programStage(program) +
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
