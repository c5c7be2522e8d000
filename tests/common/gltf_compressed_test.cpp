// The loader on compressed and quantized glTF: EXT_meshopt_compression, KHR_draco_mesh_compression,
// KHR_mesh_quantization and sparse accessors, each checked against the same mesh stored plainly.
// Every file is encoded here, at test time, with meshoptimizer's and Draco's own encoders; no
// third-party file is read. Also: required extensions mrr cannot read, absent .bin files,
// textures that are never read, and the one-line warnings for skins, morphs and alpha modes.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "tests/common/gltf_builder.h"

namespace mrr {
namespace {
using namespace mrr::gltftest;

constexpr int kByte = 5120;
constexpr int kShort = 5122;

// A 5×4 height field: 20 vertices, 24 triangles, curved so that normals vary.
struct Grid {
  std::vector<glm::vec3> positions, normals;
  std::vector<uint32_t> indices;
};

Grid makeGrid() {
  Grid g;
  constexpr int nx = 5, ny = 4;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const float u = static_cast<float>(x) * 0.5f, v = static_cast<float>(y) * 0.5f;
      g.positions.push_back({u, v, 0.3f * std::sin(u) * std::cos(v)});
      g.normals.push_back(glm::normalize(glm::vec3(-0.3f * std::cos(u) * std::cos(v), 0.3f * std::sin(u) * std::sin(v), 1.0f)));
    }
  for (int y = 0; y + 1 < ny; ++y)
    for (int x = 0; x + 1 < nx; ++x) {
      const auto i = static_cast<uint32_t>(y * nx + x);
      g.indices.insert(g.indices.end(), {i, i + 1, i + nx, i + 1, i + nx + 1, i + nx});
    }
  return g;
}

// The grid stored plainly (float positions and normals, uint32 indices), as the reference.
Scene loadPlainGrid(const Grid& g) {
  GltfBuilder b;
  b.addMesh("grid", {b.primitive(g.positions, g.normals, g.indices)});
  b.setRoots({b.addNode({{"mesh", 0}})});
  return loadGltf(b.writeGltf(test::scratchDir(), "plain.gltf"));
}

using Triangle = std::array<glm::vec3, 3>;

std::vector<Triangle> triangles(const Mesh& mesh) {
  std::vector<Triangle> out;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
    out.push_back({mesh.positions[mesh.indices[t]], mesh.positions[mesh.indices[t + 1]],
                   mesh.positions[mesh.indices[t + 2]]});
  return out;
}

// Codecs may reorder triangles and rotate each one's vertices (winding kept): every triangle of
// `actual` must match one of `expected`, in some rotation, within `tolerance` per vertex.
void expectSameTriangles(const Mesh& actual, const Mesh& expected, float tolerance) {
  const std::vector<Triangle> a = triangles(actual), e = triangles(expected);
  ASSERT_EQ(a.size(), e.size());
  std::vector<char> used(e.size(), 0);
  for (const Triangle& t : a) {
    bool found = false;
    for (size_t k = 0; k < e.size() && !found; ++k)
      for (int r = 0; r < 3 && !found; ++r)
        if (!used[k] && glm::distance(t[0], e[k][r]) <= tolerance && glm::distance(t[1], e[k][(r + 1) % 3]) <= tolerance &&
            glm::distance(t[2], e[k][(r + 2) % 3]) <= tolerance)
        {
          used[k] = 1;
          found = true;
        }
    EXPECT_TRUE(found) << "triangle (" << t[0].x << ", " << t[0].y << ", " << t[0].z << ") ... has no match";
  }
}

// Each loaded vertex's normal against the reference normal at the nearest reference position.
void expectSameNormals(const Mesh& actual, const Mesh& expected, float tolerance) {
  ASSERT_EQ(actual.normals.size(), actual.positions.size());
  for (size_t i = 0; i < actual.positions.size(); ++i) {
    size_t nearest = 0;
    for (size_t k = 1; k < expected.positions.size(); ++k)
      if (glm::distance(actual.positions[i], expected.positions[k]) <
          glm::distance(actual.positions[i], expected.positions[nearest]))
        nearest = k;
    expectNear(actual.normals[i], expected.normals[nearest], tolerance);
  }
}

// Writes `doc` with its binary buffer as .gltf (a data URI) or .glb (the BIN chunk): buffer 0.
std::string writeWithBin(json doc, const std::vector<uint8_t>& bin, const std::string& name, bool glb,
                         const std::string& dir = test::scratchDir()) {
  json buffer = {{"byteLength", bin.size()}};
  if (!glb) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
  if (!doc["buffers"].is_array()) doc["buffers"] = json::array();
  doc["buffers"].insert(doc["buffers"].begin(), buffer);
  const std::string path = (fs::path(dir) / name).string();
  writeFile(path, glb ? test::glbFile(doc.dump(), bin) : doc.dump(1));
  return path;
}

// ---- EXT_meshopt_compression ------------------------------------------------------------------

// A glTF whose bufferViews are meshopt streams in buffer 0, decoding into buffer 1: the
// fallback, which has neither uri nor data (what gltfpack writes).
struct MeshoptFile {
  json doc = {{"asset", {{"version", "2.0"}}},
              {"extensionsUsed", {"EXT_meshopt_compression", "KHR_mesh_quantization"}},
              {"extensionsRequired", {"EXT_meshopt_compression", "KHR_mesh_quantization"}}};
  std::vector<uint8_t> bin;
  size_t fallbackSize = 0;

