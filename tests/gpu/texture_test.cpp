// Base-colour textures as albedo (docs/spec.md §1.2): a quad made here, its 4×4 texture
// of 16 distinct colours written as a PNG beside it, seen square on. Each pixel centre's ray
// meets the quad's plane at a known point, so its texture coordinate, its texel (wrap modes,
// KHR_texture_transform, TEXCOORD_1) and its albedo are known without the renderer; both paths
// must give exactly that albedo at every pixel not within a hair of a texel border. Then the
// port against the oracle on the textured frame, every stage (SSGI bleeds the texture's colours).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <set>

#include "compare/parity/parity.h"
#include "cpu_ref/pipeline.h"
#include "gpu/pipeline.h"
#include "scenes/default_light.h"
#include "tests/common/gltf_builder.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

using gltftest::GltfBuilder;
using gltftest::json;

constexpr int kTexels = 4;
constexpr float kEyeZ = 3.0f;
const glm::vec3 kFactor{0.5f, 1.0f, 0.8f};

// Texel (i, j) (column i, row j from the image's first row): 16 distinct sRGB colours.
glm::ivec3 texelBytes(int i, int j) { return {16 * i + 8, 40 * j + 100, (37 * (i + 4 * j) + 11) % 256}; }

std::string writeChecker(const std::string& path) {
  std::vector<uint8_t> rgb;
  for (int j = 0; j < kTexels; ++j)
    for (int i = 0; i < kTexels; ++i) {
      const glm::ivec3 b = texelBytes(i, j);
      rgb.insert(rgb.end(), {static_cast<uint8_t>(b.x), static_cast<uint8_t>(b.y), static_cast<uint8_t>(b.z)});
    }
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out);
  EXPECT_TRUE(out->open(path, OIIO::ImageSpec(kTexels, kTexels, 3, OIIO::TypeDesc::UINT8)));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
  out->close();
  return path;
}

// One case: the sampler's wrap mode, which TEXCOORD_n the material reads, and an optional
// KHR_texture_transform (offset, scale, rotation, and its texCoord override).
struct Case {
  std::string name;
  int wrap = 10497;  // REPEAT
  int texCoord = 0;
  bool transform = false;
  int transformTexCoord = -1;
};

// The quad [0, 2]² at z = 0 facing +z. TEXCOORD_0 runs over [−½, 3/2] (so the wrap modes show),
// TEXCOORD_1 over [0, 1]; where a case reads the other set, its own set is all zeros, so reading
// the wrong one shows one colour.
glm::dvec2 uv0(double x, double y) { return {-0.5 + x, 1.5 - y}; }
glm::dvec2 uv1(double x, double y) { return {0.5 * x, 1.0 - 0.5 * y}; }
constexpr double kOffset[2] = {0.25, -0.1}, kScale[2] = {1.5, 0.75}, kRotation = 0.4;

int readSet(const Case& c) { return c.transformTexCoord >= 0 ? c.transformTexCoord : c.texCoord; }

// The texture coordinate a case reads at the plane point (x, y), transformed as the extension says.
glm::dvec2 expectedUv(const Case& c, double x, double y) {
  glm::dvec2 uv = readSet(c) == 1 ? uv1(x, y) : uv0(x, y);
  if (c.transform) {
    const double s = kScale[0] * uv.x, t = kScale[1] * uv.y, co = std::cos(kRotation), si = std::sin(kRotation);
    uv = {kOffset[0] + co * s + si * t, kOffset[1] - si * s + co * t};
  }
  return uv;
}

std::string writeScene(const Case& c, const std::string& dir) {
  writeChecker(dir + "/checker.png");
  GltfBuilder b;
  const std::vector<glm::vec3> corners = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  json p = b.primitive(corners, std::vector<glm::vec3>(4, {0, 0, 1}), {0, 1, 2, 0, 2, 3}, 0);
  std::vector<float> st0, st1;
  for (const glm::vec3& q : corners) {
    const glm::dvec2 a = uv0(q.x, q.y), d = uv1(q.x, q.y);
    st0.insert(st0.end(), {static_cast<float>(a.x), static_cast<float>(a.y)});
    st1.insert(st1.end(), {static_cast<float>(d.x), static_cast<float>(d.y)});
  }
  if (readSet(c) == 1) std::fill(st0.begin(), st0.end(), 0.0f);
  p["attributes"]["TEXCOORD_0"] = b.addAccessor(b.addView(st0.data(), st0.size() * 4), gltftest::kFloat, "VEC2", 4);
  p["attributes"]["TEXCOORD_1"] = b.addAccessor(b.addView(st1.data(), st1.size() * 4), gltftest::kFloat, "VEC2", 4);
  b.addMesh("quad", {p});
  json info = {{"index", 0}, {"texCoord", c.texCoord}};
  if (c.transform) {
    json t = {{"offset", {kOffset[0], kOffset[1]}}, {"scale", {kScale[0], kScale[1]}}, {"rotation", kRotation}};
    if (c.transformTexCoord >= 0) t["texCoord"] = c.transformTexCoord;
    info["extensions"] = {{"KHR_texture_transform", t}};
    b.doc["extensionsUsed"] = {"KHR_texture_transform"};
  }
  b.push("materials", {{"pbrMetallicRoughness",
                        {{"baseColorFactor", {kFactor.x, kFactor.y, kFactor.z, 1.0}}, {"baseColorTexture", info}}}});
  b.push("textures", {{"source", 0}, {"sampler", 0}});
  b.push("samplers", {{"wrapS", c.wrap}, {"wrapT", c.wrap}, {"magFilter", 9728}});
  b.push("images", {{"uri", "checker.png"}});
  b.setRoots({b.addNode({{"mesh", 0}})});
  return b.writeGltf(dir, c.name + ".gltf");
}

