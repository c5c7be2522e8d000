// Tests of the glTF loader. Small files are generated at test time (.gltf with an embedded
// base64 buffer, or a .glb assembled by hand); the three shared scenes are loaded when present.
#include "scenes/gltf_loader.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "scenes/builtin.h"
#include "tests/common/gltf_builder.h"
#include "tests/test_support.h"

namespace mrr {
namespace {
using mrr::test::base64;
using namespace mrr::gltftest;

namespace fs = std::filesystem;
using nlohmann::json;

glm::vec3 geometricNormal(const Mesh& mesh, size_t triangle) {
  const glm::vec3& a = mesh.positions[mesh.indices[3 * triangle]];
  const glm::vec3& b = mesh.positions[mesh.indices[3 * triangle + 1]];
  const glm::vec3& c = mesh.positions[mesh.indices[3 * triangle + 2]];
  return glm::cross(b - a, c - a);
}

// Fraction of non-degenerate triangles whose winding agrees with their vertex normals.
double windingAgreement(const Scene& scene) {
  size_t agree = 0, total = 0;
  for (const Mesh& mesh : scene.meshes) {
    for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
      const glm::vec3 g = geometricNormal(mesh, t);
      if (!(glm::length(g) > 0.0f)) continue;
      const glm::vec3 n = mesh.normals[mesh.indices[3 * t]] + mesh.normals[mesh.indices[3 * t + 1]] +
                          mesh.normals[mesh.indices[3 * t + 2]];
      ++total;
      if (glm::dot(g, n) > 0.0f) ++agree;
    }
  }
  return total == 0 ? 0.0 : static_cast<double>(agree) / static_cast<double>(total);
}

std::vector<uint8_t> floatBytes(const std::vector<float>& values) {
  std::vector<uint8_t> bytes(values.size() * sizeof(float));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// ---- good input -----------------------------------------------------------------------------

TEST(GltfTest, SingleTriangleLoadsInWorldSpace) {
  const std::string path =
      singleTriangle({{"translation", {1.0, 2.0, 3.0}}}).writeGltf(test::scratchDir(), "tri.gltf");
  const Scene scene = loadGltf(path);
  EXPECT_EQ(scene.name, path);
  EXPECT_EQ(scene.credit, "");
  EXPECT_FALSE(scene.hasLight);
  EXPECT_TRUE(scene.cameras.empty());
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.name, "tri/0");
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
  ASSERT_EQ(mesh.positions.size(), 3u);
  expectNear(mesh.positions[0], {1, 2, 3});
  expectNear(mesh.positions[1], {2, 2, 3});
  expectNear(mesh.positions[2], {1, 3, 3});
  for (const glm::vec3& n : mesh.normals) expectNear(n, {0, 0, 1});
  EXPECT_EQ(mesh.baseColor, glm::vec3(1.0f));  // no material
  EXPECT_EQ(scene.triangleCount(), 1u);
}

TEST(GltfTest, NodeHierarchyComposesTransforms) {
  GltfBuilder b;
  b.addMesh("tri", {b.primitive(kTriangle, kUpNormals, {0, 1, 2})});
  const double h = std::sqrt(0.5);
  // root: T(10,0,0)·S(2) → child: T(0,1,0)·Rz(90°), mesh → grandchild: matrix T(0,0,5), mesh.
  b.addNode({{"translation", {10.0, 0.0, 0.0}}, {"scale", {2.0, 2.0, 2.0}}, {"children", {1}}});
  b.addNode({{"translation", {0.0, 1.0, 0.0}}, {"rotation", {0.0, 0.0, h, h}}, {"mesh", 0}, {"children", {2}}});
  b.addNode({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}, {"mesh", 0}});
  b.setRoots({0});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "hierarchy.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);  // the mesh is instanced twice
  const Mesh& child = scene.meshes[0];
  expectNear(child.positions[0], {10, 2, 0});
  expectNear(child.positions[1], {10, 4, 0});
  expectNear(child.positions[2], {8, 2, 0});
  for (const glm::vec3& n : child.normals) expectNear(n, {0, 0, 1});
  const Mesh& grandchild = scene.meshes[1];
  expectNear(grandchild.positions[0], {10, 2, 10});
  expectNear(grandchild.positions[1], {10, 4, 10});
  expectNear(grandchild.positions[2], {8, 2, 10});
  EXPECT_EQ(scene.triangleCount(), 2u);
}

