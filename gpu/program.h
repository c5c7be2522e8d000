#pragma once
// Shader programs for the port: GLSL 3.30 sources are compiled into the binary from
// gpu/shaders/ (one file per stage, named like the cpu_ref/ file it mirrors).
#include <string>

namespace mrr::gpu {

// The text of gpu/shaders/<name> (e.g. "gbuffer.frag"); throws MrrError if unknown.
const char* shaderSource(const std::string& name);

// Compiles and links; a compile or link error throws MrrError with the stage name and the
// driver's log on one line. `defines` ("#define X\n" lines) go after each #version line, so
// one file can hold a stage's variants (e.g. ssgi.frag: the direct light and the gather).
unsigned compileProgram(const std::string& stage, const std::string& vertexName, const std::string& fragmentName,
                        const std::string& defines = "");

// The same from source text (what compileProgram uses; tests feed it broken shaders).
unsigned compileProgramFromSource(const std::string& stage, const std::string& vertexName,
                                  const std::string& vertexText, const std::string& fragmentName,
                                  const std::string& fragmentText, const std::string& defines = "");

// Throws MrrError naming `stage` when glGetError reports an error (checked after every stage).
void checkGl(const std::string& stage);

}  // namespace mrr::gpu
