#pragma once
// The shader contract: what each file of gpu/shaders/ is given and must give back,
// so a user's own GLSL (`--shaders DIR`) can replace it. One row per file: the host programs
// compiled from it, the defines that pick a variant, its inputs (textures, vertex attributes,
// varyings) with their formats, its uniforms with units, its outputs with their locations and
// formats, and what the oracle computes. docs/shader-contract.md is generated from this table
// and the stage list (`mrr shaders contract`); a test checks the table against the shaders'
// declarations (tests/gpu/shader_contract_test.cpp) and the document against the table.
#include <string>
#include <string_view>
#include <vector>

namespace mrr {

struct ShaderVariable {
  std::string_view name;
  std::string_view type;     // GLSL type, and for a texture its format ("sampler2D RGBA32F")
  std::string_view meaning;  // what it holds, in which unit
  int location = -1;         // outputs and vertex attributes: layout(location = N); -1: none
  std::string_view variant;  // the define that declares it ("" : every variant)
};

struct ShaderContract {
  std::string_view file;      // gpu/shaders/<file>
  std::string_view role;      // "fragment", "vertex", "include" or "test"
  std::string_view programs;  // the host's programs made with it (gpu/*.cpp), for errors
  std::string_view defines;   // the host's defines, "NAME: meaning; …" ("" : none)
  std::vector<ShaderVariable> inputs;    // textures (sampler2D), vertex attributes and varyings
  std::vector<ShaderVariable> uniforms;  // every other uniform
  std::vector<ShaderVariable> outputs;   // render targets (location ≥ 0) and varyings
  std::string_view oracle;    // what the oracle computes (cpu_ref/), one or two lines
};

// Every file of gpu/shaders/, sorted by name.
const std::vector<ShaderContract>& shaderContracts();
// The row of `file`, or nullptr.
const ShaderContract* shaderContract(std::string_view file);
// The first uniform or input named `name` in any row (for error messages), or nullptr.
const ShaderVariable* findShaderVariable(std::string_view name);

// docs/shader-contract.md: the stage list's parts and shaders, the conventions, then each
// file's contract. `mrr shaders contract` prints it; the README of `mrr shaders export` is a
// short form (shaderExportReadme).
std::string shaderContractMarkdown();
std::string shaderExportReadme();

}  // namespace mrr