TEST(GltfTest, NonUniformScaleTransformsNormalsByInverseTranspose) {
  // A 45° slope stretched 3× along x: its normal tilts towards +y, not towards +x.
  const std::vector<glm::vec3> slope = {{0, 0, 0}, {0, 0, 1}, {1, 1, 0}};
  const glm::vec3 n = glm::normalize(glm::cross(slope[1] - slope[0], slope[2] - slope[0]));
  GltfBuilder b;
  b.addMesh("slope", {b.primitive(slope, {n, n, n}, {0, 1, 2})});
  b.setRoots({b.addNode({{"mesh", 0}, {"scale", {3.0, 1.0, 1.0}}})});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "slope.gltf"));
  const Mesh& mesh = scene.meshes[0];
  const glm::vec3 expected = glm::normalize(geometricNormal(mesh, 0));
  for (const glm::vec3& normal : mesh.normals) expectNear(normal, expected);
}

TEST(GltfTest, MirroredNodeFlipsWinding) {
  const std::vector<glm::vec3> tilted = {{0, 0, 0}, {1, 0, 1}, {0, 1, 0}};
  const glm::vec3 n = glm::normalize(glm::vec3(-1, 0, 1));
  GltfBuilder b;
  b.addMesh("tilted", {b.primitive(tilted, {n, n, n}, {0, 1, 2})});
  const int plain = b.addNode({{"mesh", 0}});
  const int mirrored = b.addNode({{"mesh", 0}, {"scale", {-1.0, 1.0, 1.0}}});
  const int inverted = b.addNode({{"mesh", 0}, {"scale", {-1.0, -1.0, -1.0}}});
  b.setRoots({plain, mirrored, inverted});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "mirror.gltf"));
  ASSERT_EQ(scene.meshes.size(), 3u);
  EXPECT_EQ(scene.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(scene.meshes[1].indices, (std::vector<uint32_t>{0, 2, 1}));
  EXPECT_EQ(scene.meshes[2].indices, (std::vector<uint32_t>{0, 2, 1}));
  expectNear(scene.meshes[1].normals[0], glm::normalize(glm::vec3(1, 0, 1)));
  expectNear(scene.meshes[2].normals[0], glm::normalize(glm::vec3(1, 0, -1)));
  for (const Mesh& mesh : scene.meshes) {
    const glm::vec3 g = glm::normalize(geometricNormal(mesh, 0));
    for (const glm::vec3& normal : mesh.normals) expectNear(normal, g);
  }
}

TEST(GltfTest, TwoPrimitivesBecomeTwoMeshesWithTheirColours) {
  GltfBuilder b;
  const int red = b.addMaterial({0.8, 0.1, 0.1, 1.0});
  const int bright = b.addMaterial({0.2, 1.5, -0.5, 1.0});  // out of range: clamped
  const std::vector<glm::vec3> other = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  b.addMesh("pair", {b.primitive(kTriangle, kUpNormals, {0, 1, 2}, red), b.primitive(other, kUpNormals, {0, 1, 2}, bright)});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "pair.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].name, "pair/0");
  EXPECT_EQ(scene.meshes[1].name, "pair/1");
  expectNear(scene.meshes[0].baseColor, {0.8f, 0.1f, 0.1f});
  expectNear(scene.meshes[1].baseColor, {0.2f, 1.0f, 0.0f});
  expectNear(scene.meshes[1].positions[0], {0, 0, 1});
}