// The texel index along one axis, as the spec says, in double (the test's own arithmetic).
int expectedTexel(double t, int wrap) {
  const long long i = static_cast<long long>(std::floor(t * kTexels));
  if (wrap == 33071) return static_cast<int>(std::clamp<long long>(i, 0, kTexels - 1));
  const long long period = wrap == 33648 ? 2 * kTexels : kTexels;
  const long long k = ((i % period) + period) % period;
  return static_cast<int>(k < kTexels ? k : 2 * kTexels - 1 - k);
}

Constants frameConstants(Effect effect, int w, int h, float framed) {
  Settings s = defaultSettings(effect);
  s.width = w;
  s.height = h;
  s.mode = Mode::Mrr;
  s.neverSlower = false;
  s.ssgi.samples = 16;
  return makeConstants(s, framed);
}

struct Tally {
  int checked = 0, wrong = 0;
  std::set<int> texels;  // which texels the checked pixels showed
};

Tally check(const Case& c, const FrameResult& f) {
  const GBuffer& g = f.levels[0].gbuffer;
  const float* linear = srgbToLinearTable();
  Tally t;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const glm::vec3 d = f.view.worldRay(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
      const glm::dvec3 p = glm::dvec3(f.view.eye) + glm::dvec3(d) * (-static_cast<double>(f.view.eye.z) / d.z);
      if (!(p.x > 0.01 && p.x < 1.99 && p.y > 0.01 && p.y < 1.99)) continue;
      const glm::dvec2 uv = expectedUv(c, p.x, p.y);
      const auto nearBorder = [](double u) { return std::fabs(u * kTexels - std::round(u * kTexels)) < 0.02; };
      if (nearBorder(uv.x) || nearBorder(uv.y)) continue;
      const int i = expectedTexel(uv.x, c.wrap), j = expectedTexel(uv.y, c.wrap);
      const glm::ivec3 bytes = texelBytes(i, j);
      const glm::vec3 expected = kFactor * glm::vec3(linear[bytes.x], linear[bytes.y], linear[bytes.z]);
      ++t.checked;
      t.texels.insert(i + kTexels * j);
      bool same = g.hit.at(x, y) != 0;
      for (int k = 0; k < 3; ++k) same = same && g.albedo.at(x, y, k) == expected[k];
      t.wrong += !same;
    }
  return t;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"repeat", 10497},
      {"clamp", 33071},
      {"mirror", 33648},
      {"transform", 10497, 0, true},
      {"texcoord1", 10497, 1},
      {"transform_texcoord1", 33648, 0, true, 1},
  };
  return all;
}

void expectExact(const Case& c, const Tally& t, const std::string& path) {
  EXPECT_GT(t.checked, 15000) << c.name << " " << path;
  EXPECT_GE(t.texels.size(), 9u) << c.name << " " << path << ": too few texels in view to tell a wrong lookup";
  EXPECT_EQ(t.wrong, 0) << c.name << " " << path << ": " << t.wrong << " of " << t.checked
                        << " pixels' albedo is not the texel's";
}

TEST(Texture, SrgbTableIsTheTransferFunction) {
  const float* t = srgbToLinearTable();
  EXPECT_EQ(t[0], 0.0f);
  EXPECT_EQ(t[255], 1.0f);
  EXPECT_NEAR(t[10], 10.0 / 255.0 / 12.92, 1e-9);                        // the linear toe
  EXPECT_NEAR(t[128], std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4), 1e-7);  // 0.2158
  for (int i = 1; i < 256; ++i) EXPECT_LT(t[i - 1], t[i]) << i;
}

TEST(Texture, LoaderReadsTheTextureSamplerAndTransform) {
  const std::string dir = test::scratchDir();
  const Case& c = cases()[3];  // transform
  const Scene s = loadGltf(writeScene(c, dir));
  ASSERT_EQ(s.textures.size(), 1u);
  const ColorTexture& t = s.textures[0];
  EXPECT_EQ(t.width, kTexels);
  EXPECT_EQ(t.height, kTexels);
  EXPECT_EQ(t.wrapS, Wrap::Repeat);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].texture, 0);
  EXPECT_EQ(s.meshes[0].cutout, -1);
  ASSERT_EQ(s.meshes[0].texcoords.size(), 4u);
  // the transform is applied to the vertices' coordinates on the host, once for both paths
  const glm::dvec2 at2 = expectedUv(c, 2.0, 2.0);
  EXPECT_NEAR(s.meshes[0].texcoords[2].x, at2.x, 1e-6);
  EXPECT_NEAR(s.meshes[0].texcoords[2].y, at2.y, 1e-6);
  // texel (1, 2) through the table, times the factor
  const glm::ivec3 b = texelBytes(1, 2);
  const float* linear = srgbToLinearTable();
  EXPECT_EQ(t.linearAt(1.5f / kTexels, 2.5f / kTexels), glm::vec3(linear[b.x], linear[b.y], linear[b.z]));
}

