// Alpha MASK materials read as cutouts (docs/spec.md §1.1): files made here, with
// their PNGs written by OpenImageIO beside them or inside the GLB.
#include <OpenImageIO/imageio.h>

#include "tests/common/gltf_builder.h"

namespace mrr::gltftest {
namespace {

// A 4×2 RGBA image whose alpha row by row is 0 64 128 255 / 255 127 128 0.
const uint8_t kAlpha[8] = {0, 64, 128, 255, 255, 127, 128, 0};

std::string writePng(const std::string& path) {
  std::vector<uint8_t> rgba;
  for (uint8_t a : kAlpha) rgba.insert(rgba.end(), {200, 100, 50, a});
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out);
  const OIIO::ImageSpec spec(4, 2, 4, OIIO::TypeDesc::UINT8);
  EXPECT_TRUE(out->open(path, spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgba.data()));
  out->close();
  return path;
}

// A unit quad with TEXCOORD_0 (optionally UNSIGNED_SHORT normalized, KHR_mesh_quantization) and
// material 0; `image` is added by the caller.
GltfBuilder cutoutQuad(const json& material, bool quantizedTexcoords = false) {
  GltfBuilder b;
  const std::vector<glm::vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  json p = b.primitive(corners, std::vector<glm::vec3>(4, {0, 0, 1}), {0, 1, 2, 0, 2, 3}, 0);
  if (quantizedTexcoords) {
    const uint16_t st[8] = {0, 65535, 65535, 65535, 65535, 0, 0, 0};
    const int view = b.addView(st, sizeof st);
    const int accessor = b.addAccessor(view, kUnsignedShort, "VEC2", 4);
    b.doc["accessors"][static_cast<size_t>(accessor)]["normalized"] = true;
    p["attributes"]["TEXCOORD_0"] = accessor;
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  } else {
    const float st[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    p["attributes"]["TEXCOORD_0"] = b.addAccessor(b.addView(st, sizeof st), kFloat, "VEC2", 4);
  }
  b.addMesh("quad", {p});
  b.push("materials", material);
  b.push("textures", {{"source", 0}, {"sampler", 0}});
  b.push("samplers", {{"wrapS", 33071}, {"wrapT", 33648}});
  b.setRoots({b.addNode({{"mesh", 0}})});
  return b;
}

json maskMaterial(double factorAlpha = 1.0, double cutoff = 0.5) {
  return {{"alphaMode", "MASK"},
          {"alphaCutoff", cutoff},
          {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, factorAlpha}}, {"baseColorTexture", {{"index", 0}}}}}};
}

std::vector<int> bits(const Cutout& c) { return {c.opaque.begin(), c.opaque.end()}; }

TEST(GltfCutout, MaskReadsTheBaseColourAlphaAgainstTheCutoff) {
  const std::string dir = test::scratchDir();
  writePng(dir + "/cut.png");
  GltfBuilder b = cutoutQuad(maskMaterial());
  b.push("images", {{"uri", "cut.png"}});
  const Scene s = loadGltf(b.writeGltf(dir, "mask.gltf"));
  ASSERT_EQ(s.cutouts.size(), 1u);
  const Cutout& c = s.cutouts[0];
  EXPECT_EQ(c.width, 4);
  EXPECT_EQ(c.height, 2);
  // 128/255 = 0.502 is opaque at 0.5, 127/255 = 0.498 is not (glTF: alpha >= cutoff is opaque)
  EXPECT_EQ(bits(c), (std::vector<int>{0, 0, 1, 1, 1, 0, 1, 0}));
  EXPECT_EQ(c.wrapS, Wrap::Clamp);
  EXPECT_EQ(c.wrapT, Wrap::Mirror);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].cutout, 0);
  ASSERT_EQ(s.meshes[0].texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].texcoords[2], glm::vec2(1, 0));
}

TEST(GltfCutout, TheFactorsAlphaMultipliesAndTheCutoffIsTheMaterials) {
  const std::string dir = test::scratchDir();
  writePng(dir + "/cut.png");
  GltfBuilder half = cutoutQuad(maskMaterial(0.5));  // only alpha 255 reaches 0.5
  half.push("images", {{"uri", "cut.png"}});
  EXPECT_EQ(bits(loadGltf(half.writeGltf(dir, "half.gltf")).cutouts.at(0)), (std::vector<int>{0, 0, 0, 1, 1, 0, 0, 0}));
  GltfBuilder low = cutoutQuad(maskMaterial(1.0, 0.2));  // 64/255 = 0.25 passes 0.2
  low.push("images", {{"uri", "cut.png"}});
  EXPECT_EQ(bits(loadGltf(low.writeGltf(dir, "low.gltf")).cutouts.at(0)), (std::vector<int>{0, 1, 1, 1, 1, 1, 1, 0}));
}

TEST(GltfCutout, AnImageInsideTheGlbAndQuantizedTexcoordsRead) {
  const std::string dir = test::scratchDir();
  const std::string png = test::readFile(writePng(dir + "/cut.png"));
  GltfBuilder b = cutoutQuad(maskMaterial(), /*quantizedTexcoords=*/true);
  const int view = b.addView(png.data(), png.size());
  b.push("images", {{"bufferView", view}, {"mimeType", "image/png"}});
  const Scene s = loadGltf(b.writeGlb(dir, "mask.glb"));
  ASSERT_EQ(s.cutouts.size(), 1u);
  EXPECT_EQ(bits(s.cutouts[0]), (std::vector<int>{0, 0, 1, 1, 1, 0, 1, 0}));
  EXPECT_EQ(s.meshes.at(0).texcoords.at(0), glm::vec2(0, 1));  // 65535 normalized is exactly 1
}