TEST(GltfTest, MissingNormalsAreComputed) {
  GltfBuilder b;
  // No NORMAL and no indices: normals from the CCW winding, indices generated.
  b.addMesh("bare", {b.primitive(kTriangle, {}, {})});
  b.setRoots({b.addNode({{"mesh", 0}, {"rotation", {std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)}}})});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "bare.gltf"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
  ASSERT_EQ(mesh.normals.size(), 3u);
  for (const glm::vec3& n : mesh.normals) {
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    expectNear(n, {0, -1, 0});  // +Z rotated 90° about X
  }
}

TEST(GltfTest, StripsAndFansBecomeTriangleLists) {
  GltfBuilder b;
  const std::vector<glm::vec3> strip = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}};
  const std::vector<glm::vec3> fan = {{0, 0, 2}, {1, 0, 2}, {1, 1, 2}, {0, 1, 2}};
  b.addMesh("shapes", {b.primitive(strip, {}, {}, -1, 5), b.primitive(fan, {}, {0, 1, 2, 3}, -1, 6)});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "shapes.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].indices.size(), 9u);
  EXPECT_EQ(scene.meshes[1].indices.size(), 6u);
  for (const Mesh& mesh : scene.meshes) {
    for (size_t t = 0; t < mesh.indices.size() / 3; ++t) expectNear(glm::normalize(geometricNormal(mesh, t)), {0, 0, 1});
    for (const glm::vec3& n : mesh.normals) expectNear(n, {0, 0, 1});
  }
}

TEST(GltfTest, InterleavedAttributesAndSmallIndexTypes) {
  GltfBuilder b;
  // Position and normal interleaved in one bufferView with a 24-byte stride.
  std::vector<float> interleaved;
  for (size_t v = 0; v < 3; ++v)
    interleaved.insert(interleaved.end(), {kTriangle[v].x, kTriangle[v].y, kTriangle[v].z, 0.0f, 0.0f, 1.0f});
  const std::vector<uint8_t> bytes = floatBytes(interleaved);
  const int view = b.addView(bytes.data(), bytes.size(), 24);
  const int position = b.addAccessor(view, kFloat, "VEC3", 3);
  const int normal = b.addAccessor(view, kFloat, "VEC3", 3, 12);
  const int bytesIdx = b.addIndices({0, 1, 2}, kUnsignedByte);
  const int shortsIdx = b.addIndices({2, 1, 0}, kUnsignedShort);
  b.addMesh("packed", {json{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"indices", bytesIdx}},
                       json{{"attributes", {{"POSITION", position}}}, {"indices", shortsIdx}}});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "packed.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].positions, kTriangle);
  for (const glm::vec3& n : scene.meshes[0].normals) expectNear(n, {0, 0, 1});
  EXPECT_EQ(scene.meshes[1].indices, (std::vector<uint32_t>{2, 1, 0}));
  for (const glm::vec3& n : scene.meshes[1].normals) expectNear(n, {0, 0, -1});
}

TEST(GltfTest, LinesPrimitiveIsSkippedWithAWarning) {
  GltfBuilder b;
  const std::vector<glm::vec3> line = {{0, 0, 0}, {5, 5, 5}};
  b.addMesh("mixed", {b.primitive(line, {}, {}, -1, 1), b.primitive(kTriangle, kUpNormals, {0, 1, 2})});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const std::string path = b.writeGltf(test::scratchDir(), "mixed.gltf");
  testing::internal::CaptureStderr();
  const Scene scene = loadGltf(path);
  const std::string warnings = testing::internal::GetCapturedStderr();
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].name, "mixed/1");
  EXPECT_NE(warnings.find("mrr: warning: " + path + ": mesh 'mixed' primitive 0 is LINES, skipped"),
            std::string::npos)
      << warnings;
}