  // Encodes `count` elements of `stride` bytes; returns the bufferView's index.
  int addStream(const void* data, size_t count, size_t stride, const std::string& mode,
                const std::string& filter = "NONE", bool vertexAttribute = true) {
    std::vector<uint8_t> encoded;
    if (mode == "ATTRIBUTES") {
      encoded.resize(meshopt_encodeVertexBufferBound(count, stride));
      encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), data, count, stride));
    } else {
      std::vector<unsigned int> indices(count);
      for (size_t i = 0; i < count; ++i)
        indices[i] = stride == 2 ? static_cast<const uint16_t*>(data)[i] : static_cast<const uint32_t*>(data)[i];
      const bool triangles = mode == "TRIANGLES";
      encoded.resize(triangles ? meshopt_encodeIndexBufferBound(count, 1000) : meshopt_encodeIndexSequenceBound(count, 1000));
      encoded.resize(triangles ? meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), indices.data(), count)
                               : meshopt_encodeIndexSequence(encoded.data(), encoded.size(), indices.data(), count));
    }
    EXPECT_GT(encoded.size(), 0u);
    while (bin.size() % 4 != 0) bin.push_back(0);
    const size_t offset = bin.size();
    bin.insert(bin.end(), encoded.begin(), encoded.end());
    json ext = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", encoded.size()}, {"byteStride", stride},
                {"count", count}, {"mode", mode}};
    if (filter != "NONE") ext["filter"] = filter;
    json view = {{"buffer", 1}, {"byteOffset", fallbackSize}, {"byteLength", count * stride},
                 {"extensions", {{"EXT_meshopt_compression", ext}}}};
    if (vertexAttribute) view["byteStride"] = stride;
    fallbackSize += (count * stride + 3) / 4 * 4;
    doc["bufferViews"].push_back(view);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }

  int addAccessor(int view, int componentType, const std::string& type, size_t count, bool normalized = false) {
    json accessor = {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}};
    if (normalized) accessor["normalized"] = true;
    doc["accessors"].push_back(accessor);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }

  std::string write(const std::string& name, bool glb, const std::string& dir = test::scratchDir()) const {
    json d = doc;
    d["buffers"] = json::array(
        {{{"byteLength", fallbackSize}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
    return writeWithBin(d, bin, name, glb, dir);
  }
};

// Positions through the EXPONENTIAL filter, normals through OCTAHEDRAL (normalized bytes),
// triangles through the index codec; `sequence`: plain positions and the INDICES codec on
// 16-bit indices instead.
MeshoptFile meshoptGrid(const Grid& g, bool sequence) {
  MeshoptFile f;
  const size_t n = g.positions.size();
  std::vector<float> xyz;
  for (const glm::vec3& p : g.positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  int position;
  if (sequence) {
    position = f.addAccessor(f.addStream(xyz.data(), n, 12, "ATTRIBUTES"), kFloat, "VEC3", n);
  } else {
    std::vector<uint32_t> filtered(n * 3);
    meshopt_encodeFilterExp(filtered.data(), n, 12, 15, xyz.data());
    position = f.addAccessor(f.addStream(filtered.data(), n, 12, "ATTRIBUTES", "EXPONENTIAL"), kFloat, "VEC3", n);
  }
  std::vector<float> nxyzw;
  for (const glm::vec3& v : g.normals) nxyzw.insert(nxyzw.end(), {v.x, v.y, v.z, 0.0f});
  std::vector<int8_t> octahedral(n * 4);
  meshopt_encodeFilterOct(octahedral.data(), n, 4, 8, nxyzw.data());
  const int normal =
      f.addAccessor(f.addStream(octahedral.data(), n, 4, "ATTRIBUTES", "OCTAHEDRAL"), kByte, "VEC3", n, true);
  int indices;
  if (sequence) {
    std::vector<uint16_t> shorts(g.indices.begin(), g.indices.end());
    indices = f.addAccessor(f.addStream(shorts.data(), shorts.size(), 2, "INDICES", "NONE", false), kUnsignedShort,
                            "SCALAR", shorts.size());
  } else {
    indices = f.addAccessor(f.addStream(g.indices.data(), g.indices.size(), 4, "TRIANGLES", "NONE", false),
                            kUnsignedInt, "SCALAR", g.indices.size());
  }
  const json primitive = {{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"indices", indices}};
  f.doc["meshes"] = json::array({{{"primitives", json::array({primitive})}}});
  f.doc["nodes"] = json::array({{{"mesh", 0}}});
  f.doc["scenes"] = json::array({{{"nodes", {0}}}});
  f.doc["scene"] = 0;
  return f;
}

TEST(GltfCompressedTest, MeshoptLoadsLikeTheUncompressedMesh) {
  const Grid g = makeGrid();
  const Scene plain = loadPlainGrid(g);
  for (const bool sequence : {false, true})
    for (const bool glb : {false, true}) {
      SCOPED_TRACE(std::string(sequence ? "INDICES, no filter" : "TRIANGLES, EXPONENTIAL") + (glb ? ", .glb" : ", .gltf"));
      const std::string path = meshoptGrid(g, sequence).write(glb ? "meshopt.glb" : "meshopt.gltf", glb);
      testing::internal::CaptureStderr();
      const Scene scene = loadGltf(path);
      EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
      ASSERT_EQ(scene.meshes.size(), 1u);
      // Without a filter the codec is lossless; EXPONENTIAL keeps 15 bits of mantissa under
      // one exponent per vertex (the largest coordinate, up to 2): steps of 2^-13.
      expectSameTriangles(scene.meshes[0], plain.meshes[0], sequence ? 0.0f : 5e-4f);
      expectSameNormals(scene.meshes[0], plain.meshes[0], 0.02f);  // 8-bit octahedral
      if (sequence) {
        EXPECT_EQ(scene.meshes[0].indices, plain.meshes[0].indices);
      }
    }
}

TEST(GltfCompressedTest, CorruptMeshoptDataIsAOneLineError) {
  const Grid g = makeGrid();
  const std::string dir = test::scratchDir();
  for (const bool glb : {false, true}) {
    MeshoptFile garbage = meshoptGrid(g, false);
    const size_t offset = garbage.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteOffset"];
    for (size_t i = 0; i < 8; ++i) garbage.bin[offset + i] = 0xFF;  // a header no codec version has
    expectLoadError(garbage.write(glb ? "garbage.glb" : "garbage.gltf", glb, dir), "corrupt");

    MeshoptFile cut = meshoptGrid(g, false);
    cut.doc["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 5;  // the triangles, cut short
    expectLoadError(cut.write(glb ? "cut.glb" : "cut.gltf", glb, dir), "corrupt");

    MeshoptFile huge = meshoptGrid(g, false);
    huge.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 100000000;
    expectLoadError(huge.write(glb ? "huge.glb" : "huge.gltf", glb, dir), "corrupt");

    MeshoptFile stride = meshoptGrid(g, false);
    stride.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6;
    expectLoadError(stride.write(glb ? "stride.glb" : "stride.gltf", glb, dir), "byteStride 6");
  }
}

// ---- KHR_draco_mesh_compression ---------------------------------------------------------------

// The grid as one Draco mesh (positions quantized to 14 bits, normals to 10), in a file whose
// accessors have no bufferView, as Draco exporters write them.
std::string dracoGrid(const Grid& g, const std::string& name, bool glb, const std::string& dir,
                      std::vector<uint8_t>* encodedOut = nullptr, const std::vector<uint8_t>* replace = nullptr) {
  draco::TriangleSoupMeshBuilder builder;
  const int faces = static_cast<int>(g.indices.size() / 3);
  builder.Start(faces);
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nor = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f) {
    const auto corner = [&](int c) { return g.indices[static_cast<size_t>(3 * f + c)]; };
    builder.SetAttributeValuesForFace(pos, draco::FaceIndex(f), &g.positions[corner(0)], &g.positions[corner(1)],
                                      &g.positions[corner(2)]);
    builder.SetAttributeValuesForFace(nor, draco::FaceIndex(f), &g.normals[corner(0)], &g.normals[corner(1)],
                                      &g.normals[corner(2)]);
  }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  EXPECT_TRUE(mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  draco::EncoderBuffer buffer;
  EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
  std::vector<uint8_t> bin(buffer.data(), buffer.data() + buffer.size());
  if (encodedOut) *encodedOut = bin;
  if (replace) bin = *replace;
  const json ext = {{"bufferView", 0},
                    {"attributes", {{"POSITION", mesh->attribute(pos)->unique_id()},
                                    {"NORMAL", mesh->attribute(nor)->unique_id()}}}};
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_draco_mesh_compression"}},
      {"extensionsRequired", {"KHR_draco_mesh_compression"}},
      {"bufferViews", json::array({{{"buffer", 0}, {"byteLength", bin.size()}}})},
      {"accessors", json::array({{{"componentType", kFloat}, {"type", "VEC3"}, {"count", mesh->num_points()}},
                                 {{"componentType", kFloat}, {"type", "VEC3"}, {"count", mesh->num_points()}},
                                 {{"componentType", kUnsignedInt}, {"type", "SCALAR"}, {"count", g.indices.size()}}})},
      {"meshes", json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}},
                                                            {"indices", 2},
                                                            {"extensions", {{"KHR_draco_mesh_compression", ext}}}}})}}})},
      {"nodes", json::array({{{"mesh", 0}}})},
      {"scenes", json::array({{{"nodes", {0}}}})},
      {"scene", 0}};
  return writeWithBin(doc, bin, name, glb, dir);
}

