// tinygltf's implementation, compiled from Debian's own header (libtinygltf-dev) into
// mrr_common in every build, instead of linking libtinygltf.so: libdraco.so bundles and
// exports a tinygltf of its own (another version, another class layout), and with both
// shared libraries loaded the dynamic linker may bind TinyGLTF::Load* to draco's copy, which
// then writes past our objects. Symbols defined in the executable always come first. In the
// fuzz build this also puts the JSON and GLB parsing under coverage instrumentation.
// Images are never decoded (the loader drops them and installs a skipping image loader) and
// none are written: TINYGLTF_NO_STB_IMAGE and _WRITE come from CMake, for every translation
// unit alike.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