// glTF 2.0 itself allows normalized UNSIGNED_BYTE and UNSIGNED_SHORT texture coordinates: they
// need no KHR_mesh_quantization. Not normalized, they do, and the loader says so.
TEST(GltfCutout, NormalizedUnsignedTexcoordsNeedNoExtensionOthersDo) {
  const std::string dir = test::scratchDir();
  writePng(dir + "/cut.png");
  GltfBuilder b = cutoutQuad(maskMaterial(), /*quantizedTexcoords=*/true);
  b.doc.erase("extensionsUsed");
  b.push("images", {{"uri", "cut.png"}});
  const Scene s = loadGltf(b.writeGltf(dir, "core.gltf"));
  EXPECT_EQ(s.meshes.at(0).texcoords.at(0), glm::vec2(0, 1));
  const int accessor = b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"];
  b.doc["accessors"][static_cast<size_t>(accessor)]["normalized"] = false;
  expectLoadError(b.writeGltf(dir, "unnormalized.gltf"),
                  "TEXCOORD_0 accessor " + std::to_string(accessor) +
                      " has componentType UNSIGNED_SHORT, which needs KHR_mesh_quantization");
}

TEST(GltfCutout, AMaskWithoutTextureIsAllOrNothing) {
  const std::string dir = test::scratchDir();
  GltfBuilder b;
  b.push("materials", {{"alphaMode", "MASK"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.3}}}}});
  b.push("materials", {{"alphaMode", "MASK"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.7}}}}});
  b.addMesh("two", {b.primitive(kTriangle, kUpNormals, {0, 1, 2}, 0), b.primitive(kTriangle, kUpNormals, {0, 1, 2}, 1)});
  b.setRoots({b.addNode({{"mesh", 0}})});
  testing::internal::CaptureStderr();
  const Scene s = loadGltf(b.writeGltf(dir, "factor.gltf"));
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(s.meshes.size(), 1u);  // alpha 0.3 < 0.5: left out; 0.7: drawn, no cutout needed
  EXPECT_EQ(s.meshes[0].cutout, -1);
  EXPECT_TRUE(s.cutouts.empty());
  EXPECT_NE(err.find("1 primitives are left out"), std::string::npos) << err;
}

TEST(GltfCutout, AMissingImageIsDrawnOpaqueAndSaidOnce) {
  const std::string dir = test::scratchDir();
  GltfBuilder b = cutoutQuad(maskMaterial());
  b.push("images", {{"uri", "absent.png"}});
  testing::internal::CaptureStderr();
  const Scene s = loadGltf(b.writeGltf(dir, "absent.gltf"));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(s.cutouts.empty());
  EXPECT_EQ(s.meshes.at(0).cutout, -1);
  EXPECT_NE(err.find("drawn without its cutout"), std::string::npos) << err;
}

TEST(GltfCutout, AnOpaqueMaterialsImageIsItsAlbedoNotACutout) {
  // An opaque material's base-colour image is read for its colour (docs/spec.md §1.2), never as
  // a cutout: the mesh gets a texture and its texture coordinates, and no cutout.
  const std::string dir = test::scratchDir();
  writePng(dir + "/cut.png");
  GltfBuilder b = cutoutQuad({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.push("images", {{"uri", "cut.png"}});
  testing::internal::CaptureStderr();
  const Scene s = loadGltf(b.writeGltf(dir, "opaque.gltf"));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(s.cutouts.empty());
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.meshes.at(0).texture, 0);
  EXPECT_EQ(s.meshes.at(0).texcoords.size(), 4u);
  // the colour as stored, not premultiplied by the alpha (the first texel's alpha is 0, the
  // fourth's 255)
  const std::vector<uint8_t>& rgba = s.textures[0].rgba;
  EXPECT_EQ(std::vector<int>(rgba.begin(), rgba.begin() + 4), (std::vector<int>{200, 100, 50, 255}));
  EXPECT_EQ(std::vector<int>(rgba.begin() + 12, rgba.begin() + 16), (std::vector<int>{200, 100, 50, 255}));
  EXPECT_EQ(err, "");
}

TEST(GltfCutout, AMaskAlsoColoursWithTheSameImage) {
  const std::string dir = test::scratchDir();
  writePng(dir + "/cut.png");
  GltfBuilder b = cutoutQuad(maskMaterial());
  b.push("images", {{"uri", "cut.png"}});
  const Scene s = loadGltf(b.writeGltf(dir, "both.gltf"));
  ASSERT_EQ(s.cutouts.size(), 1u);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.meshes.at(0).cutout, 0);
  EXPECT_EQ(s.meshes.at(0).texture, 0);
  EXPECT_EQ(bits(s.cutouts[0]), (std::vector<int>{0, 0, 1, 1, 1, 0, 1, 0}));  // the same bits as the cutout alone
}

TEST(GltfCutout, ACorruptImageIsSaidAndDrawnOpaque) {
  const std::string dir = test::scratchDir();
  writeFile(dir + "/bad.png", "\x89PNG\r\n\x1a\n this is not a png");
  GltfBuilder b = cutoutQuad(maskMaterial());
  b.push("images", {{"uri", "bad.png"}});
  testing::internal::CaptureStderr();
  const Scene s = loadGltf(b.writeGltf(dir, "bad.gltf"));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(s.cutouts.empty());
  EXPECT_NE(err.find("drawn without its cutout"), std::string::npos) << err;
}

}  // namespace
}  // namespace mrr::gltftest