TEST(GltfCompressedTest, DracoLoadsLikeTheUncompressedMesh) {
  const Grid g = makeGrid();
  const Scene plain = loadPlainGrid(g);
  for (const bool glb : {false, true}) {
    SCOPED_TRACE(glb ? ".glb" : ".gltf");
    const Scene scene = loadGltf(dracoGrid(g, glb ? "draco.glb" : "draco.gltf", glb, test::scratchDir()));
    ASSERT_EQ(scene.meshes.size(), 1u);
    // 14 bits over a 2-unit range: about 1e-4 per coordinate.
    expectSameTriangles(scene.meshes[0], plain.meshes[0], 5e-4f);
    expectSameNormals(scene.meshes[0], plain.meshes[0], 0.01f);
  }
}

TEST(GltfCompressedTest, CorruptDracoDataIsAOneLineError) {
  const Grid g = makeGrid();
  const std::string dir = test::scratchDir();
  std::vector<uint8_t> encoded;
  dracoGrid(g, "good.glb", true, dir, &encoded);
  std::vector<uint8_t> zeros(encoded.size(), 0);
  std::vector<uint8_t> half(encoded.begin(), encoded.begin() + static_cast<std::ptrdiff_t>(encoded.size() / 2));
  std::vector<uint8_t> flipped = encoded;
  for (size_t i = encoded.size() / 3; i < encoded.size(); i += 7) flipped[i] ^= 0x5A;
  int n = 0;
  for (const std::vector<uint8_t>* bad : {&zeros, &half, &flipped})
    for (const bool glb : {false, true}) {
      const std::string name = "bad" + std::to_string(n++) + (glb ? ".glb" : ".gltf");
      try {
        // Flipped bits may still decode: then the geometry is checked like any other.
        loadGltf(dracoGrid(g, name, glb, dir, nullptr, bad), {.quiet = true});
        EXPECT_EQ(bad, &flipped) << name << " loaded";
      } catch (const MrrError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(name), std::string::npos) << message;
        if (bad != &flipped) {
          EXPECT_NE(message.find("KHR_draco_mesh_compression"), std::string::npos) << message;
        }
      }
    }
}

