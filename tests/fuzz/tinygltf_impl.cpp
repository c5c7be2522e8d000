// tinygltf's implementation, compiled from Debian's own header (libtinygltf-dev) in the fuzz
// build only, so coverage instrumentation reaches the JSON and GLB parsing as well. Images
// are never decoded (the loader installs a skipping image loader) and nothing is written.
// (TINYGLTF_NO_STB_IMAGE and _WRITE come from CMake, for every translation unit alike.)
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
