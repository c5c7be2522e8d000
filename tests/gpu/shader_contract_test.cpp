// The shader contract (common/shader_contract.h, docs/shader-contract.md) against the shaders
// themselves: every file of gpu/shaders/ has a row, and each row lists exactly the uniforms,
// textures, attributes, varyings and outputs (with locations) the file declares. No GL needed.
// Then the shared constants (common/shader_constants.h): pasted with their C++ type and value,
// declared by no shader, and seen by the driver as the very C++ values (GL).
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "common/error.h"
#include "common/scene.h"
#include "common/shader_constants.h"
#include "common/shader_contract.h"
#include "common/stages.h"
#include "gpu/context.h"
#include "gpu/gbuffer.h"
#include "gpu/program.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

struct Declared {
  std::set<std::string> textures, uniforms, inputs, outputs;  // outputs: "name@location" (-1: a varying)
};

// Declarations at the start of a line (function parameters are indented): `uniform T a, b[N];`,
// `layout(location = N) out|in T name;`, `out|in T name;`.
Declared declarations(const std::string& text) {
  Declared d;
  static const std::regex uniform(R"(^uniform\s+(\w+)\s+([^;]+);)");
  static const std::regex located(R"(^layout\s*\(\s*location\s*=\s*(\d+)\s*\)\s*(in|out)\s+\w+\s+(\w+)\s*;)");
  static const std::regex plain(R"(^(in|out)\s+\w+\s+(\w+)\s*;)");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, uniform)) {
      std::istringstream names(m[2].str());
      for (std::string n; std::getline(names, n, ',');) {
        n = std::regex_replace(n, std::regex(R"(\[.*\]|\s)"), "");
        (m[1].str() == "sampler2D" ? d.textures : d.uniforms).insert(n);
      }
    } else if (std::regex_search(line, m, located)) {
      (m[2].str() == "out" ? d.outputs : d.inputs).insert(m[3].str() + (m[2].str() == "out" ? "@" + m[1].str() : ""));
    } else if (std::regex_search(line, m, plain)) {
      (m[1].str() == "out" ? d.outputs : d.inputs).insert(m[2].str() + (m[1].str() == "out" ? "@-1" : ""));
    }
  }
  return d;
}

TEST(ShaderContract, EveryShaderFileHasARowAndNoOther) {
  std::set<std::string> files, rows;
  for (const std::string& f : gpu::shaderFileNames()) files.insert(f);
  for (const ShaderContract& c : shaderContracts()) rows.insert(std::string(c.file));
  EXPECT_EQ(files, rows);
  // the stage list's shaders all have a row
  for (const PartInfo& p : kParts) {
    std::istringstream names{std::string(p.shader)};
    for (std::string n; names >> n;) EXPECT_NE(shaderContract(n), nullptr) << p.name << ": " << n;
  }
}

TEST(ShaderContract, RowsListExactlyWhatEachFileDeclares) {
  for (const ShaderContract& c : shaderContracts()) {
    const std::string file(c.file);
    const Declared d = declarations(gpu::builtinShaderSource(file));
    Declared listed;
    for (const ShaderVariable& v : c.inputs) {
      const std::string type(v.type);
      if (type.rfind("sampler2D", 0) == 0) listed.textures.insert(std::string(v.name));
      else listed.inputs.insert(std::string(v.name));
    }
    for (const ShaderVariable& v : c.uniforms) listed.uniforms.insert(std::string(v.name));
    for (const ShaderVariable& v : c.outputs) listed.outputs.insert(std::string(v.name) + "@" + std::to_string(v.location));
    EXPECT_EQ(d.textures, listed.textures) << file << ": textures";
    EXPECT_EQ(d.uniforms, listed.uniforms) << file << ": uniforms";
    EXPECT_EQ(d.inputs, listed.inputs) << file << ": attributes and varyings in";
    EXPECT_EQ(d.outputs, listed.outputs) << file << ": outputs";
    EXPECT_FALSE(c.oracle.empty()) << file;
  }
}