TEST(GltfTest, PerspectiveCameraAndDirectionalLight) {
  GltfBuilder b = singleTriangle();
  const double h = std::sqrt(0.5);
  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}, {"aspectRatio", 1.5}}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"intensity", 5.0}},
      {{"type", "directional"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 2.0}},
      {{"type", "directional"}, {"intensity", 1.0}}};
  const int camera = b.addNode({{"camera", 0}, {"translation", {0.0, 1.0, 5.0}}});
  // The camera on a child of a rotated parent: looks along world −X, up stays +Y.
  const int turned = b.addNode({{"rotation", {0.0, h, 0.0, h}}, {"children", {b.addNode({{"camera", 0}})}}});
  const int point = b.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // Rotated −90° about X: the light's −Z axis points straight down.
  const int sun = b.addNode({{"rotation", {-h, 0.0, 0.0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const int later = b.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  b.setRoots({0, camera, turned, point, sun, later});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "lit.gltf"));

  ASSERT_EQ(scene.cameras.size(), 2u);
  expectNear(scene.cameras[0].eye, {0, 1, 5});
  expectNear(scene.cameras[0].target, {0, 1, 4});
  expectNear(scene.cameras[0].up, {0, 1, 0});
  EXPECT_FLOAT_EQ(scene.cameras[0].yfov, 0.7f);
  expectNear(scene.cameras[1].eye, {0, 0, 0});
  expectNear(scene.cameras[1].target, {-1, 0, 0});
  expectNear(scene.cameras[1].up, {0, 1, 0});

  ASSERT_TRUE(scene.hasLight);
  expectNear(scene.light.direction, {0, -1, 0});
  expectNear(scene.light.color, {2.0f, 1.0f, 0.5f});
}

TEST(GltfTest, GlbLoadsTheSameAsGltf) {
  GltfBuilder b;
  const int material = b.addMaterial({0.3, 0.6, 0.9, 1.0});
  b.addMesh("tri", {b.primitive(kTriangle, kUpNormals, {0, 1, 2}, material)});
  b.addMesh("bare", {b.primitive({{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0, 1, 1}}, {}, {0, 1, 2, 2, 1, 3})});
  b.setRoots({b.addNode({{"mesh", 0}, {"translation", {1.0, 2.0, 3.0}}}),
              b.addNode({{"mesh", 1}, {"scale", {-2.0, 1.0, 1.0}}})});
  const std::string dir = test::scratchDir();
  const Scene text = loadGltf(b.writeGltf(dir, "same.gltf"));
  const Scene binary = loadGltf(b.writeGlb(dir, "same.glb"));
  ASSERT_EQ(text.meshes.size(), binary.meshes.size());
  for (size_t m = 0; m < text.meshes.size(); ++m) {
    EXPECT_EQ(text.meshes[m].name, binary.meshes[m].name);
    EXPECT_EQ(text.meshes[m].positions, binary.meshes[m].positions);
    EXPECT_EQ(text.meshes[m].normals, binary.meshes[m].normals);
    EXPECT_EQ(text.meshes[m].indices, binary.meshes[m].indices);
    EXPECT_EQ(text.meshes[m].baseColor, binary.meshes[m].baseColor);
  }
  EXPECT_EQ(text.triangleCount(), 3u);
}

TEST(GltfTest, SceneWithoutScenesUsesRootNodes) {
  GltfBuilder b;
  b.addMesh("tri", {b.primitive(kTriangle, kUpNormals, {0, 1, 2})});
  b.addNode({{"mesh", 0}, {"children", {1}}});
  b.addNode({{"mesh", 0}, {"translation", {0.0, 0.0, 1.0}}});
  const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "noscenes.gltf"));
  EXPECT_EQ(scene.meshes.size(), 2u);  // node 1 only once, as node 0's child
}

TEST(GltfTest, FlipUpOptionRotatesTheLoadedScene) {
  const std::string path = singleTriangle({{"translation", {0.0, 2.0, 3.0}}}).writeGltf(test::scratchDir(), "flip.gltf");
  const Scene scene = loadGltf(path, LoadOptions{.flipUp = true});
  const Mesh& mesh = scene.meshes[0];
  expectNear(mesh.positions[0], {0, -2, -3});
  expectNear(mesh.positions[1], {1, -2, -3});
  expectNear(mesh.positions[2], {0, -3, -3});
  for (const glm::vec3& n : mesh.normals) expectNear(n, {0, 0, -1});
  EXPECT_GT(glm::dot(geometricNormal(mesh, 0), mesh.normals[0]), 0.0f);
}