// ---- KHR_mesh_quantization ---------------------------------------------------------------------

// One triangle stored in `componentType` (normalized or not) with a 4-byte-aligned stride,
// dequantized by a node scale: it must land where the float triangle does.
TEST(GltfCompressedTest, QuantizedPositionsAndNormalsLoadThroughTheNodeTransform) {
  struct Case {
    int componentType;
    bool normalized;
    double range;  // the stored value for 1.0
  };
  const std::vector<Case> cases = {{kShort, true, 32767.0}, {kUnsignedShort, false, 1000.0},
                                   {kByte, true, 127.0}, {kUnsignedByte, false, 100.0},
                                   {kShort, false, 1000.0}, {kUnsignedShort, true, 65535.0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::to_string(c.componentType) + (c.normalized ? " normalized" : ""));
    const size_t size = c.componentType == kShort || c.componentType == kUnsignedShort ? 2 : 1;
    const double unit = c.normalized ? 1.0 : c.range;  // what 1.0 reads back as
    std::vector<uint8_t> bytes(3 * 8, 0);
    for (size_t v = 0; v < 3; ++v)
      for (size_t k = 0; k < 3; ++k) {
        const auto q = static_cast<int64_t>(std::lround(kTriangle[v][static_cast<int>(k)] * c.range));
        std::memcpy(bytes.data() + v * 8 + k * size, &q, size);  // little-endian low bytes
      }
    std::vector<int8_t> normals;
    for (size_t v = 0; v < 3; ++v) normals.insert(normals.end(), {0, 0, 127, 0});
    GltfBuilder b;
    const int position = b.addView(bytes.data(), bytes.size(), 8);
    b.doc["accessors"].push_back(
        {{"bufferView", position}, {"componentType", c.componentType}, {"normalized", c.normalized}, {"type", "VEC3"}, {"count", 3}});
    const int normal = b.addView(normals.data(), normals.size(), 4);
    b.doc["accessors"].push_back(
        {{"bufferView", normal}, {"componentType", kByte}, {"normalized", true}, {"type", "VEC3"}, {"count", 3}});
    b.addMesh("q", {json{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}});
    const double s = 2.0 / unit;
    b.setRoots({b.addNode({{"mesh", 0}, {"scale", {s, s, s}}, {"translation", {1.0, 0.0, 0.0}}})});
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    const Scene scene = loadGltf(b.writeGltf(test::scratchDir(), "quantized.gltf"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    for (size_t v = 0; v < 3; ++v) {
      expectNear(scene.meshes[0].positions[v], 2.0f * kTriangle[v] + glm::vec3(1, 0, 0), 2.0f / static_cast<float>(c.range));
      expectNear(scene.meshes[0].normals[v], {0, 0, 1});
    }
  }
}

// Integer attributes in a file that does not declare KHR_mesh_quantization: one clear error naming
// the primitive, the attribute, its accessor, its type and the extension (read, they would be
// garbage geometry rendered with exit status 0). Declared, the same file loads.
TEST(GltfCompressedTest, QuantizedAttributesWithoutTheExtensionAreAnError) {
  const std::string dir = test::scratchDir();
  for (const auto& [componentType, name] : {std::pair{kByte, "BYTE"}, std::pair{kUnsignedByte, "UNSIGNED_BYTE"},
                                            std::pair{kShort, "SHORT"}, std::pair{kUnsignedShort, "UNSIGNED_SHORT"}})
    for (bool normalized : {false, true}) {
      SCOPED_TRACE(std::string(name) + (normalized ? " normalized" : ""));
      const size_t size = componentType == kShort || componentType == kUnsignedShort ? 2 : 1;
      std::vector<uint8_t> bytes(3 * 8, 0);  // (0,0,0), (1,0,0), (0,1,0), 8 bytes apart (little-endian)
      bytes[8] = bytes[16 + size] = 1;
      GltfBuilder b;
      b.doc["accessors"].push_back({{"bufferView", b.addView(bytes.data(), bytes.size(), 8)},
                                    {"componentType", componentType},
                                    {"normalized", normalized},
                                    {"type", "VEC3"},
                                    {"count", 3}});
      b.addMesh("q", {json{{"attributes", {{"POSITION", 0}}}}});
      b.setRoots({b.addNode({{"mesh", 0}})});
      expectLoadError(b.writeGltf(dir, "undeclared.gltf"),
                      "mesh 'q' primitive 0 POSITION accessor 0 has componentType " + std::string(name) +
                          (normalized ? " (normalized)" : "") + ", which needs KHR_mesh_quantization (not declared");
      b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
      EXPECT_EQ(loadGltf(b.writeGltf(dir, "declared.gltf")).meshes.size(), 1u);
    }
  // A BYTE normal beside float positions: the normal is named.
  GltfBuilder b;
  const std::vector<int8_t> normals = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0};
  const json p = b.primitive(kTriangle, kUpNormals, {0, 1, 2});
  b.doc["accessors"].push_back({{"bufferView", b.addView(normals.data(), normals.size(), 4)},
                                {"componentType", kByte},
                                {"normalized", true},
                                {"type", "VEC3"},
                                {"count", 3}});
  json q = p;
  q["attributes"]["NORMAL"] = b.doc["accessors"].size() - 1;
  b.addMesh("n", {q});
  b.setRoots({b.addNode({{"mesh", 0}})});
  expectLoadError(b.writeGltf(dir, "normals.gltf"),
                  "NORMAL accessor " + std::to_string(b.doc["accessors"].size() - 1) +
                      " has componentType BYTE (normalized), which needs KHR_mesh_quantization");
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};  // declared as required alone: enough
  EXPECT_EQ(loadGltf(b.writeGltf(dir, "normals-declared.gltf")).meshes.size(), 1u);
}