// The document names every stage of the stage list and every file.
TEST(ShaderContract, DocumentCoversTheStageListAndEveryFile) {
  const std::string md = shaderContractMarkdown();
  for (const PartInfo& p : kParts) EXPECT_NE(md.find("| `" + std::string(p.name) + "` |"), std::string::npos) << p.name;
  for (const ShaderContract& c : shaderContracts())
    EXPECT_NE(md.find("### " + std::string(c.file) + "\n"), std::string::npos) << c.file;
  // and every shared constant as the shaders see it
  for (const ShaderConstant& k : kShaderConstants)
    EXPECT_NE(md.find("\n" + k.glslDeclaration() + "\n"), std::string::npos) << k.name;
}

// A shader's text without its comments (// to the end of the line, /* … */).
std::string withoutComments(const std::string& text) {
  static const std::regex comments(R"(//[^\n]*|/\*[\s\S]*?\*/)");
  return std::regex_replace(text, comments, "");
}

// No built-in shader declares a shared constant's name (the host pastes it; a shader's own copy
// would be a second definition of the number, and does not compile besides).
TEST(SharedConstants, NoShaderDeclaresOne) {
  for (const std::string& file : gpu::shaderFileNames()) {
    const std::string text = withoutComments(gpu::builtinShaderSource(file));
    for (const ShaderConstant& k : kShaderConstants) {
      const std::regex declared("(\\b(float|int|uint|bool)\\s+|#define\\s+)" + std::string(k.name) + "\\b");
      EXPECT_FALSE(std::regex_search(text, declared)) << file << " declares " << k.name << " (common/shader_constants.h)";
    }
  }
}

// A number a built-in shader fixes at file scope is one the oracle uses too, so it belongs in
// common/shader_constants.h: the shaders declare no file-scope constants but π (SSGI's form
// factor; π is not a choice that could drift).
TEST(SharedConstants, ShadersDeclareNoFileScopeConstantsOfTheirOwn) {
  static const std::regex fileScope(R"((^|\n)const\s+\w+\s+(\w+))");
  for (const std::string& file : gpu::shaderFileNames()) {
    const std::string text = withoutComments(gpu::builtinShaderSource(file));
    for (std::sregex_iterator it(text.begin(), text.end(), fileScope), end; it != end; ++it)
      EXPECT_EQ((*it)[2].str(), "kPi") << file << ": a file-scope constant; numbers the oracle shares belong in "
                                        << "common/shader_constants.h (kShaderConstants)";
  }
}

// The pasted text: one line per constant, in the table's order, `const int` for a C++ integer and
// `const float` with a float literal for a C++ float, whose decimal text reads back as the same
// float bit for bit.
TEST(SharedConstants, PastedWithTheirCppTypeAndValue) {
  std::istringstream lines(gpu::sharedConstantsGlsl());
  static const std::regex declaration(R"(^const (int|float) (\w+) = ([^;]+);$)");
  size_t i = 0;
  std::set<std::string> names;
  for (std::string line; std::getline(lines, line); ++i) {
    ASSERT_LT(i, std::size(kShaderConstants)) << line;
    const ShaderConstant& k = kShaderConstants[i];
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, declaration)) << line;
    EXPECT_EQ(m[2].str(), k.name);
    EXPECT_TRUE(names.insert(m[2].str()).second) << "twice: " << k.name;
    const std::string value = m[3].str();
    if (k.isInt) {
      EXPECT_EQ(m[1].str(), "int") << line;
      EXPECT_EQ(value, std::to_string(k.intValue)) << line;
    } else {
      EXPECT_EQ(m[1].str(), "float") << line;
      EXPECT_NE(value.find_first_of(".e"), std::string::npos) << line << ": not a float literal";
      EXPECT_EQ(std::bit_cast<uint32_t>(std::strtof(value.c_str(), nullptr)), std::bit_cast<uint32_t>(k.floatValue))
          << line << " does not read back as " << k.floatValue;
    }
  }
  EXPECT_EQ(i, std::size(kShaderConstants));
  // the C++ types decide the GLSL ones
  EXPECT_EQ(std::string(ShaderConstant("a", kTileSize).glslType()), "int");
  EXPECT_EQ(std::string(ShaderConstant("b", kPcfSamplePcf).glslType()), "int");  // a class byte
  EXPECT_EQ(std::string(ShaderConstant("c", kMaxSearchTexels).glslType()), "float");
  EXPECT_EQ(ShaderConstant("d", 64.0f).glslDeclaration(), "const float d = 64.0;");
  EXPECT_EQ(ShaderConstant("e", 1.0e9f).glslDeclaration(), "const float e = 1e+09;");
}