TEST(GltfTest, CreditComesFromAttributionFile) {
  const std::string dir = test::scratchDir();
  const std::string path = singleTriangle().writeGltf(dir, "credited.gltf");
  writeFile((fs::path(dir) / "ATTRIBUTION.txt").string(),
            "Scene: test\nLicences / attribution:\n  Suggested credit: \"Test Box by Someone,\n"
            "  converted by Other (MIT).\"\nAttribution: \"not this one\"\n");
  EXPECT_EQ(loadGltf(path).credit, "Test Box by Someone, converted by Other (MIT).");
  writeFile((fs::path(dir) / "ATTRIBUTION.txt").string(),
            "Licence: CC-BY\nRequired credit: Based on \"Flat\" (https://x)\nby A. Person.\n\nMore text\n");
  EXPECT_EQ(loadGltf(path).credit, "Based on \"Flat\" (https://x) by A. Person.");
  writeFile((fs::path(dir) / "ATTRIBUTION.txt").string(), "Attribution: \"Thing by Me, CC0.\"\nNext line\n");
  EXPECT_EQ(loadGltf(path).credit, "Thing by Me, CC0.");
}

// ---- bad input ------------------------------------------------------------------------------

TEST(GltfTest, MissingFileIsAnError) {
  expectLoadError((fs::path(test::scratchDir()) / "nope.gltf").string(), "no such file");
}

TEST(GltfTest, DirectoryIsAnError) {
  const std::string dir = (fs::path(test::scratchDir()) / "folder.gltf").string();
  fs::create_directories(dir);
  expectLoadError(dir, "directory");
}

TEST(GltfTest, UnsupportedExtensionIsAnError) {
  const std::string path = singleTriangle().writeGltf(test::scratchDir(), "scene.obj");
  expectLoadError(path, "unsupported extension");
}

TEST(GltfTest, EmptyFileIsAnError) {
  const std::string dir = test::scratchDir();
  for (const char* name : {"empty.gltf", "empty.glb"}) {
    const std::string path = (fs::path(dir) / name).string();
    writeFile(path, "");
    expectLoadError(path, "empty");
  }
}

TEST(GltfTest, WrongMagicGlbIsAnError) {
  const std::string dir = test::scratchDir();
  std::string bytes = singleTriangle().glbBytes();
  bytes.replace(0, 4, "gLTF");
  writeFile((fs::path(dir) / "magic.glb").string(), bytes);
  expectLoadError((fs::path(dir) / "magic.glb").string());
  // A text glTF given the binary extension is the same mistake.
  const std::string text = singleTriangle().writeGltf(dir, "text.glb");
  expectLoadError(text);
}

TEST(GltfTest, TruncatedGlbIsAnError) {
  const std::string dir = test::scratchDir();
  const std::string bytes = singleTriangle().glbBytes();
  for (size_t keep : {size_t{8}, size_t{20}, bytes.size() / 2, bytes.size() - 4}) {
    const std::string path = (fs::path(dir) / ("cut" + std::to_string(keep) + ".glb")).string();
    writeFile(path, bytes.substr(0, keep));
    expectLoadError(path);
  }
}

TEST(GltfTest, JsonThatIsNotGltfIsAnError) {
  const std::string dir = test::scratchDir();
  int n = 0;
  for (const char* text : {"{\"hello\": \"world\"}", "[1, 2, 3]", "not json {", "{\"asset\": 5}"}) {
    const std::string path = (fs::path(dir) / ("junk" + std::to_string(n++) + ".gltf")).string();
    writeFile(path, text);
    expectLoadError(path);
  }
}

TEST(GltfTest, BadBufferUriIsAnError) {
  GltfBuilder b = singleTriangle();
  json doc = b.finished(false);
  doc["buffers"][0]["uri"] = "missing.bin";
  const std::string path = (fs::path(test::scratchDir()) / "baduri.gltf").string();
  writeFile(path, doc.dump());
  expectLoadError(path);
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@@@";
  writeFile(path, doc.dump());
  expectLoadError(path);
}

