#pragma once
// Shader programs for the port: GLSL 3.30 sources are compiled into the binary from
// gpu/shaders/ (one file per stage, named like the cpu_ref/ file it mirrors).
#include <initializer_list>
#include <string>
#include <utility>

#include "common/camera.h"
#include "common/params.h"

namespace mrr::gpu {

// The text of gpu/shaders/<name> (e.g. "gbuffer.frag"); throws MrrError if unknown.
const char* shaderSource(const std::string& name);

// The shared constants (common/shader_constants.h) as GLSL `const float` lines, pasted after
// every shader's #version line.
std::string sharedConstantsGlsl();

// Compiles and links; a compile or link error throws MrrError with the stage name and the
// driver's log on one line. `defines` ("#define X\n" lines) go after each #version line, so
// one file can hold a stage's variants (e.g. ssgi.frag: the direct light and the gather).
unsigned compileProgram(const std::string& stage, const std::string& vertexName, const std::string& fragmentName,
                        const std::string& defines = "");

// The same from source text (what compileProgram uses; tests feed it broken shaders).
unsigned compileProgramFromSource(const std::string& stage, const std::string& vertexName,
                                  const std::string& vertexText, const std::string& fragmentName,
                                  const std::string& fragmentText, const std::string& defines = "");

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
