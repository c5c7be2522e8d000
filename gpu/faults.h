#pragma once
// Planted faults: deliberate shader bugs that the port's checks must catch ("the
// comparison is only worth something if it catches real shader bugs"). Setting
// MRR_GPU_FAULT=NAME patches one shader's source text before it compiles; everything else
// runs unchanged. Each fault is an exact text replacement, and a fault whose text is no
// longer in its shader is an error, so the catalogue cannot silently rot as shaders change.
#include <string>
#include <vector>

namespace mrr::gpu {

struct ShaderFault {
  std::string name;     // MRR_GPU_FAULT=name
  std::string file;     // the shader it patches (gpu/shaders/<file>)
  std::string find;     // exact text in that file
  std::string replace;  // what it becomes
  std::string what;     // the bug, in one line
  std::string stage;    // the first stage `mrr compare` flags (its row name's prefix), or "compile"
};

const std::vector<ShaderFault>& shaderFaults();

// `text` of gpu/shaders/<file>, with the fault named by MRR_GPU_FAULT applied when it
// patches this file. Throws MrrError for an unknown fault name, or when its text is missing.
std::string applyPlantedFault(const std::string& file, const std::string& text);

// The fault named by MRR_GPU_FAULT, or nullptr when none is set (validated on first use).
const ShaderFault* plantedFault();

}  // namespace mrr::gpu