// Each shared constant is read by some built-in shader: the table holds what the shaders share.
TEST(SharedConstants, EveryOneIsUsedByABuiltinShader) {
  std::string all;
  for (const std::string& file : gpu::shaderFileNames()) all += withoutComments(gpu::builtinShaderSource(file));
  for (const ShaderConstant& k : kShaderConstants)
    EXPECT_TRUE(std::regex_search(all, std::regex("\\b" + std::string(k.name) + "\\b")))
        << k.name << ": no built-in shader reads it";
}

// The driver compiles the pasted declarations to the C++ values, bit for bit: a probe pass
// writes constant i at pixel (i, 0) of an RGBA32F target, each first assigned to a variable of
// its GLSL type (an int constant that were not an int would not compile there).
TEST(GpuSharedConstants, TheDriverSeesTheCppValues) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::string probe = "#version 330 core\nlayout(location = 0) out vec4 value;\nvoid main() {\n"
                      "  int i = int(gl_FragCoord.x);\n  float v = -1.0;\n";
  const int n = static_cast<int>(std::size(kShaderConstants));
  for (int i = 0; i < n; ++i) {
    const ShaderConstant& k = kShaderConstants[i];
    ASSERT_TRUE(!k.isInt || (k.intValue >= -(1 << 24) && k.intValue <= (1 << 24))) << k.name << ": not exact in a float";
    probe += "  if (i == " + std::to_string(i) + ") { " + k.glslType() + " c = " + k.name + "; v = float(c); }\n";
  }
  probe += "  value = vec4(v, 0.0, 0.0, 1.0);\n}\n";
  const unsigned program = gpu::compileProgramFromSource("shared.constants", "fullscreen.vert",
                                                         gpu::shaderSource("fullscreen.vert"), "constants_probe.frag", probe, "");
  const gpu::Framebuffer target(n, 1, 1, false, gpu::Texel::Rgba32f);
  target.bind();
  glUseProgram(program);
  scene.drawFullscreen();
  gpu::checkGl("shared constants probe");
  const ImageF seen = target.read(0);
  for (int i = 0; i < n; ++i) {
    const ShaderConstant& k = kShaderConstants[i];
    const float want = k.isInt ? static_cast<float>(k.intValue) : k.floatValue;
    EXPECT_EQ(std::bit_cast<uint32_t>(seen.at(i, 0, 0)), std::bit_cast<uint32_t>(want))
        << k.name << ": the driver sees " << seen.at(i, 0, 0) << ", C++ has " << want;
  }
  glDeleteProgram(program);
}

// Driver logs in the three forms, mapped to the file of their source string (no GL needed).
TEST(ShaderErrors, DriverLogsNameTheFileAndLine) {
  const std::vector<std::string> files = {"ssao.frag", "common.glsl"};
  EXPECT_EQ(gpu::locateShaderError("0:42(5): error: syntax error, unexpected ';'\n", files),
            "gpu/shaders/ssao.frag:42: syntax error, unexpected ';'");
  EXPECT_EQ(gpu::locateShaderError("1(7) : error C0000: syntax error, unexpected identifier\n", files),
            "gpu/shaders/common.glsl:7: syntax error, unexpected identifier");
  EXPECT_EQ(gpu::locateShaderError("WARNING: 0:3: unused\nERROR: 1:12: 'x' : undeclared identifier\n", files),
            "gpu/shaders/common.glsl:12: 'x' : undeclared identifier");
  EXPECT_EQ(gpu::locateShaderError("0:1(1): warning: nothing\n", files), "");
}

}  // namespace
}  // namespace mrr