// ---- sparse accessors ----------------------------------------------------------------------------

TEST(GltfCompressedTest, SparseAccessorsSubstituteTheirValues) {
  const std::string dir = test::scratchDir();
  // Over a bufferView: vertex 2 moves from (0, 1, 0) to (0, 3, 0).
  GltfBuilder b = singleTriangle();
  const std::vector<uint8_t> index = {2, 0, 0, 0};
  const std::vector<float> value = {0.0f, 3.0f, 0.0f};
  const int indexView = b.addView(index.data(), 1);
  const int valueView = b.addView(value.data(), 12);
  b.doc["accessors"][0]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", indexView}, {"componentType", kUnsignedByte}}},
                                     {"values", {{"bufferView", valueView}}}};
  Scene scene = loadGltf(b.writeGltf(dir, "sparse.gltf"));
  expectNear(scene.meshes[0].positions[2], {0, 3, 0});
  expectNear(scene.meshes[0].positions[1], {1, 0, 0});
  // Without one: zeros, then vertices 1 and 2 set.
  GltfBuilder z;
  const std::vector<uint16_t> indices = {1, 2};
  const std::vector<float> values = {1, 0, 0, 0, 1, 0};
  const int iv = z.addView(indices.data(), 4);
  const int vv = z.addView(values.data(), 24);
  z.doc["accessors"].push_back({{"componentType", kFloat},
                                {"type", "VEC3"},
                                {"count", 3},
                                {"sparse", {{"count", 2},
                                            {"indices", {{"bufferView", iv}, {"componentType", kUnsignedShort}}},
                                            {"values", {{"bufferView", vv}}}}}});
  z.addMesh("zeros", {json{{"attributes", {{"POSITION", 0}}}}});
  z.setRoots({z.addNode({{"mesh", 0}})});
  scene = loadGltf(z.writeGltf(dir, "sparsezeros.gltf"));
  for (size_t v = 0; v < 3; ++v) expectNear(scene.meshes[0].positions[v], kTriangle[v]);
  // A substitution outside the accessor is an error.
  GltfBuilder bad = singleTriangle();
  const std::vector<uint8_t> outside = {9, 0, 0, 0};
  const int ov = bad.addView(outside.data(), 1);
  const int ovv = bad.addView(value.data(), 12);
  bad.doc["accessors"][0]["sparse"] = {{"count", 1},
                                       {"indices", {{"bufferView", ov}, {"componentType", kUnsignedByte}}},
                                       {"values", {{"bufferView", ovv}}}};
  expectLoadError(bad.writeGltf(dir, "sparsebad.gltf"), "sparse index 9 is out of range");
}