TEST(GltfTest, BufferShorterThanItsAccessorIsAnError) {
  GltfBuilder b = singleTriangle();
  b.doc["accessors"][0]["count"] = 30;  // POSITION: 3 vertices stored, 30 claimed
  expectLoadError(b.writeGltf(test::scratchDir(), "short.gltf"));
  GltfBuilder c = singleTriangle();
  c.doc["bufferViews"][0]["byteLength"] = 1000;  // the view runs past the buffer
  expectLoadError(c.writeGltf(test::scratchDir(), "shortview.gltf"));
}

TEST(GltfTest, OutOfRangeIndexIsAnError) {
  GltfBuilder b;
  b.addMesh("tri", {b.primitive(kTriangle, kUpNormals, {0, 1, 7})});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const std::string path = b.writeGltf(test::scratchDir(), "badindex.gltf");
  expectLoadError(path, "7");
  expectLoadError(path, "out of range");
}

TEST(GltfTest, WrongComponentTypeForPositionIsAnError) {
  GltfBuilder b;
  // Integer positions are KHR_mesh_quantization's BYTE and SHORT; 32-bit ones are nothing.
  const std::vector<uint32_t> ints = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int position = b.addAccessor(b.addView(ints.data(), ints.size() * 4), kUnsignedInt, "VEC3", 3);
  b.addMesh("ints", {json{{"attributes", {{"POSITION", position}}}}});
  b.setRoots({b.addNode({{"mesh", 0}})});
  expectLoadError(b.writeGltf(test::scratchDir(), "shorts.gltf"), "POSITION");
  GltfBuilder c = singleTriangle();
  c.doc["accessors"][0]["type"] = "VEC2";
  expectLoadError(c.writeGltf(test::scratchDir(), "vec2.gltf"), "POSITION");
  GltfBuilder d = singleTriangle();
  d.doc["accessors"][2]["componentType"] = kFloat;  // float indices
  expectLoadError(d.writeGltf(test::scratchDir(), "floatindices.gltf"), "indices");
}

TEST(GltfTest, NanPositionIsAnError) {
  GltfBuilder b;
  std::vector<glm::vec3> positions = kTriangle;
  positions[1].y = std::numeric_limits<float>::quiet_NaN();
  b.addMesh("nan", {b.primitive(positions, kUpNormals, {0, 1, 2})});
  b.setRoots({b.addNode({{"mesh", 0}})});
  expectLoadError(b.writeGltf(test::scratchDir(), "nan.gltf"), "not finite");
}

TEST(GltfTest, NonFiniteOrZeroNormalsAreRecomputed) {
  // Real exporters write NaN normals for degenerate faces (the arcade has some): repaired
  // from the geometry with a warning rather than rejected.
  GltfBuilder b;
  std::vector<glm::vec3> normals = kUpNormals;
  normals[1].x = std::numeric_limits<float>::quiet_NaN();
  normals[2] = glm::vec3(0.0f);
  b.addMesh("broken", {b.primitive(kTriangle, normals, {0, 1, 2})});
  b.setRoots({b.addNode({{"mesh", 0}})});
  const std::string path = b.writeGltf(test::scratchDir(), "nannormal.gltf");
  testing::internal::CaptureStderr();
  const Scene scene = loadGltf(path);
  const std::string warnings = testing::internal::GetCapturedStderr();
  for (const glm::vec3& n : scene.meshes[0].normals) expectNear(n, {0, 0, 1});
  EXPECT_NE(warnings.find("2 zero or non-finite normals"), std::string::npos) << warnings;
}

TEST(GltfTest, EmptySceneIsAnError) {
  const std::string dir = test::scratchDir();
  GltfBuilder none;
  expectLoadError(none.writeGltf(dir, "nothing.gltf"), "no meshes");
  GltfBuilder nodesOnly;
  nodesOnly.setRoots({nodesOnly.addNode({{"name", "empty"}})});
  expectLoadError(nodesOnly.writeGltf(dir, "nodes.gltf"), "no meshes");
  GltfBuilder glb;
  expectLoadError(glb.writeGlb(dir, "nothing.glb"), "no meshes");
}

