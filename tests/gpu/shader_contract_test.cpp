// The shader contract (common/shader_contract.h, docs/shader-contract.md) against the shaders
// themselves: every file of gpu/shaders/ has a row, and each row lists exactly the uniforms,
// textures, attributes, varyings and outputs (with locations) the file declares. No GL needed.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "common/shader_contract.h"
#include "common/stages.h"
#include "gpu/program.h"

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