// ---- what the loader refuses, names or skips ------------------------------------------------------

TEST(GltfCompressedTest, UnknownRequiredExtensionIsNamedBeforeBuffersAreRead) {
  GltfBuilder b = singleTriangle();
  json doc = b.finished(false);
  doc["extensionsRequired"] = {"KHR_mesh_quantization", "EXT_foo_bar"};
  doc["buffers"][0]["uri"] = "absent.bin";  // would be the error if buffers came first
  const std::string path = (fs::path(test::scratchDir()) / "foo.gltf").string();
  writeFile(path, doc.dump());
  expectLoadError(path, "requires glTF extension EXT_foo_bar, which mrr does not read");
}

TEST(GltfCompressedTest, MissingBinNamesTheFileAndWhereItWasExpected) {
  const std::string dir = test::scratchDir();
  for (const bool glb : {false, true}) {
    GltfBuilder b = singleTriangle();
    json doc = b.finished(false);
    doc["buffers"][0]["uri"] = "scene.bin";
    const std::string path = (fs::path(dir) / (glb ? "scene.glb" : "scene.gltf")).string();
    writeFile(path, glb ? test::glbFile(doc.dump(), {}) : doc.dump());
    const std::string expected = (fs::absolute(fs::path(dir)) / "scene.bin").lexically_normal().string();
    expectLoadError(path, "buffer 0: file scene.bin not found (expected at " + expected + ")");
  }
}