TEST(GltfTest, OnlyDegenerateTrianglesIsAnError) {
  GltfBuilder b;
  b.addMesh("flat", {b.primitive({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {}, {0, 1, 2})});
  b.setRoots({b.addNode({{"mesh", 0}})});
  expectLoadError(b.writeGltf(test::scratchDir(), "flat.gltf"), "degenerate");
}

TEST(GltfTest, MalformedStructureIsAnError) {
  const std::string dir = test::scratchDir();
  GltfBuilder cycle = singleTriangle();
  cycle.addNode({{"children", {2}}});
  cycle.addNode({{"children", {1}}});
  cycle.setRoots({0, 1});
  expectLoadError(cycle.writeGltf(dir, "cycle.gltf"));
  GltfBuilder badMesh = singleTriangle({{"children", {5}}});
  expectLoadError(badMesh.writeGltf(dir, "badchild.gltf"));
  GltfBuilder badMaterial = singleTriangle();
  badMaterial.doc["meshes"][0]["primitives"][0]["material"] = 4;
  expectLoadError(badMaterial.writeGltf(dir, "badmaterial.gltf"));
  GltfBuilder sparse = singleTriangle();
  // Four substitutions in a three-element accessor (sparse data itself: gltf_compressed_test).
  sparse.doc["accessors"][0]["sparse"] = {{"count", 4},
                                          {"indices", {{"bufferView", 2}, {"componentType", kUnsignedInt}}},
                                          {"values", {{"bufferView", 0}}}};
  expectLoadError(sparse.writeGltf(dir, "sparse.gltf"));
}

// ---- in memory, and a write-then-load round trip ----------------------------------------------

TEST(GltfMemoryTest, EveryBuiltinSceneSurvivesAWriteThenLoadRoundTrip) {
  for (const std::string& name : builtinSceneNames())
    for (const bool binary : {false, true}) {
      SCOPED_TRACE(name + (binary ? " .glb" : " .gltf"));
      const Scene original = makeBuiltinScene(name);
      const Scene loaded = loadGltfFromMemory(test::sceneToGltf(original, binary), name, binary, {.quiet = true});
      ASSERT_EQ(loaded.meshes.size(), original.meshes.size());
      for (size_t m = 0; m < original.meshes.size(); ++m) {
        const Mesh& a = original.meshes[m];
        const Mesh& b = loaded.meshes[m];
        ASSERT_EQ(a.indices, b.indices);
        ASSERT_EQ(a.positions.size(), b.positions.size());
        for (size_t i = 0; i < a.positions.size(); ++i) {
          EXPECT_EQ(a.positions[i], b.positions[i]);  // float32 in, float32 out, identity transform
          EXPECT_LT(glm::length(a.normals[i] - b.normals[i]), 1e-6f);
        }
        EXPECT_LT(glm::length(a.baseColor - b.baseColor), 1e-6f);
      }
      ASSERT_TRUE(loaded.hasLight);
      EXPECT_LT(glm::length(loaded.light.direction - glm::normalize(original.light.direction)), 1e-5f);
      EXPECT_LT(glm::length(loaded.light.color - original.light.color), 1e-5f);
      ASSERT_EQ(loaded.cameras.size(), original.cameras.size());
      for (size_t c = 0; c < original.cameras.size(); ++c) {
        const Camera& a = original.cameras[c];
        const Camera& b = loaded.cameras[c];
        EXPECT_LT(glm::length(a.eye - b.eye), 1e-4f);
        EXPECT_LT(glm::length(glm::normalize(a.target - a.eye) - glm::normalize(b.target - b.eye)), 1e-5f);
        EXPECT_FLOAT_EQ(a.yfov, b.yfov);
      }
    }
}

TEST(GltfMemoryTest, ExternalFilesAreRefusedFromMemory) {
  // From memory there is no folder: a buffer URI naming a file must fail, never read it —
  // here a file that exists, so only the refusal can make this fail.
  GltfBuilder b = singleTriangle();
  json doc = b.finished(false);
  const std::string dir = test::scratchDir();
  const std::string bin = (fs::path(dir) / "buffer.bin").string();
  writeFile(bin, std::string(4096, '\0'));
  doc["buffers"][0]["uri"] = bin;
  const std::string text = doc.dump();
  try {
    loadGltfFromMemory({text.begin(), text.end()}, "memory.gltf", false, {.quiet = true});
    FAIL() << "an external buffer was read from memory";
  } catch (const MrrError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("memory.gltf: "), std::string::npos) << message;
    EXPECT_NE(message.find("not allowed"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// ---- the shared scenes ----------------------------------------------------------------------

bool isFiniteBounds(const Bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return false;
  return true;
}

TEST(GltfSharedSceneTest, CornellBox) {
  const std::string relative = "cornell-box/CornellBox-Original.gltf";
  if (!test::haveSharedScene(relative)) GTEST_SKIP() << "shared scene " << relative << " is absent";
  const Scene scene = loadGltf(test::sharedScene(relative));
  EXPECT_EQ(scene.triangleCount(), 32u);
  EXPECT_EQ(scene.meshes.size(), 8u);
  const Bounds b = scene.bounds();
  ASSERT_TRUE(isFiniteBounds(b));
  EXPECT_NEAR(b.lo.y, 0.0f, 0.05f);
  EXPECT_NEAR(b.hi.y, 1.99f, 0.05f);
  EXPECT_NEAR(b.lo.x, -1.02f, 0.05f);
  EXPECT_NEAR(b.hi.x, 1.0f, 0.05f);
  EXPECT_NE(scene.credit.find("Cornell Box by"), std::string::npos) << scene.credit;
  EXPECT_FALSE(scene.hasLight);
  EXPECT_TRUE(scene.cameras.empty());
  EXPECT_GT(windingAgreement(scene), 0.99);
}

TEST(GltfSharedSceneTest, SaschaArcadeFlippedUp) {
  const std::string relative = "sascha-arcade/subpass_scene_opaque.gltf";
  if (!test::haveSharedScene(relative)) GTEST_SKIP() << "shared scene " << relative << " is absent";
  const Scene scene = loadGltf(test::sharedScene(relative), LoadOptions{.flipUp = true});
  EXPECT_EQ(scene.triangleCount(), 23388u);
  const Bounds b = scene.bounds();
  ASSERT_TRUE(isFiniteBounds(b));
  EXPECT_NEAR(b.lo.y, -0.49f, 0.05f);
  EXPECT_NEAR(b.hi.y, 9.71f, 0.05f);
  EXPECT_NEAR(b.hi.x - b.lo.x, 22.0f, 0.5f);
  EXPECT_NE(scene.credit.find("Sascha Willems"), std::string::npos) << scene.credit;
  // Most nodes are mirrored: the winding must still agree with the normals.
  EXPECT_GT(windingAgreement(scene), 0.99);
}

TEST(GltfSharedSceneTest, DreamApartment) {
  const std::string relative = "dream-apartment/dream-apartment.glb";
  if (!test::haveSharedScene(relative)) GTEST_SKIP() << "shared scene " << relative << " is absent";
  const Scene scene = loadGltf(test::sharedScene(relative));
  EXPECT_EQ(scene.triangleCount(), 177934u);
  EXPECT_EQ(scene.meshes.size(), 67u);
  const Bounds b = scene.bounds();
  ASSERT_TRUE(isFiniteBounds(b));
  expectNear(b.lo, {0.44f, -0.10f, -11.43f}, 0.05f);
  expectNear(b.hi, {12.81f, 2.68f, -0.13f}, 0.05f);
  EXPECT_NE(scene.credit.find("Maxim Lukyanov"), std::string::npos) << scene.credit;
  EXPECT_GT(windingAgreement(scene), 0.95);
}

}  // namespace
}  // namespace mrr