TEST(Texture, OracleAlbedoIsTheTexelTimesTheFactor) {
  for (const Case& c : cases()) {
    const std::string dir = test::scratchDir();
    const Scene scene = loadGltf(writeScene(c, dir));
    const Renderer renderer(scene);
    const Camera camera = lookAt({1.0f, 1.0f, kEyeZ}, {1.0f, 1.0f, 0.0f}, 45.0f);
    expectExact(c, check(c, renderer.render(camera, frameConstants(Effect::Ssao, 320, 180, framedSize(scene, camera, 320.0f / 180.0f).size))),
                "oracle");
  }
}

TEST(Texture, WithoutItTheAlbedoIsTheFactor) {
  // The planted fault: the texture taken away must fail the check above.
  const Case& c = cases()[0];
  Scene scene = loadGltf(writeScene(c, test::scratchDir()));
  scene.meshes.at(0).texture = -1;
  const Renderer renderer(scene);
  const Camera camera = lookAt({1.0f, 1.0f, kEyeZ}, {1.0f, 1.0f, 0.0f}, 45.0f);
  const Tally t = check(c, renderer.render(camera, frameConstants(Effect::Ssao, 320, 180, framedSize(scene, camera, 320.0f / 180.0f).size)));
  EXPECT_EQ(t.wrong, t.checked);
}

TEST(Texture, PortAlbedoIsTheTexelTimesTheFactor) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (const Case& c : cases()) {
    const std::string dir = test::scratchDir();
    const Scene scene = loadGltf(writeScene(c, dir));
    const gpu::GpuRenderer renderer(scene);
    const Camera camera = lookAt({1.0f, 1.0f, kEyeZ}, {1.0f, 1.0f, 0.0f}, 45.0f);
    expectExact(c, check(c, renderer.render(camera, frameConstants(Effect::Ssao, 320, 180, framedSize(scene, camera, 320.0f / 180.0f).size))),
                "port");
  }
}

TEST(Texture, PortMatchesTheOracleOnATexturedFrame) {
  MRR_REQUIRE_GL_OR_SKIP();
  // The textured quad before a grey wall, seen at an angle (so texels cross pixels obliquely), in
  // SSGI: the wall receives the texture's colours.
  const Case& c = cases()[3];
  Scene scene = loadGltf(writeScene(c, test::scratchDir()));
  Mesh wall;
  wall.name = "wall";
  wall.positions = {{-3, -1, -1.5f}, {5, -1, -1.5f}, {5, 4, -1.5f}, {-3, 4, -1.5f}, {-3, -1, 2}, {5, -1, 2}};
  wall.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  wall.indices = {0, 1, 2, 0, 2, 3};
  wall.baseColor = glm::vec3(0.8f);
  Mesh floor = wall;
  floor.name = "floor";
  floor.positions = {{-3, -0.2f, -1.5f}, {5, -0.2f, -1.5f}, {5, -0.2f, 3}, {-3, -0.2f, 3}};
  floor.normals.assign(4, {0, 1, 0});
  floor.indices = {0, 2, 1, 0, 3, 2};
  wall.positions.resize(4);
  wall.normals.resize(4);
  scene.meshes.push_back(wall);
  scene.meshes.push_back(floor);
  scene.light.direction = glm::normalize(glm::vec3(-0.3f, -0.6f, -1.0f));
  const Camera camera = lookAt({2.6f, 1.6f, 3.2f}, {0.8f, 0.9f, 0.0f}, 50.0f);
  for (Effect effect : {Effect::Ssgi, Effect::Ssao}) {
    const Constants k = frameConstants(effect, 161, 97, framedSize(scene, camera, 161.0f / 97.0f).size);
    const Renderer oracle(scene);
    const gpu::GpuRenderer port(scene);
    const RenderOptions keep{true, {}, nullptr};
    const FrameResult a = oracle.render(camera, k, keep), b = port.render(camera, k, keep);
    const ParityResult r = compareFrames(a, b, scene.light);
    EXPECT_TRUE(r.pass()) << toString(effect) << ": first failing stage " << r.firstFailing() << "\n"
                          << formatParityTable(r);
    bool sawAlbedo = false;
    for (const StageRow& row : r.rows)
      if (row.stage == "gbuffer.L0.albedo") {
        sawAlbedo = true;
        ASSERT_TRUE(row.endToEnd);
        EXPECT_TRUE(row.endToEnd->pass) << row.endToEnd->figures;
      }
    EXPECT_TRUE(sawAlbedo) << "no albedo row";
  }
}

}  // namespace
}  // namespace mrr
