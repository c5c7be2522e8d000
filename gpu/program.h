#pragma once
// Shader programs for the port: GLSL 3.30 sources are compiled into the binary from
// gpu/shaders/ (one file per stage, named like the cpu_ref/ file it mirrors).
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "common/camera.h"
#include "common/params.h"

namespace mrr::gpu {

// The text of gpu/shaders/<name> (e.g. "gbuffer.frag"), or of the user's file of that name
// when loadShaderDirectory read one; throws MrrError if unknown.
const char* shaderSource(const std::string& name);
// The built-in text, whatever --shaders gave.
const char* builtinShaderSource(const std::string& name);
// Every built-in file name: the stage shaders and their includes, sorted.
std::vector<std::string> shaderFileNames();

// --shaders DIR: each file of DIR named like a built-in shader replaces it (includes too);
// the built-ins serve the rest. `loaded`: the files taken from DIR; `unknown`: files of DIR
// that are no shader of mrr (README.md and hidden files are ignored). Throws MrrError when
// DIR is not a folder. Process-wide: every program compiled afterwards sees it.
struct ShaderDirectory {
  std::string dir;
  std::vector<std::string> loaded, unknown;
};
ShaderDirectory loadShaderDirectory(const std::string& dir);
bool shaderOverridden(const std::string& name);
// Where a shader comes from, for messages: "DIR/ssao.frag" or "gpu/shaders/ssao.frag".
std::string shaderPath(const std::string& name);

// The shared constants (common/shader_constants.h) as GLSL `const int` and `const float`
// lines, one per kShaderConstants entry in its order, pasted after every shader's #version line.
std::string sharedConstantsGlsl();

// The first error of a driver's compile log as "FILE:LINE: message", FILE named through the
// source-string numbers (`sourceFiles[k]` is source string k, as `#line N k` set it; shown as
// shaderPath). Reads Mesa ("0:42(5): error: msg"), NVIDIA ("0(42) : error C0000: msg") and
// AMD's ("ERROR: 0:42: msg"); "" when no line of the log is in one of these forms.
std::string locateShaderError(const std::string& log, const std::vector<std::string>& sourceFiles);

// Compiles and links; a compile error throws MrrError "FILE:LINE: the driver's message (stage
// S: NAME does not compile)", FILE:LINE in the file the error is in (an include too); a link
// error names the stage and the driver's log on one line. A program made with a user's file
// must have every uniform and output the built-in one has (else MrrError naming it). `defines` ("#define X\n" lines) go after each #version line, so
// one file can hold a stage's variants (e.g. ssgi.frag: the direct light and the gather).
unsigned compileProgram(const std::string& stage, const std::string& vertexName, const std::string& fragmentName,
                        const std::string& defines = "");

// The same from source text (what compileProgram uses; tests feed it broken shaders).
unsigned compileProgramFromSource(const std::string& stage, const std::string& vertexName,
                                  const std::string& vertexText, const std::string& fragmentName,
                                  const std::string& fragmentText, const std::string& defines = "");

// What compiled `program`: the stage key it was compiled under (its variant included, e.g.
// "blend.final.7.3.covered.blocks") and its fragment shader file; empty for a program not made here.
struct ProgramName {
  std::string stage, fragment;
};
ProgramName programName(unsigned program);

// The location of the uniform `name` of `program`. A name the program does not have as an
// active uniform (a typo, or a value the shader ignores) would silently set nothing: with
// MRR_STRICT_UNIFORMS=1 (every test runs so, tests/CMakeLists.txt) it throws MrrError naming
// the uniform and the program's stage; otherwise it returns -1, which GL ignores.
int uniform(unsigned program, const char* name);

// Binds each texture to the next texture unit from `firstUnit` on and points the named
// sampler uniform of `program` at it (the program must be in use).
void bindTextures(unsigned program, std::initializer_list<std::pair<const char*, unsigned>> samplers,
                  int firstUnit = 0);

// The uniforms every level pass shares: level (ℓ, for the hash), invScale (1/s_ℓ) and camera
// (focal length and principal point, to project view points to pixels).
void setLevelUniforms(unsigned program, const View& view, const LevelConstants& level);

// Throws MrrError naming `stage` when glGetError reports an error (checked after every stage).
void checkGl(const std::string& stage);

}  // namespace mrr::gpu
