#pragma once
#include <string>
#include <vector>

#include "common/scene.h"

namespace mrr {

struct LoadOptions {
  bool flipUp = false;  // rotate 180° about X after loading (files authored Y-down)
  bool quiet = false;   // no warnings on stderr (the fuzzer)
  bool skipBlend = false;  // --blend-materials skip: drop primitives whose material is alphaMode BLEND
};

// Loads a glTF 2.0 file (.gltf or .glb) through tinygltf into the world-space scene model:
// - the default scene's node hierarchy with TRS / matrix transforms, including mirrored
//   nodes (negative determinant: winding is flipped so fronts stay fronts);
// - every triangle primitive of every mesh (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN);
//   points and lines are skipped with a warning on stderr;
// - POSITION and NORMAL as FLOAT or quantized (KHR_mesh_quantization), sparse accessors, and
//   compressed geometry (EXT_meshopt_compression, KHR_draco_mesh_compression);
// - base colour: the factor, times the base-colour texture (PNG or JPEG, decoded only for the
//   materials drawn; its sampler's wrap modes, TEXCOORD_n and KHR_texture_transform: docs/spec.md
//   §1.2); no other image is read;
// - normals, computed where missing;
// - perspective cameras and the first KHR_lights_punctual directional light, when present.
// Skins and morph targets stay in the bind pose, BLEND and MASK materials are opaque: one
// warning line each. Any problem (missing file or buffer, not glTF, a required extension mrr
// cannot read, truncated or corrupt data, bad accessor, indices out of range, NaN/Inf,
// nothing to render) throws MrrError with one line naming the file.
Scene loadGltf(const std::string& path, const LoadOptions& options = {});

// The same from bytes in memory (`binary`: a .glb). `name` stands for the file in messages.
// External files are refused — only data: URIs and the GLB's own chunk resolve — so this is
// the whole path from untrusted bytes to a validated scene (tests/fuzz/ drives it).
Scene loadGltfFromMemory(const std::vector<unsigned char>& bytes, const std::string& name, bool binary,
                         const LoadOptions& options = {});

}  // namespace mrr