TEST(GltfCompressedTest, OnlyDrawnBaseColourImagesAreReadAndAnAbsentOneIsSaid) {
  // Material 0 draws the triangle with a base-colour image that is absent: said, drawn with its
  // factor. Image 1 is only a normal map, image 2 only an unused material's base colour: neither
  // is read, so their broken bytes say nothing.
  GltfBuilder b = singleTriangle();
  b.doc["materials"] = json::array(
      {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}, {"baseColorTexture", {{"index", 0}}}}},
        {"normalTexture", {{"index", 1}}}},
       {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 2}}}}}}});
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}, {{"source", 2}}});
  b.doc["images"] = json::array({{{"uri", "absent/albedo.png"}},
                                 {{"uri", "data:image/png;base64,AAAA"}},
                                 {{"uri", "data:image/png;base64,AAAA"}}});
  const std::string path = b.writeGltf(test::scratchDir(), "textured.gltf");
  testing::internal::CaptureStderr();
  const Scene scene = loadGltf(path);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("material 0: base-colour image 0 could not be read (see above): drawn with its factor"),
            std::string::npos)
      << err;
  EXPECT_EQ(err.find("image 1"), std::string::npos) << err;
  EXPECT_EQ(err.find("image 2"), std::string::npos) << err;
  EXPECT_EQ(scene.meshes[0].texture, -1);
  EXPECT_TRUE(scene.textures.empty());
  expectNear(scene.meshes[0].baseColor, {0.5f, 0.25f, 1.0f});
}

TEST(GltfCompressedTest, SkinsMorphsAndAlphaModesWarnOnceInOneLineEach) {
  GltfBuilder b = singleTriangle({{"skin", 0}});
  b.doc["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 0}}});
  b.doc["skins"] = json::array({{{"joints", {0}}}});
  b.addNode({{"mesh", 0}, {"skin", 0}});
  b.setRoots({0, 1});
  b.doc["materials"] = json::array({{{"alphaMode", "BLEND"}}, {{"alphaMode", "BLEND"}}, {{"alphaMode", "MASK"}}});
  const std::string path = b.writeGltf(test::scratchDir(), "skinned.gltf");
  testing::internal::CaptureStderr();
  const Scene scene = loadGltf(path);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 2) << err;  // a MASK without texture and alpha 1: nothing to say
  EXPECT_NE(err.find("skins and morph targets are not applied (2 skinned mesh nodes, 1 primitives with morph targets)"),
            std::string::npos) << err;
  EXPECT_NE(err.find("2 materials are alphaMode BLEND, rendered opaque"), std::string::npos) << err;
  EXPECT_EQ(err.find("MASK"), std::string::npos) << err;
}

// --blend-materials skip leaves BLEND primitives out (a fake light cone, glass); the default
// draws them opaque. Either way one line says how many there are.
TEST(GltfCompressedTest, BlendMaterialsAreOpaqueOrSkipped) {
  GltfBuilder b;
  const int opaque = b.addMaterial({0.5, 0.5, 0.5, 1.0});
  const int blend = b.addMaterial({1.0, 1.0, 0.0, 0.29});
  b.doc["materials"][static_cast<size_t>(blend)]["alphaMode"] = "BLEND";
  b.addMesh("solid", {b.primitive(kTriangle, kUpNormals, {0, 1, 2}, opaque)});
  b.addMesh("cone", {b.primitive(kTriangle, kUpNormals, {0, 1, 2}, blend)});
  b.setRoots({b.addNode({{"mesh", 0}}), b.addNode({{"mesh", 1}, {"translation", {0, 0, -1}}})});
  const std::string path = b.writeGltf(test::scratchDir(), "blend.gltf");
  testing::internal::CaptureStderr();
  const Scene drawn = loadGltf(path);
  const std::string drawnErr = testing::internal::GetCapturedStderr();
  EXPECT_EQ(drawn.meshes.size(), 2u);
  EXPECT_NE(drawnErr.find("1 materials are alphaMode BLEND, rendered opaque"), std::string::npos) << drawnErr;
  LoadOptions skip;
  skip.skipBlend = true;
  testing::internal::CaptureStderr();
  const Scene skipped = loadGltf(path, skip);
  const std::string skippedErr = testing::internal::GetCapturedStderr();
  ASSERT_EQ(skipped.meshes.size(), 1u);
  expectNear(skipped.meshes[0].baseColor, {0.5f, 0.5f, 0.5f});
  EXPECT_NE(skippedErr.find("1 materials are alphaMode BLEND, skipped (--blend-materials skip): 1 primitives left out"),
            std::string::npos)
      << skippedErr;
}

}  // namespace
}  // namespace mrr
