// Tests of the command line: they run the real `mrr` binary (MRR_BINARY) on good and bad
// input, with stdout and stderr captured to files in the test's scratch directory. Every
// render is tiny (builtin scenes, 64x48 or smaller, 4 or 8 samples) so the file runs in seconds.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/cost_model.h"
#include "common/image_io.h"
#include "tests/test_support.h"

namespace mrr {
namespace {
using mrr::test::base64;
using mrr::test::readFile;

namespace fs = std::filesystem;
using nlohmann::json;

// ---- running the binary -----------------------------------------------------------------

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  return out + "'";
}

struct RunResult {
  int status = -1;       // exit status (WEXITSTATUS), or -1 if it did not exit normally
  bool exited = false;   // false: killed by a signal (a crash)
  std::string out, err;  // captured stdout and stderr
  std::string command;
};

// How a run is started beyond its arguments.
struct RunEnv {
  std::vector<std::string> env;  // NAME=VALUE pairs set for the program only
  // Run as `nobody` when the tests run as root (CI containers do): root writes anywhere, so a
  // read-only folder only refuses a write to an unprivileged user.
  bool unprivileged = false;
};

// Runs `program args...` with stdout/stderr captured to files in `captureDir`.
RunResult runProgram(const std::string& program, const std::vector<std::string>& args,
                     const std::string& captureDir, const RunEnv& how = {}) {
  RunResult r;
  const std::string outPath = (fs::path(captureDir) / "captured.stdout").string();
  const std::string errPath = (fs::path(captureDir) / "captured.stderr").string();
  std::string cmd;
  if (how.unprivileged && ::geteuid() == 0) cmd += "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  if (!how.env.empty()) {
    cmd += "env";
    for (const std::string& e : how.env) cmd += " " + shellQuote(e);
    cmd += " ";
  }
  cmd += shellQuote(program);
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  r.command = cmd;
  cmd += " >" + shellQuote(outPath) + " 2>" + shellQuote(errPath) + " </dev/null";
  const int raw = std::system(cmd.c_str());
  r.exited = raw != -1 && WIFEXITED(raw);
  r.status = r.exited ? WEXITSTATUS(raw) : -1;
  r.out = readFile(outPath);
  r.err = readFile(errPath);
  fs::remove(outPath);
  fs::remove(errPath);
  return r;
}

RunResult runMrr(const std::vector<std::string>& args, const std::string& captureDir, const RunEnv& how = {}) {
  return runProgram(MRR_BINARY, args, captureDir, how);
}

std::string describe(const RunResult& r) {
  return "command: " + r.command + "\nexit: " + std::to_string(r.status) + "\nstdout:\n" + r.out +
         "\nstderr:\n" + r.err;
}

// Every file (recursively) under `dir`, as paths relative to it.
std::set<std::string> listTree(const std::string& dir) {
  std::set<std::string> names;
  if (!fs::exists(dir)) return names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    names.insert(fs::relative(e.path(), dir).string());
  return names;
}

void expectNoTemporaries(const std::string& dir) {
  for (const std::string& name : listTree(dir))
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "temporary file left behind: " << dir << "/" << name;
}

// `bytes` of an OpenEXR file with the value of every "capDate" header attribute (the
// capture time OpenImageIO writes, as DateTime) replaced by 'X's.
std::string blankCaptureDates(std::string bytes) {
  const std::string key("capDate\0string\0", 15);
  for (size_t p = bytes.find(key); p != std::string::npos; p = bytes.find(key, p + 1)) {
    const size_t sizeAt = p + key.size();
    if (sizeAt + 4 > bytes.size()) break;
    uint32_t size = 0;
    for (int i = 0; i < 4; ++i) size |= static_cast<uint32_t>(static_cast<uint8_t>(bytes[sizeAt + i])) << (8 * i);
    for (size_t i = sizeAt + 4; i < sizeAt + 4 + size && i < bytes.size(); ++i) bytes[i] = 'X';
  }
  return bytes;
}

bool nonEmptyFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0;
}

// Common arguments for a tiny, quiet render. Frames this small and cheap would often fall back
// to full under the never-slower rule (SPEC §11), which would hide the stages these tests
// check: the rule has its own test (NeverSlowerReportsTheFallback).
std::vector<std::string> tiny(std::vector<std::string> args, const std::string& size = "64x48",
                              const std::string& samples = "4") {
  args.insert(args.end(), {"--size", size, "--samples", samples, "--never-slower", "off", "--quiet"});
  return args;
}

// ---- generated glTF files -----------------------------------------------------------------
// The approach of tests/common/gltf_test.cpp (a document with one base64 buffer, or a GLB
// assembled by hand), reduced to what these tests need.

constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;

template <class T>
void appendBytes(std::vector<uint8_t>& bin, const std::vector<T>& values) {
  while (bin.size() % 4 != 0) bin.push_back(0);
  const auto* p = reinterpret_cast<const uint8_t*>(values.data());
  bin.insert(bin.end(), p, p + values.size() * sizeof(T));
}

// A one-mesh glTF document (one triangle list) and its binary buffer.
struct TriangleGltf {
  json doc;
  std::vector<uint8_t> bin;

  TriangleGltf(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
    appendBytes(bin, positions);
    const size_t indexOffset = (bin.size() + 3) / 4 * 4;
    appendBytes(bin, indices);
    const size_t vertexCount = positions.size() / 3;
    doc = {{"asset", {{"version", "2.0"}}},
           {"scene", 0},
           {"scenes", json::array({{{"nodes", {0}}}})},
           {"nodes", json::array({{{"mesh", 0}}})},
           {"meshes", json::array({{{"name", "tri"},
                                    {"primitives", json::array({{{"attributes", {{"POSITION", 0}}},
                                                                 {"indices", 1}}})}}})},
           {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions.size() * 4}},
                                        {{"buffer", 0},
                                         {"byteOffset", indexOffset},
                                         {"byteLength", indices.size() * 4}}})},
           {"accessors", json::array({{{"bufferView", 0},
                                       {"componentType", kFloat},
                                       {"type", "VEC3"},
                                       {"count", vertexCount}},
                                      {{"bufferView", 1},
                                       {"componentType", kUnsignedInt},
                                       {"type", "SCALAR"},
                                       {"count", indices.size()}}})}};
  }

  json finished(bool glb) const {
    json d = doc;
    json buffer = {{"byteLength", bin.size()}};
    if (!glb) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
    d["buffers"] = json::array({buffer});
    return d;
  }

  std::string gltfText() const { return finished(false).dump(1); }

  std::string glbBytes() const { return test::glbFile(finished(true).dump(), bin); }
};

const std::vector<float> kTriangle = {-1, -1, 0, 1, -1, 0, 0, 1, 0};

// Writes every input file the bad-input cases name into `in`.
void writeBadInputs(const std::string& in) {
  auto path = [&](const char* name) { return (fs::path(in) / name).string(); };
  fs::create_directories(path("folder.gltf"));
  fs::create_directories(path("isdir.exr"));
  writeFile(path("empty.gltf"), "");
  std::string magic = TriangleGltf(kTriangle, {0, 1, 2}).glbBytes();
  magic.replace(0, 4, "gLTF");
  writeFile(path("magic.glb"), magic);
  const std::string glb = TriangleGltf(kTriangle, {0, 1, 2}).glbBytes();
  writeFile(path("truncated.glb"), glb.substr(0, glb.size() / 2));
  writeFile(path("notgltf.gltf"), R"({"hello": "world", "numbers": [1, 2, 3]})");
  // frame files that cannot be a frame
  writeFile(path("unknown-key.json"), R"({"scene": "builtin:demo", "colour": 1})");
  writeFile(path("no-view.json"), R"({"scene": "builtin:demo", "eye": [1, 2, 3], "target": [1, 2, 3]})");
  writeFile(path("negative-size.json"), R"({"scene": "builtin:demo", "size": "-64x48"})");
  writeFile(path("not-a-frame.json"), "[1, 2, 3]");
  // cost models (--cost-model) in the --calibrate format, one figure missing or out of range
  nlohmann::json costs = CostModel::defaults("cpu").toJson();
  costs.erase("ns_per_blend_pixel");
  writeFile(path("costs-missing-key.json"), costs.dump(2));
  costs = CostModel::defaults("cpu").toJson();
  costs["effects"]["ssgi"]["sparse_factor"] = 2.5;
  writeFile(path("costs-sparse-factor.json"), costs.dump(2));
  // previous frames (--prev-frame, SPEC §13) of another scene or size than the 32x24 builtin:demo frame
  const std::string camera = R"("eye": [0, 1, 5], "target": [0, 1, 0], "up": [0, 1, 0], "fov": 60)";
  writeFile(path("prev-other-scene.json"), R"({"scene": "builtin:corner", "size": "32x24", )" + camera + "}");
  writeFile(path("prev-other-size.json"), R"({"scene": "builtin:demo", "size": "64x48", )" + camera + "}");
  // an EXR that is not a stages file (compare --against): one part named like no stage
  writeMultiPartExr(path("beauty.exr"), {{"beauty", ImageF(32, 24, 3, 0.5f), {"R", "G", "B"}}}, 32, 24);
  writeFile(path("badindex.gltf"), TriangleGltf(kTriangle, {0, 1, 7}).gltfText());
  std::vector<float> nan = kTriangle;
  nan[4] = std::numeric_limits<float>::quiet_NaN();
  writeFile(path("nanposition.gltf"), TriangleGltf(nan, {0, 1, 2}).gltfText());
  writeFile(path("nomeshes.gltf"), R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0})");
  std::vector<float> inf = kTriangle;
  inf[0] = std::numeric_limits<float>::infinity();
  writeFile(path("infposition.gltf"), TriangleGltf(inf, {0, 1, 2}).gltfText());
  TriangleGltf badUri(kTriangle, {0, 1, 2});
  json badUriDoc = badUri.finished(false);
  badUriDoc["buffers"][0]["uri"] = "no-such-buffer.bin";
  writeFile(path("baduri.gltf"), badUriDoc.dump());
  json shortDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  shortDoc["accessors"][0]["count"] = 300;  // 300 vertices from a 36-byte view
  writeFile(path("shortbuffer.gltf"), shortDoc.dump());
  json typeDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  typeDoc["accessors"][0]["componentType"] = 5125;  // UNSIGNED_INT positions (bytes and shorts are quantized ones)
  writeFile(path("componenttype.gltf"), typeDoc.dump());
  json quantizedDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  quantizedDoc["accessors"][0]["componentType"] = 5121;  // UNSIGNED_BYTE positions, KHR_mesh_quantization undeclared
  writeFile(path("quantized.gltf"), quantizedDoc.dump());
  json extensionDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  extensionDoc["extensionsRequired"] = {"EXT_foo_bar"};
  writeFile(path("extension.gltf"), extensionDoc.dump());
  // Compressed views whose bytes are plain floats, not a meshopt or Draco stream.
  json meshoptDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  meshoptDoc["extensionsRequired"] = {"EXT_meshopt_compression"};
  meshoptDoc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"] = {
      {"buffer", 0}, {"byteLength", 36}, {"byteStride", 12}, {"count", 3}, {"mode", "ATTRIBUTES"}};
  writeFile(path("meshopt.gltf"), meshoptDoc.dump());
  json dracoDoc = TriangleGltf(kTriangle, {0, 1, 2}).finished(false);
  dracoDoc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  dracoDoc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {
      {"bufferView", 0}, {"attributes", {{"POSITION", 0}}}};
  writeFile(path("draco.glb"), test::glbFile(dracoDoc.dump(), {}));
  const std::vector<float> line = {0, 0, 0, 1, 1, 1, 2, 2, 2};  // three collinear points
  writeFile(path("zeroarea.gltf"), TriangleGltf(line, {0, 1, 2, 0, 0, 1}).gltfText());
  fs::create_directories(path("readonly"));
  fs::permissions(path("readonly"), fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                        fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
}

// ---- good runs ----------------------------------------------------------------------------

class CliRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::scratchDir();
    out = (fs::path(dir) / "out").string();
    fs::create_directories(out);
  }
  std::string at(const std::string& name) const { return (fs::path(out) / name).string(); }

  std::string dir, out;
};

bool glAvailable(const std::string& dir);  // below: whether the GL path works here

// A frame written by --frame-out and read back by --frame gives the same bits, on both paths,
// with the camera from the catalogue and the light turned; the report and the stages EXR carry
// the same frame, and an option given beside --frame wins.
TEST_F(CliRenderTest, FrameOutAndFrameReproduceTheBits) {
  for (const std::string path : {"cpu", "gpu"}) {
    if (path == "gpu" && !glAvailable(dir)) continue;  // glAvailable: the GL tests' own check (CI has GL)
    const RunResult a = runMrr({"render", "--scene", "builtin:shadows", "--effect", "ssm", "--size", "64x40", "--samples",
                                "16", "-q", "--path", path, "--light-dir", "-0.2,1,0.3", "--tau-n", "0.2", "--out",
                                at(path + "a.exr"), "--report", at(path + "a.json"), "--frame-out", at(path + "f.json")},
                               dir);
    ASSERT_EQ(a.status, 0) << describe(a);
    const RunResult b = runMrr({"render", "--frame", at(path + "f.json"), "-q", "--path", path, "--out", at(path + "b.exr")}, dir);
    ASSERT_EQ(b.status, 0) << describe(b);
    EXPECT_EQ(readFile(at(path + "a.exr")), readFile(at(path + "b.exr"))) << path << ": not the same bits";
    const json frame = json::parse(readFile(at(path + "f.json")));
    EXPECT_EQ(json::parse(readFile(at(path + "a.json")))["frame"], frame);
    EXPECT_EQ(frame["tau_n"].get<float>(), 0.2f);
    const RunResult c = runMrr({"render", "--frame", at(path + "f.json"), "-q", "--path", path, "--tau-n", "0.5",
                                "--report", at(path + "c.json")},
                               dir);
    ASSERT_EQ(c.status, 0) << describe(c);
    EXPECT_EQ(json::parse(readFile(at(path + "c.json")))["frame"]["tau_n"].get<float>(), 0.5f);
  }
}

// mrr-effect's widening as frame parameters (SPEC §12): a frame file carries them (level 0 and a
// small cap, so 0 must be a valid whole number in a file) and reproduces the bits on both paths;
// the two paths shade the same pixels; mrr's own files do not name them.
TEST_F(CliRenderTest, MrrEffectsWideningTravelsInFrameFiles) {
  std::map<std::string, int64_t> shaded;
  for (const std::string path : {"cpu", "gpu"}) {
    if (path == "gpu" && !glAvailable(dir)) continue;
    // a priori (--effect-budget 0): the budget prices with each path's own cost model (SPEC §12.4)
    const RunResult a = runMrr({"render", "--scene", "builtin:demo", "--method", "mrr-effect", "--effect-cap", "3",
                                "--effect-first-level", "0", "--effect-budget", "0", "--size", "96x64", "--samples", "8",
                                "-q", "--path", path,
                                "--out", at(path + "e.exr"), "--report", at(path + "e.json"), "--frame-out",
                                at(path + "ef.json")},
                               dir);
    ASSERT_EQ(a.status, 0) << describe(a);
    const json frame = json::parse(readFile(at(path + "ef.json")));
    EXPECT_EQ(frame["effect_cap"], 3);
    EXPECT_EQ(frame["effect_first_level"], 0);
    const RunResult b = runMrr({"render", "--frame", at(path + "ef.json"), "-q", "--path", path, "--out", at(path + "f.exr")}, dir);
    ASSERT_EQ(b.status, 0) << describe(b);
    EXPECT_EQ(readFile(at(path + "e.exr")), readFile(at(path + "f.exr"))) << path << ": not the same bits";
    shaded[path] = json::parse(readFile(at(path + "e.json")))["shaded_pixels_total"].get<int64_t>();
  }
  if (shaded.count("gpu")) EXPECT_EQ(shaded["gpu"], shaded["cpu"]);
  const RunResult m = runMrr({"render", "--scene", "builtin:demo", "--size", "32x32", "--samples", "4", "-q", "--out",
                              at("m.exr"), "--frame-out", at("mf.json")},
                             dir);
  ASSERT_EQ(m.status, 0) << describe(m);
  EXPECT_FALSE(json::parse(readFile(at("mf.json"))).contains("effect_cap"));
  // The a-posteriori term and the ablation's effect-only arm (SPEC §12.2, §12.3) travel too, on
  // both paths, and reproduce the bits; effect-only shades fewer pixels than the default, and the
  // paths shade the same number.
  std::map<std::string, std::array<int64_t, 2>> total;
  for (const std::string path : {"cpu", "gpu"}) {
    if (path == "gpu" && !glAvailable(dir)) continue;
    for (const bool only : {false, true}) {
      std::vector<std::string> args = {"render", "--scene", "builtin:demo", "--method", "mrr-effect",
                                       "--effect-posterior", "0.05", "--effect-budget", "0", "--size", "96x64",
                                       "--samples", "8", "-q", "--never-slower", "off", "--path", path, "--out", at("p.exr"), "--report",
                                       at("p.json"), "--frame-out", at("pf.json")};
      if (only) args.push_back("--effect-only");
      const RunResult p = runMrr(args, dir);
      ASSERT_EQ(p.status, 0) << describe(p);
      const json frame = json::parse(readFile(at("pf.json")));
      EXPECT_NEAR(frame["effect_posterior"].get<double>(), 0.05, 1e-7);
      EXPECT_EQ(frame["effect_only"], only);
      total[path][only] = json::parse(readFile(at("p.json")))["shaded_pixels_total"].get<int64_t>();
      const RunResult q = runMrr({"render", "--frame", at("pf.json"), "-q", "--path", path, "--out", at("q.exr")}, dir);
      ASSERT_EQ(q.status, 0) << describe(q);
      EXPECT_EQ(readFile(at("p.exr")), readFile(at("q.exr"))) << path << " effect_only " << only << ": not the same bits";
    }
    EXPECT_LT(total[path][1], total[path][0]) << path;
  }
  if (total.count("gpu")) EXPECT_EQ(total["gpu"], total["cpu"]);
}

// The a-posteriori term (SPEC §12.2) from the command line, on both paths: it travels in frame
// files, shades more than the a priori masks alone, and the paths shade alike on this frame.
TEST_F(CliRenderTest, MrrEffectsPosteriorTermTravelsInFrameFiles) {
  std::map<std::string, int64_t> shaded, prior;
  for (const std::string path : {"cpu", "gpu"}) {
    if (path == "gpu" && !glAvailable(dir)) continue;
    const std::vector<std::string> frame = {"render", "--scene", "builtin:demo", "--method", "mrr-effect", "--effect-cap",
                                            "4", "--effect-budget", "0", "--never-slower", "off", "--size", "96x64",
                                            "--samples", "8", "-q", "--path", path};
    std::vector<std::string> refined = frame;
    refined.insert(refined.end(), {"--effect-posterior", "0.05", "--effect-posterior-finest", "0", "--out",
                                   at(path + "p.exr"), "--report", at(path + "p.json"), "--frame-out", at(path + "pf.json")});
    const RunResult a = runMrr(refined, dir);
    ASSERT_EQ(a.status, 0) << describe(a);
    const json file = json::parse(readFile(at(path + "pf.json")));
    EXPECT_FLOAT_EQ(file["effect_posterior"].get<float>(), 0.05f);
    EXPECT_EQ(file["effect_posterior_finest"], 0);
    const RunResult b = runMrr({"render", "--frame", at(path + "pf.json"), "-q", "--path", path, "--out", at(path + "q.exr")}, dir);
    ASSERT_EQ(b.status, 0) << describe(b);
    EXPECT_EQ(readFile(at(path + "p.exr")), readFile(at(path + "q.exr"))) << path << ": not the same bits";
    shaded[path] = json::parse(readFile(at(path + "p.json")))["shaded_pixels_total"].get<int64_t>();
    std::vector<std::string> apriori = frame;
    apriori.insert(apriori.end(), {"--out", at(path + "a.exr"), "--report", at(path + "a.json")});
    ASSERT_EQ(runMrr(apriori, dir).status, 0);
    prior[path] = json::parse(readFile(at(path + "a.json")))["shaded_pixels_total"].get<int64_t>();
    EXPECT_GT(shaded[path], prior[path]) << path << ": the term refined nothing";
  }
  if (shaded.count("gpu")) EXPECT_EQ(shaded["gpu"], shaded["cpu"]);
}

// mrr info: what a scene holds and the view a render would take, as text and JSON.
TEST_F(CliRenderTest, InfoTellsWhatASceneHolds) {
  const RunResult text = runMrr({"info", "builtin:fence"}, dir);
  ASSERT_EQ(text.status, 0) << describe(text);
  for (const char* line : {"geometry    6 triangles in 3 meshes", "cutout 16x16, 43.75% opaque",
                           "view        --eye 2.5,2.20000005,5.5 --target 0,0.899999976,-0.5 --fov 55",
                           "suggested   --eye "})
    EXPECT_NE(text.out.find(line), std::string::npos) << line << "\n" << text.out;
  const RunResult j = runMrr({"info", "builtin:fence", "--json", "--size", "320x180"}, dir);
  ASSERT_EQ(j.status, 0) << describe(j);
  const json info = json::parse(j.out);
  EXPECT_EQ(info["triangles"], 6);
  EXPECT_EQ(info["cameras"].size(), 1u);
  EXPECT_EQ(info["light"]["from_scene"], true);
  EXPECT_EQ(info["cutouts"][0]["width"], 16);
  EXPECT_EQ(info["suggested"]["interior"], false);
  // The suggested view is a real one: rendering with its --eye/--target works and sees the fence.
  auto triple = [](const json& v) {
    return std::to_string(v[0].get<double>()) + "," + std::to_string(v[1].get<double>()) + "," +
           std::to_string(v[2].get<double>());
  };
  const RunResult r = runMrr({"render", "--scene", "builtin:fence", "--size", "64x36", "--samples", "4", "-q", "--eye",
                              triple(info["suggested"]["eye"]), "--target", triple(info["suggested"]["target"]),
                              "--report", at("suggested.json")},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_GT(json::parse(readFile(at("suggested.json")))["levels"][0]["shaded_pixels"].get<int>() +
                json::parse(readFile(at("suggested.json")))["levels"][3]["shaded_pixels"].get<int>(),
            0);
}

// The report records the frame's camera and light as given, and --light-dir
// (toward the light) turns the scene's light: the shadows of SSM move with it.
TEST_F(CliRenderTest, ReportRecordsTheCameraAndTheLight) {
  auto render = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", "--scene", "builtin:shadows", "--effect", "ssm", "--samples", "16",
                                     "--size", "64x48", "-q", "--eye", "1,3,6", "--target", "0,0.5,0", "--fov", "50",
                                     "--report", at(name + ".json"), "--out", at(name + ".exr")};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runMrr(args, dir);
    EXPECT_EQ(r.status, 0) << describe(r);
    return json::parse(readFile(at(name + ".json")));
  };
  const json scene = render("scene", {});
  const json turned = render("turned", {"--light-dir", "0,2,0"});
  ASSERT_TRUE(scene.contains("camera") && scene.contains("light")) << scene.dump(2);
  EXPECT_EQ(scene["camera"]["eye"], json::array({1.0, 3.0, 6.0}));
  EXPECT_EQ(scene["camera"]["target"], json::array({0.0, 0.5, 0.0}));
  EXPECT_NEAR(scene["camera"]["yfov_degrees"].get<double>(), 50.0, 1e-4);
  EXPECT_EQ(turned["light"]["toward_light"], json::array({0.0, 1.0, 0.0}));  // normalised
  EXPECT_EQ(turned["light"]["direction"], json::array({-0.0, -1.0, -0.0}));
  EXPECT_NE(scene["light"]["direction"], turned["light"]["direction"]);
  EXPECT_NEAR(turned["light"]["angular_diameter_rad"].get<double>(), 0.05, 1e-6);
  const ImageF a = readImage(at("scene.exr")), b = readImage(at("turned.exr"));
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_NE(a.data, b.data) << "--light-dir did not change the shadows";
}

TEST_F(CliRenderTest, RenderWritesEveryOutputAndAFullReport) {
  const RunResult r = runMrr(tiny({"render", "--scene", "builtin:demo", "--out", at("final.exr"), "--shaded",
                                   at("shaded.png"), "--stages", at("stages.exr"), "--report", at("report.json"),
                                   "--reference"}),
                             dir);
  ASSERT_TRUE(r.exited) << describe(r);
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.err, "") << "--quiet run wrote to stderr\n" << describe(r);
  for (const char* name : {"final.exr", "shaded.png", "stages.exr", "report.json"})
    EXPECT_TRUE(nonEmptyFile(at(name))) << name;
  EXPECT_EQ(listTree(out), (std::set<std::string>{"final.exr", "shaded.png", "stages.exr", "report.json"}));
  expectNoTemporaries(out);

  const json j = json::parse(readFile(at("report.json")));
  for (const char* key : {"scene", "effect", "path", "mode", "width", "height", "samples", "threads", "levels",
                          "shaded_pixels_total", "ideal_speedup", "timings_ms", "error_vs_full"})
    EXPECT_TRUE(j.contains(key)) << "report lacks " << key << ":\n" << j.dump(2);
  ASSERT_TRUE(j.contains("levels") && j.contains("width") && j.contains("error_vs_full"));
  EXPECT_EQ(j["effect"], "ssao");
  EXPECT_EQ(j["path"], "cpu");
  EXPECT_EQ(j["mode"], "mrr");
  EXPECT_EQ(j["method"], "mrr");
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["height"], 48);
  EXPECT_EQ(j["samples"], 4);
  EXPECT_GE(j["threads"].get<int>(), 1);
  ASSERT_TRUE(j["levels"].is_array());
  ASSERT_EQ(j["levels"].size(), 4u);
  int64_t sum = 0;
  for (const json& level : j["levels"]) {
    for (const char* key : {"scale", "enabled", "sigma2", "weight", "shaded_pixels"})
      EXPECT_TRUE(level.contains(key)) << "level lacks " << key << ": " << level.dump();
    sum += level.value("shaded_pixels", int64_t{0});
  }
  EXPECT_EQ(j["levels"][0]["scale"], 1);
  EXPECT_EQ(j["levels"][3]["scale"], 8);
  const int64_t total = j["shaded_pixels_total"].get<int64_t>();
  EXPECT_EQ(total, sum);
  ASSERT_GT(total, 0);
  EXPECT_LT(total, 64 * 48) << "the demo scene should shade fewer pixels than full resolution";
  EXPECT_NEAR(j["ideal_speedup"].get<double>(), 64.0 * 48.0 / static_cast<double>(total), 1e-9);
  ASSERT_TRUE(j["timings_ms"].is_object());
  ASSERT_TRUE(j["timings_ms"].contains("total")) << j["timings_ms"].dump();
  EXPECT_GE(j["timings_ms"]["total"].get<double>(), 0.0);
  const json& e = j["error_vs_full"];
  for (const char* key : {"rms", "psnr", "ssim", "max_abs", "edge_band_rms"})
    EXPECT_TRUE(e.contains(key)) << "error_vs_full lacks " << key << ": " << e.dump();
  EXPECT_GE(e.value("rms", -1.0), 0.0);
  EXPECT_LE(e.value("ssim", 2.0), 1.0);
  // LDR-FLIP of the effect buffer and of the shaded image.
  for (const char* part : {"error_vs_full", "error_vs_full_shaded"}) {
    ASSERT_TRUE(j[part].contains("flip")) << part << ": " << j[part].dump();
    const json& f = j[part]["flip"];
    for (const char* key : {"mean", "median", "q1", "q3", "max"}) {
      ASSERT_TRUE(f.contains(key)) << part << ".flip lacks " << key << ": " << f.dump();
      EXPECT_GE(f[key].get<double>(), 0.0);
      EXPECT_LE(f[key].get<double>(), 1.0);
    }
    EXPECT_LE(f["q1"].get<double>(), f["q3"].get<double>());
  }
}

// The part names every multires run writes, for all four levels where they apply.
const std::vector<std::string> kExpectedParts = {
    "gbuffer.L0", "gbuffer.L3",    "edges",          "mask.L1",      "mask.L3",  "alpha.L2",
    "stencil.L3", "sub.L0",        "upsample.L0",    "blendalpha.L0", "composite.L0", "levelmap",
    "final",      "shaded",        "raw.L1",         "composite.L3"};

TEST_F(CliRenderTest, NeverSlowerReportsTheFallback) {
  // An image that is all edges: the method cannot gain, so the frame is shaded at full res,
  // the report says so, and stderr says why; with the rule off the method runs as asked.
  for (const std::string rule : {"on", "off"}) {
    const RunResult r = runMrr({"render", "--scene", "builtin:alledges", "--size", "160x90", "--samples", "8",
                                "--never-slower", rule, "--report", at("r-" + rule + ".json")},
                               dir);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json j = json::parse(readFile(at("r-" + rule + ".json")));
    if (rule == "on") {
      ASSERT_TRUE(j.contains("never_slower")) << j.dump(2);
      EXPECT_TRUE(j["never_slower"]["fell_back_to_full"].get<bool>());
      EXPECT_GT(j["never_slower"]["predicted_mrr_ms"].get<double>(), j["never_slower"]["predicted_full_ms"].get<double>());
      EXPECT_EQ(j["ideal_speedup"].get<double>(), 1.0);
      EXPECT_NE(r.err.find("never slower"), std::string::npos) << describe(r);
      // the counts it decided from (a silhouette pixel is one on geometry, so B ≤ H)
      EXPECT_GT(j["never_slower"]["hit_pixels"].get<int64_t>(), 160 * 90 / 2);
      EXPECT_LE(j["never_slower"]["silhouette_pixels"].get<int64_t>(), j["never_slower"]["hit_pixels"].get<int64_t>());
      // an image of edges samples an edge in (nearly) every one of its 20×12 blocks. Past its
      // floor, it falls back early or on the stencils: at this size the early estimate is within
      // 1% of full's rest, so which of the two decides is the calibration's call
      EXPECT_GE(j["never_slower"]["edge_sample_blocks"].get<int64_t>(), 20 * 12 * 9 / 10);
      EXPECT_TRUE(j["never_slower"]["decided"] == "early, before the edges" || j["never_slower"]["decided"] == "on the stencils")
          << j["never_slower"]["decided"];
    } else {
      EXPECT_FALSE(j.contains("never_slower"));
      EXPECT_LT(j["ideal_speedup"].get<double>(), 1.0) << "every level shades nearly everything";
    }
  }
}

TEST_F(CliRenderTest, NeverSlowerSkipsTheEdgeSampleWhereTheFloorRulesTheMethodOut) {
  // A camera looking up at the sky: a few pixels on geometry, so even the least the method could
  // pay (its coarse G-buffers and blend, every pixel of its coarsest level) is more than full's
  // rest. The rule decides there, on the floor, and never samples the edges.
  const RunResult r = runMrr({"render", "--scene", "builtin:demo", "--eye", "0,2,6", "--target", "0,30,-10", "--size",
                              "160x90", "--samples", "16", "--report", at("sky.json")},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const json j = json::parse(readFile(at("sky.json")));
  ASSERT_TRUE(j.contains("never_slower")) << j.dump(2);
  EXPECT_TRUE(j["never_slower"]["fell_back_to_full"].get<bool>());
  EXPECT_EQ(j["never_slower"]["decided"], "early, on the floor, before the edge sample");
  EXPECT_FALSE(j["never_slower"].contains("edge_sample_blocks")) << "no sample was taken";
  EXPECT_LT(j["never_slower"]["hit_pixels"].get<int64_t>(), 160 * 90 / 10);
  EXPECT_GT(j["never_slower"]["predicted_mrr_ms"].get<double>(), j["never_slower"]["predicted_full_ms"].get<double>());
  EXPECT_NE(r.err.find("before the edge sample"), std::string::npos) << describe(r);
}

TEST_F(CliRenderTest, RuleSweepJudgesEveryFrameByItsOwnTimes) {
  // One scene's four views, two configurations each, two pairs per frame: the verdicts and the
  // summary must follow from the times the sweep recorded (docs/figures.md reads them).
  const RunResult r = runMrr({"bench", "--rule-sweep", at("sweep.json"), "--paths", "cpu", "--scenes", "builtin:plane",
                              "--repeats", "2", "--threads", "2"},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.out.find("| frames | right (faster within 5%) | wrong beyond noise |"), std::string::npos) << r.out;
  const json j = json::parse(readFile(at("sweep.json")));
  const json& frames = j["frames"];
  ASSERT_EQ(frames.size(), 8u);
  int right = 0, wrongBeyondNoise = 0, kept = 0;
  double worstKept = 0.0;
  std::set<std::string> views;
  for (const json& f : frames) {
    views.insert(f["view"].get<std::string>());
    const std::string decision = f["decision"];
    EXPECT_TRUE(decision == "mrr" || decision == "full" || decision == "full-early" || decision == "full-floor") << decision;
    const double fullMs = f["full_ms"], mrrMs = f["mrr_ms"];
    EXPECT_GT(fullMs, 0.0);
    EXPECT_GT(mrrMs, 0.0);
    const bool keptMrr = decision == "mrr";
    EXPECT_EQ(f["right"].get<bool>(), keptMrr ? mrrMs <= 1.05 * fullMs : fullMs <= 1.05 * mrrMs) << f.dump();
    const size_t pairs = f["pair_ratios"].size();
    EXPECT_EQ(pairs, static_cast<size_t>(f["repeats"].get<int>())) << "one ratio per timed pair";
    EXPECT_TRUE(pairs == 2 || pairs == 4) << pairs;
    if (f["wrong_beyond_noise"].get<bool>()) EXPECT_FALSE(f["right"].get<bool>());
    right += f["right"].get<bool>();
    wrongBeyondNoise += f["wrong_beyond_noise"].get<bool>();
    if (keptMrr) {
      ++kept;
      worstKept = std::max(worstKept, mrrMs / fullMs);
    }
  }
  EXPECT_EQ(views, (std::set<std::string>{"catalogue", "default", "sky", "close-up"}));
  const json& summary = j["summary"];
  EXPECT_EQ(summary["frames"], 8);
  EXPECT_EQ(summary["right"], right);
  EXPECT_EQ(summary["wrong_beyond_noise"], wrongBeyondNoise);
  EXPECT_EQ(summary["kept_mrr"], kept);
  EXPECT_EQ(summary["fell_back"], 8 - kept);
  EXPECT_DOUBLE_EQ(summary["worst_kept_mrr_over_full"].get<double>(), worstKept);
  // How far the prices were from the times: full's rest, RMS of predicted / measured − 1.
  double squares = 0.0;
  for (const json& f : frames) {
    const double off = f["predicted_full_rest_ms"].get<double>() / f["measured_full_rest_ms"].get<double>() - 1.0;
    squares += off * off;
  }
  EXPECT_NEAR(summary["prediction_error"]["full_rest"]["rms"].get<double>(), std::sqrt(squares / 8.0), 1e-12);
  for (const char* key : {"mrr_rest", "mrr_early_estimate"}) EXPECT_GT(summary["prediction_error"][key]["rms"].get<double>(), 0.0) << key;
  EXPECT_NE(r.out.find("Predicted against measured: full's rest "), std::string::npos) << r.out;

  // Replayed with the model that decided it, the sweep decides and judges every frame as recorded
  // (a decision is a function of the counts the sweep keeps)...
  const RunResult same = runMrr({"bench", "--rule-replay", at("sweep.json"), "--json", at("replay.json")}, dir);
  ASSERT_EQ(same.status, 0) << describe(same);
  EXPECT_NE(same.out.find("0 frames decided or judged otherwise than the sweep recorded."), std::string::npos) << same.out;
  const json replayed = json::parse(readFile(at("replay.json")));
  EXPECT_EQ(replayed["summary"], summary);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(replayed["frames"][i]["decision"], frames[i]["decision"]) << i;
    EXPECT_DOUBLE_EQ(replayed["frames"][i]["predicted_mrr_early_ms"].get<double>(),
                     frames[i]["predicted_mrr_early_ms"].get<double>())
        << i;
  }
  // ...and a frame the method kept, its counts made those of a frame edged everywhere (every
  // level stencilled whole, every block marked), is decided otherwise, and said so.
  json planted = j;
  size_t victim = frames.size();
  for (size_t i = 0; i < frames.size() && victim == frames.size(); ++i)
    if (frames[i]["decision"] == "mrr") victim = i;
  ASSERT_LT(victim, frames.size()) << "the plane's sweep keeps the method on some frame (its close-ups)";
  json& f = planted["frames"][victim];
  const int w = f["width"], h = f["height"];
  json& counts = f["counts"];
  for (const char* key : {"shaded", "shaded_hit", "shaded_searched", "reach"})
    for (int l = 0; l < 4; ++l) counts[key][l] = static_cast<int64_t>((w + (1 << l) - 1) >> l) * ((h + (1 << l) - 1) >> l);
  counts["hit"] = counts["searched"] = static_cast<int64_t>(w) * h;
  counts["edge_blocks"] = static_cast<int64_t>((w + 7) / 8) * ((h + 7) / 8);
  writeFile(at("planted.json"), planted.dump());
  const RunResult other = runMrr({"bench", "--rule-replay", at("planted.json"), "--json", at("replay2.json")}, dir);
  ASSERT_EQ(other.status, 0) << describe(other);
  EXPECT_NE(other.out.find("1 frame decided or judged otherwise than the sweep recorded:"), std::string::npos) << other.out;
  EXPECT_NE(other.out.find("| mrr → full"), std::string::npos) << other.out;
  const json replayed2 = json::parse(readFile(at("replay2.json")));
  EXPECT_NE(replayed2["frames"][victim]["decision"], "mrr");
  EXPECT_TRUE(replayed2["frames"][victim]["rule_ms"].is_null()) << "the with-rule time of a fallback the sweep never ran";
  EXPECT_EQ(replayed2["summary"]["rule_unmeasured"], 1);

  // With another model (`--cost-model`, "{path}" replaced): one whose method costs a second more
  // on every frame falls back from every frame on its floor, before the edge sample, and names itself.
  CostModel dear = CostModel::defaults("cpu");
  dear.source = "a model whose method costs a second more";
  for (EffectCost& e : dear.effect) e.fixedMs += 1000.0;
  writeFile(at("dear-cpu.json"), dear.toJson().dump());
  const RunResult third =
      runMrr({"bench", "--rule-replay", at("sweep.json"), "--cost-model", at("dear-{path}.json"), "--json", at("replay3.json")}, dir);
  ASSERT_EQ(third.status, 0) << describe(third);
  const json replayed3 = json::parse(readFile(at("replay3.json")));
  EXPECT_EQ(replayed3["summary"]["kept_mrr"], 0);
  EXPECT_EQ(replayed3["summary"]["fell_back"], 8);
  EXPECT_EQ(replayed3["replayed_with"], json::array({"cpu: a model whose method costs a second more"}));
  int notOnFloor = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(replayed3["frames"][i]["decision"], "full-floor") << i;
    notOnFloor += frames[i]["decision"] != "full-floor";
  }
  ASSERT_GT(notOnFloor, 0);
  EXPECT_NE(third.out.find(std::to_string(notOnFloor) + (notOnFloor == 1 ? " frame" : " frames") +
                           " decided or judged otherwise"),
            std::string::npos)
      << third.out;
  const RunResult noModel =
      runMrr({"bench", "--rule-replay", at("sweep.json"), "--cost-model", at("absent-{path}.json")}, dir);
  EXPECT_EQ(noModel.status, 2) << describe(noModel);
  EXPECT_NE(noModel.err.find("absent-cpu.json: cannot read the file"), std::string::npos) << noModel.err;

  // Bad input: one line, exit 2.
  writeFile(at("notasweep.json"), "{\"frames\": 3}");
  for (const std::string& file : {at("missing.json"), at("notasweep.json")}) {
    const RunResult bad = runMrr({"bench", "--rule-replay", file}, dir);
    EXPECT_EQ(bad.status, 2) << describe(bad);
    EXPECT_EQ(bad.err.rfind("mrr: error: --rule-replay", 0), 0u) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  }
}

TEST_F(CliRenderTest, EveryMethodRendersAndNamesItself) {
  for (const std::string method : {"full", "uniform-1", "uniform-2", "tiles", "mrr"}) {
    const RunResult r = runMrr(tiny({"render", "--scene", "builtin:demo", "--method", method, "--report", at("m.json")}), dir);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json j = json::parse(readFile(at("m.json")));
    EXPECT_EQ(j["method"], method);
    if (method == "tiles") EXPECT_TRUE(j.contains("tiles"));
  }
}

TEST_F(CliRenderTest, StagesExrHasEveryPartByName) {
  const RunResult r = runMrr(tiny({"render", "--scene", "builtin:demo", "--stages", at("stages.exr")}, "48x32"), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const std::vector<ExrPart> parts = readParts(at("stages.exr"));
  std::set<std::string> names;
  for (const ExrPart& p : parts) names.insert(p.name);
  for (const std::string& name : kExpectedParts) EXPECT_TRUE(names.count(name)) << "no part " << name;
  for (const ExrPart& p : parts) {
    if (p.name == "final") {
      EXPECT_EQ(p.image.width, 48);
      EXPECT_EQ(p.image.height, 32);
    }
    if (p.name == "gbuffer.L3") {
      EXPECT_EQ(p.image.width, 6);
      EXPECT_EQ(p.image.height, 4);
    }
  }
}

TEST_F(CliRenderTest, OiiotoolListsTheStageParts) {
  const char* found = std::getenv("PATH");
  std::string oiiotool;
  if (found) {
    std::stringstream paths(found);
    for (std::string p; std::getline(paths, p, ':');) {
      const fs::path candidate = fs::path(p.empty() ? "." : p) / "oiiotool";
      if (::access(candidate.c_str(), X_OK) == 0) {
        oiiotool = candidate.string();
        break;
      }
    }
  }
  if (oiiotool.empty()) GTEST_SKIP() << "oiiotool not on PATH (install openimageio-tools)";
  const RunResult r = runMrr(tiny({"render", "--scene", "builtin:demo", "--stages", at("stages.exr")}, "48x32"), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const RunResult info = runProgram(oiiotool, {"-a", "--info", "-v", at("stages.exr")}, dir);
  ASSERT_EQ(info.status, 0) << describe(info);
  // `oiiotool --info -v` prints each subimage's attributes, the part name as `name: "gbuffer.L0"`.
  for (const std::string& name : kExpectedParts)
    EXPECT_NE(info.out.find("name: \"" + name + "\""), std::string::npos) << "oiiotool does not list " << name
                                                                          << "\n" << info.out;
}

TEST_F(CliRenderTest, FullModeShadesEveryPixel) {
  const RunResult r =
      runMrr(tiny({"render", "--scene", "builtin:demo", "--mode", "full", "--report", at("r.json")}), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const json j = json::parse(readFile(at("r.json")));
  EXPECT_EQ(j["mode"], "full");
  EXPECT_EQ(j["shaded_pixels_total"].get<int64_t>(), 64 * 48);
  EXPECT_EQ(j["ideal_speedup"].get<double>(), 1.0);
  EXPECT_FALSE(j.contains("error_vs_full")) << "no --reference given";
}

TEST_F(CliRenderTest, ThreadCountDoesNotChangeTheOutputBytes) {
  const RunResult one = runMrr(
      tiny({"render", "--scene", "builtin:demo", "--threads", "1", "--out", at("t1.exr")}, "97x61", "8"), dir);
  ASSERT_EQ(one.status, 0) << describe(one);
  const RunResult two = runMrr(
      tiny({"render", "--scene", "builtin:demo", "--threads", "2", "--out", at("t2.exr")}, "97x61", "8"), dir);
  ASSERT_EQ(two.status, 0) << describe(two);
  EXPECT_EQ(listTree(out), (std::set<std::string>{"t1.exr", "t2.exr"}));
  const std::string a = readFile(at("t1.exr")), b = readFile(at("t2.exr"));
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  // Every byte but the header's capture time (OpenImageIO stamps it; the wall-clock test below
  // checks that separately): this test fails only if the thread count changes the file.
  EXPECT_TRUE(blankCaptureDates(a) == blankCaptureDates(b)) << "--threads 1 and --threads 2 wrote different .exr bytes";
  // And the pixels, bit for bit.
  const ImageF pa = readImage(at("t1.exr")), pb = readImage(at("t2.exr"));
  ASSERT_EQ(pa.data.size(), pb.data.size());
  EXPECT_EQ(std::memcmp(pa.data.data(), pb.data.data(), pa.data.size() * sizeof(float)), 0);
}

// The same command run in two different wall-clock seconds must write the same bytes
// (README: outputs are bit-identical; nothing in a file may depend on when it was written).
TEST_F(CliRenderTest, OutputBytesDoNotDependOnWallClock) {
  const auto render = [&](const std::string& tag) {
    return runMrr(tiny({"render", "--scene", "builtin:plane", "--out", at("o" + tag + ".exr"), "--stages",
                        at("s" + tag + ".exr")},
                       "16x16"),
                  dir);
  };
  const RunResult first = render("1");
  ASSERT_EQ(first.status, 0) << describe(first);
  const std::time_t start = std::time(nullptr);
  while (std::time(nullptr) == start) ::usleep(20000);  // at most one second
  const RunResult second = render("2");
  ASSERT_EQ(second.status, 0) << describe(second);
  EXPECT_TRUE(readFile(at("o1.exr")) == readFile(at("o2.exr")))
      << "--out .exr bytes differ between runs a second apart (a timestamp in the header?)";
  EXPECT_TRUE(readFile(at("s1.exr")) == readFile(at("s2.exr")))
      << "--stages .exr bytes differ between runs a second apart (a timestamp in the header?)";
}

TEST_F(CliRenderTest, PlaneHasIdealSpeedup64) {
  const RunResult r = runMrr(tiny({"render", "--scene", "builtin:plane", "--report", at("r.json")}), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const json j = json::parse(readFile(at("r.json")));
  EXPECT_EQ(j["shaded_pixels_total"].get<int64_t>(), 64 * 48 / 64);
  EXPECT_DOUBLE_EQ(j["ideal_speedup"].get<double>(), 64.0);
}

TEST_F(CliRenderTest, EveryEffectRendersWithStagesReportAndProbeTerms) {
  for (const std::string effect : {"ssm", "ssgi"}) {
    const std::string samples = effect == "ssm" ? "16" : "8";
    const RunResult r = runMrr(tiny({"render", "--scene", "builtin:demo", "--effect", effect, "--out", at(effect + ".exr"),
                                     "--shaded", at(effect + ".png"), "--stages", at(effect + "_stages.exr"),
                                     "--report", at(effect + ".json"), "--reference"},
                                    "64x48", samples),
                               dir);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json j = json::parse(readFile(at(effect + ".json")));
    EXPECT_EQ(j["effect"], effect);
    EXPECT_EQ(j["samples"].get<int>(), std::stoi(samples));
    EXPECT_TRUE(j.contains("error_vs_full"));
    EXPECT_TRUE(j.contains(effect));  // the effect's own parameters
    std::set<std::string> names;
    for (const ExrPart& p : readParts(at(effect + "_stages.exr"))) names.insert(p.name);
    EXPECT_TRUE(names.count("shadowmap") && names.count("shadowtest")) << effect;
    EXPECT_EQ(readImage(at(effect + ".exr")).channels, effect == "ssgi" ? 3 : 1);
    const RunResult probe =
        runMrr(tiny({"probe", "--scene", "builtin:demo", "--effect", effect, "--pixel", "30,30"}, "64x48", samples), dir);
    ASSERT_EQ(probe.status, 0) << describe(probe);
    EXPECT_NE(probe.out.find(effect == "ssm" ? "penumbra" : "senders"), std::string::npos) << probe.out;
  }
  // SSGI keeps the paper's levels: the half level is off.
  const json gi = json::parse(readFile(at("ssgi.json")));
  EXPECT_FALSE(gi["levels"][1]["enabled"].get<bool>());
}

TEST_F(CliRenderTest, PngOutIsWritten) {
  const RunResult r = runMrr(tiny({"render", "--scene", "builtin:boxes", "--out", at("final.png")}, "32x24"), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const std::string bytes = readFile(at("final.png"));
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(listTree(out), (std::set<std::string>{"final.png"}));
  const ImageF image = readImage(at("final.png"));
  EXPECT_EQ(image.width, 32);
  EXPECT_EQ(image.height, 24);
}

TEST_F(CliRenderTest, ProgressGoesToStderrWithoutQuiet) {
  const RunResult r = runMrr({"render", "--scene", "builtin:plane", "--size", "16x16", "--samples", "4", "--report",
                              at("r.json")},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  EXPECT_EQ(r.out, "") << "render writes nothing to stdout";
  EXPECT_NE(r.err.find("[mrr]"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
}

// ---- probe --------------------------------------------------------------------------------

TEST_F(CliRenderTest, ProbePrintsEveryStageAsText) {
  const RunResult r = runMrr(tiny({"probe", "--scene", "builtin:demo", "--pixel", "20,30"}), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  for (const char* word : {"pixel (20, 30)", "edges", "level 0", "level 3", "taps", "final"})
    EXPECT_NE(r.out.find(word), std::string::npos) << "probe output lacks \"" << word << "\":\n" << r.out;
  EXPECT_EQ(listTree(out), std::set<std::string>{}) << "probe writes no files";
}

TEST_F(CliRenderTest, ProbeJsonParses) {
  const RunResult r = runMrr(tiny({"probe", "--scene", "builtin:demo", "--pixel", "63,47", "--json"}), dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  json j;
  ASSERT_NO_THROW(j = json::parse(r.out)) << r.out;
  for (const char* key : {"pixel", "gbuffer", "edges", "levels", "final"})
    EXPECT_TRUE(j.contains(key)) << "probe JSON lacks " << key << ":\n" << j.dump(2);
  EXPECT_EQ(j["pixel"], json::array({63, 47}));
  ASSERT_TRUE(j["levels"].is_array());
  EXPECT_EQ(j["levels"].size(), 4u);
  for (const json& level : j["levels"]) EXPECT_TRUE(level.contains("taps")) << level.dump();
  // Every level prints the â its α is made of: α = min(â·w, 1) where a tap is rendered (the
  // coarsest level is the base, α = 1), so a reader can check the arithmetic.
  for (size_t l = 0; l + 1 < j["levels"].size(); ++l) {
    const json& level = j["levels"][l];
    ASSERT_TRUE(level.contains("a_hat")) << level.dump();
    const double aHat = level["a_hat"], w = level["w"], alpha = level["alpha"];
    bool rendered = false;
    for (const json& tap : level["taps"]) rendered = rendered || tap["S"].get<bool>();
    EXPECT_FLOAT_EQ(alpha, rendered ? std::min(aHat * w, 1.0) : 0.0) << level.dump();
  }
}

// ---- bad input ----------------------------------------------------------------------------

struct BadCase {
  std::string name;                // the ctest name
  std::vector<std::string> args;   // {in} and {out} stand for the input and output folders
  std::string expectSubstring;     // must appear in stderr's one error line
  RunEnv how = {};                 // environment, privileges
  bool needsGl = false;            // needs a working EGL device to reach the failure
};

std::ostream& operator<<(std::ostream& os, const BadCase& c) { return os << c.name; }

std::string substitute(std::string s, const std::string& in, const std::string& out) {
  for (auto [key, value] : {std::pair<std::string, std::string>{"{in}", in}, {"{out}", out}})
    for (size_t p; (p = s.find(key)) != std::string::npos;) s.replace(p, key.size(), value);
  return s;
}

// A tiny render of `scene` to {out}/o.exr, with `extra` options.
std::vector<std::string> renderArgs(const std::string& scene, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"render", "--scene", scene, "--out", "{out}/o.exr", "--size", "32x24",
                                   "--samples", "4", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// A quiet render of builtin:demo with only `extra` added (no size, samples or output given).
std::vector<std::string> demoWith(std::vector<std::string> extra) {
  std::vector<std::string> args = {"render", "--scene", "builtin:demo", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

const std::vector<BadCase> kBadCases = {
    // scene files
    {"MissingSceneFile", renderArgs("{in}/missing.gltf"), "missing.gltf"},
    // foveation and motion (SPEC §13)
    {"GazeOutsideTheFrame", renderArgs("builtin:demo", {"--gaze", "32,5"}), "--gaze 32,5: outside the 32x24 frame"},
    {"GazeNotAPixel", renderArgs("builtin:demo", {"--gaze", "3"}), "--gaze 3: expected X,Y"},
    {"PpdZero", renderArgs("builtin:demo", {"--ppd", "0", "--gaze", "3,3"}), "--ppd 0: must be > 0"},
    {"PpdNegative", renderArgs("builtin:demo", {"--ppd=-2"}), "--ppd -2: must be > 0"},
    {"PrevFrameOtherScene", renderArgs("builtin:demo", {"--prev-frame", "{in}/prev-other-scene.json"}),
     "its scene builtin:corner is not this frame's builtin:demo"},
    {"PrevFrameOtherSize", renderArgs("builtin:demo", {"--prev-frame", "{in}/prev-other-size.json"}),
     "its size 64x48 is not this frame's 32x24"},
    {"PanWithPrevFrame", renderArgs("builtin:demo", {"--pan", "0.1", "--prev-frame", "{in}/prev-other-size.json"}),
     "--pan: not with --prev-frame (each gives the previous camera; give one)"},
    {"PanTooFar", renderArgs("builtin:demo", {"--pan", "2e6"}), "must be in [-1e6, 1e6]"},
    {"DirectoryAsScene", renderArgs("{in}/folder.gltf"), "folder.gltf"},
    {"EmptyGltf", renderArgs("{in}/empty.gltf"), "empty.gltf"},
    {"GlbWrongMagic", renderArgs("{in}/magic.glb"), "magic.glb"},
    {"TruncatedGlb", renderArgs("{in}/truncated.glb"), "truncated.glb"},
    {"JsonNotGltf", renderArgs("{in}/notgltf.gltf"), "notgltf.gltf"},
    {"OutOfRangeIndex", renderArgs("{in}/badindex.gltf"), "badindex.gltf"},
    {"NanPosition", renderArgs("{in}/nanposition.gltf"), "nanposition.gltf"},
    {"InfPosition", renderArgs("{in}/infposition.gltf"), "infposition.gltf"},
    {"BadBufferUri", renderArgs("{in}/baduri.gltf"), "buffer 0: file no-such-buffer.bin not found (expected at {in}/no-such-buffer.bin)"},
    {"BufferShorterThanAccessor", renderArgs("{in}/shortbuffer.gltf"), "shortbuffer.gltf"},
    {"WrongComponentType", renderArgs("{in}/componenttype.gltf"), "componenttype.gltf"},
    {"QuantizedWithoutExtension", renderArgs("{in}/quantized.gltf"),
     "mesh 'tri' primitive 0 POSITION accessor 0 has componentType UNSIGNED_BYTE, which needs KHR_mesh_quantization"},
    {"UnknownRequiredExtension", renderArgs("{in}/extension.gltf"), "requires glTF extension EXT_foo_bar, which mrr does not read"},
    {"CorruptMeshopt", renderArgs("{in}/meshopt.gltf"), "EXT_meshopt_compression): the ATTRIBUTES data is corrupt"},
    {"CorruptDraco", renderArgs("{in}/draco.glb"), "(KHR_draco_mesh_compression): the data is corrupt"},
    {"ZeroAreaOnlyMesh", renderArgs("{in}/zeroarea.gltf"), "zeroarea.gltf"},
    {"EmptySceneNoMeshes", renderArgs("{in}/nomeshes.gltf"), "nomeshes.gltf"},
    {"UnknownBuiltin", renderArgs("builtin:nosuch"), "builtin:nosuch"},
    // sizes and counts
    {"SizeZero", demoWith({"--out", "{out}/o.exr", "--size", "0x10"}), "--size 0x10"},
    {"SizeNegative", demoWith({"--out", "{out}/o.exr", "--size", "-5x10"}), "--size -5x10"},
    {"SizeNotANumber", demoWith({"--out", "{out}/o.exr", "--size", "abcx10"}), "--size abcx10"},
    {"SizeTooLarge", demoWith({"--out", "{out}/o.exr", "--size", "16385x10"}), "16385"},
    {"SamplesZero", demoWith({"--out", "{out}/o.exr", "--size", "16x16", "--samples", "0"}), "--samples 0"},
    {"SamplesTooMany", demoWith({"--out", "{out}/o.exr", "--size", "16x16", "--samples", "1025"}), "--samples 1025"},
    {"SamplesNotANumber", demoWith({"--out", "{out}/o.exr", "--size", "16x16", "--samples", "abc"}),
     "--samples abc: expected a whole number"},
    {"ThreadsNegative", renderArgs("builtin:demo", {"--threads", "-1"}), "--threads"},
    {"ThreadsTooMany", renderArgs("builtin:demo", {"--threads", "1025"}), "--threads"},
    {"SizeTrailingX", demoWith({"--out", "{out}/o.exr", "--size", "16x16x"}), "--size 16x16x"},
    // choices
    {"UnknownEffect", renderArgs("builtin:demo", {"--effect", "foo"}), "--effect foo"},
    {"SsmSamplesNotSquare", renderArgs("builtin:demo", {"--effect", "ssm", "--samples", "150"}), "square"},
    {"SsgiSamplesTooMany", renderArgs("builtin:demo", {"--effect", "ssgi", "--samples", "9000"}), "--samples 9000"},
    {"ShadowMapTooSmall", renderArgs("builtin:demo", {"--effect", "ssm", "--shadow-map-size", "8"}), "--shadow-map-size"},
    {"LightAngleZero", renderArgs("builtin:demo", {"--effect", "ssm", "--light-angle", "0"}), "--light-angle"},
    {"UnknownMode", renderArgs("builtin:demo", {"--mode", "foo"}), "--method foo"},
    {"UnknownMethod", renderArgs("builtin:demo", {"--method", "uniform-3"}), "--method uniform-3"},
    {"BadNeverSlower", renderArgs("builtin:demo", {"--never-slower", "maybe"}), "--never-slower maybe"},
    {"MissingCostModel", renderArgs("builtin:demo", {"--cost-model", "/nonexistent/costs.json"}), "--cost-model"},
    {"CostModelNotACostModel", renderArgs("builtin:demo", {"--cost-model", "{in}/notgltf.gltf"}),
     "--cost-model {in}/notgltf.gltf: [json.exception.out_of_range.403] key 'effects' not found"},
    {"CostModelMissingKey", renderArgs("builtin:demo", {"--cost-model", "{in}/costs-missing-key.json"}),
     "--cost-model {in}/costs-missing-key.json: [json.exception.out_of_range.403] key 'ns_per_blend_pixel' not found"},
    {"CostModelSparseFactor", renderArgs("builtin:demo", {"--cost-model", "{in}/costs-sparse-factor.json"}),
     "--cost-model {in}/costs-sparse-factor.json: effects.ssgi.sparse_factor: 2.500000 is outside [1, 2]"},
    {"UnknownPath", renderArgs("builtin:demo", {"--path", "foo"}), "--path foo"},

    {"DisableLevelZero", renderArgs("builtin:demo", {"--disable-level", "0"}), "--disable-level 0"},
    {"CameraOutOfRange", renderArgs("builtin:demo", {"--camera", "5"}), "--camera 5"},
    {"DisableLevelFour", renderArgs("builtin:demo", {"--disable-level", "4"}), "--disable-level 4"},
    {"EyeWithoutTarget", renderArgs("builtin:demo", {"--eye", "0,1,5"}), "--target"},
    {"EyeMalformed", renderArgs("builtin:demo", {"--eye", "1,2", "--target", "0,0,0"}), "--eye 1,2"},
    {"BlendMaterialsUnknown", renderArgs("builtin:demo", {"--blend-materials", "glass"}),
     "--blend-materials glass: expected opaque or skip"},
    {"LightDirZero", renderArgs("builtin:demo", {"--light-dir", "0,0,0"}), "--light-dir: needs a direction of non-zero length"},
    {"LightDirMalformed", renderArgs("builtin:demo", {"--light-dir", "0,1"}), "--light-dir 0,1"},
    {"FovOutOfRange", renderArgs("builtin:demo", {"--fov", "180"}), "--fov"},
    // outputs
    {"OutIntoMissingDirectory", demoWith({"--size", "16x16", "--out", "{out}/nodir/o.exr"}), "nodir"},
    {"OutIsADirectory", demoWith({"--size", "16x16", "--out", "{in}/isdir.exr"}), "is a directory"},
    {"OutIntoReadOnlyDirectory", demoWith({"--size", "16x16", "--out", "{in}/readonly/o.exr"}), "readonly", {.unprivileged = true}},
    {"ReportIntoReadOnlyDirectory", demoWith({"--size", "16x16", "--report", "{in}/readonly/r.json"}), "readonly", {.unprivileged = true}},
    {"OutUnsupportedExtension", demoWith({"--size", "16x16", "--out", "{out}/o.tiff"}), ".tiff"},
    {"OutJsonExtension", demoWith({"--size", "16x16", "--out", "{out}/o.json"}), "o.json"},
    {"StagesNotExr", demoWith({"--size", "16x16", "--stages", "{out}/st.png"}), "--stages"},
    {"NothingToWrite", demoWith({"--size", "16x16"}), "nothing to write"},
    // the GL path: no EGL vendor library at all (glvnd finds none), on a render and a probe
    {"GpuNoEglVendor", renderArgs("builtin:demo", {"--path", "gpu"}), "no EGL device", {.env = {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json"}}},
    {"GpuNoEglVendorProbe", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                             "--path", "gpu", "--pixel", "5,5"}, "no EGL device", {.env = {"__EGL_VENDOR_LIBRARY_DIRS=/nonexistent"}}},
    {"EffectCapOutOfRange", demoWith({"--size", "16x16", "--out", "{out}/o.exr", "--method", "mrr-effect",
                                      "--effect-cap", "99"}),
     "--effect-cap 99: must be in [0, 64]"},
    {"EffectPosteriorOutOfRange", demoWith({"--size", "16x16", "--out", "{out}/o.exr", "--method", "mrr-effect",
                                            "--effect-posterior", "200"}),
     "--effect-posterior 200: must be in [0, 100]"},
    {"EffectPosteriorFinestOutOfRange", demoWith({"--size", "16x16", "--out", "{out}/o.exr", "--method", "mrr-effect",
                                                  "--effect-posterior-finest", "4"}),
     "--effect-posterior-finest 4: must be in [0, 3]"},
    {"BenchUnknownVariant", {"bench", "--paths", "cpu", "--methods", "full", "mrr-effect+q"},
     "--methods mrr-effect+q: mrr-effect has no variant +q (it takes +cN: the widening's cap"},
    {"GpuTimingUnknown", demoWith({"--size", "16x16", "--out", "{out}/o.exr", "--path", "gpu", "--gpu-timing", "tsc"}),
     "--gpu-timing tsc"},
    {"BenchGpuTimingUnknown", {"bench", "--paths", "gpu", "--gpu-timing", "tsc"}, "--gpu-timing tsc"},
    // memory: the estimate is checked before the scene is loaded or anything allocated
    {"MemoryOverLimitOption", demoWith({"--size", "1280x720", "--out", "{out}/o.exr", "--memory-limit", "0.01"}),
     "over the memory limit"},
    {"MemoryOverLimitEnvironment", demoWith({"--size", "16384x16384", "--effect", "ssgi", "--out", "{out}/o.exr"}),
     "MRR_MEMORY_LIMIT", {.env = {"MRR_MEMORY_LIMIT=16"}}},
    {"MemoryLimitNotPositive", demoWith({"--size", "16x16", "--out", "{out}/o.exr", "--memory-limit", "-1"}),
     "--memory-limit"},
    {"MemoryLimitEnvironmentGarbage", demoWith({"--size", "16x16", "--out", "{out}/o.exr"}), "MRR_MEMORY_LIMIT=lots", {.env = {"MRR_MEMORY_LIMIT=lots"}}},
    // planted shader faults (gpu/faults.h): a compile error, reported with the stage and file
    {"GpuShaderCompileError", renderArgs("builtin:demo", {"--path", "gpu"}), "gbuffer.frag does not compile",
     {.env = {"MRR_GPU_FAULT=compile-error"}}, true},
    {"GpuUnknownPlantedFault", renderArgs("builtin:demo", {"--path", "gpu"}), "MRR_GPU_FAULT=nosuch",
     {.env = {"MRR_GPU_FAULT=nosuch"}}, true},
    // The user's shaders (--shaders DIR) and another renderer's stages (--against FILE)
    {"ShadersMissingFolder", renderArgs("builtin:demo", {"--path", "gpu", "--shaders", "{in}/nosuch"}),
     "--shaders {in}/nosuch: no such folder"},
    {"ShadersOnTheOracle", renderArgs("builtin:demo", {"--shaders", "{in}"}), "the shaders are the port's"},
    {"AgainstMissingFile", {"compare", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                            "--against", "{in}/nosuch.exr"}, "--against {in}/nosuch.exr: no such file or folder"},
    {"AgainstNotAStagesFile", {"compare", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                               "--against", "{in}/beauty.exr"}, "--against {in}/beauty.exr: not a stages file"},
    {"AgainstNotAnImage", {"compare", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                           "--against", "{in}/notgltf.gltf"}, "notgltf.gltf"},
    {"AgainstEveryEffect", {"compare", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                            "--effect", "all", "--against", "{in}/beauty.exr"}, "one effect at a time"},
    {"ProbeAgainstWithoutBoth", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                                 "--pixel", "5,5", "--against", "{in}/beauty.exr"}, "add --path both"},
    // probe
    {"ProbePixelOutside", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q", "--pixel",
                           "32,5"}, "--pixel 32,5"},
    {"ProbePixelNegative", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                            "--pixel=-1,5"}, "--pixel -1,5"},
    {"ProbePixelMalformed", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                             "--pixel", "12;7"}, "--pixel 12;7"},
    {"ProbePixelThreeNumbers", {"probe", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                                "--pixel", "1,2,3"}, "--pixel 1,2,3"},
    // the command line itself: every usage error is one line and status 2
    {"NoCommand", {}, "a command is required: render, probe, compare"},
    // frame files: one line naming the file and the key, nothing written
    {"FrameUnknownKey", demoWith({"--out", "{out}/o.exr", "--frame", "{in}/unknown-key.json"}), "unknown key \"colour\""},
    {"FrameZeroViewDirection", demoWith({"--out", "{out}/o.exr", "--frame", "{in}/no-view.json"}),
     "a zero-length view direction"},
    {"FrameNegativeSize", demoWith({"--out", "{out}/o.exr", "--frame", "{in}/negative-size.json"}), "\"size\" -64x48"},
    {"FrameNotAnObject", demoWith({"--out", "{out}/o.exr", "--frame", "{in}/not-a-frame.json"}), "a JSON object"},
    {"FrameMissing", demoWith({"--out", "{out}/o.exr", "--frame", "{in}/absent.json"}), "absent.json: cannot read"},
    // mrr info
    {"InfoWithoutScene", {"info"}, "info: scene is required"},
    {"InfoMissingFile", {"info", "{in}/absent.gltf"}, "absent.gltf: no such file"},
    {"InfoZeroSize", {"info", "builtin:demo", "--size", "0x90"}, "--size 0x90"},
    {"MisspelledCommand", {"rendr", "--scene", "builtin:demo"}, "unknown command rendr (did you mean render?)"},
    {"UnknownCommand", {"draw", "--scene", "builtin:demo"}, "unknown command draw (expected render, probe"},
    {"UnexpectedArgument", demoWith({"--out", "{out}/o.exr", "extra"}), "render: unexpected argument extra"},
    {"MisspelledOption", demoWith({"--out", "{out}/o.exr", "--sampels", "16"}),
     "render: unknown option --sampels (did you mean --samples?)"},
    {"MisspelledOptionWithValue", demoWith({"--out", "{out}/o.exr", "--szie=16x16"}),
     "render: unknown option --szie (did you mean --size?)"},
    {"UnknownOption", demoWith({"--out", "{out}/o.exr", "--frobnicate"}), "render: unknown option --frobnicate"},
    {"ProbeWithoutPixel", {"probe", "--scene", "builtin:demo", "--size", "32x24", "-q"}, "probe: --pixel is required"},
    {"OptionWithoutValue", demoWith({"--out", "{out}/o.exr", "--size"}), "render: --size: needs a value"},
    // bench: options checked before any scene is loaded
    {"BenchRepeatsZero", {"bench", "--repeats", "0"}, "--repeats"},
    {"BenchSsmSweepNotSquare", {"bench", "--ssm-sweep", "150"}, "square"},
    {"BenchUnknownMethod", {"bench", "--methods", "mrr", "half"}, "--method half"},
    {"BenchUnknownPath", {"bench", "--paths", "tpu"}, "--paths tpu"},
    {"BenchFramesOne", {"bench", "--frames", "1"}, "--frames"},
    {"BenchJsonBadExtension", {"bench", "--quick", "--json", "{out}/figures.txt"}, "figures.txt"},
    // --report: the pages need matplotlib and Jinja2 under /usr/bin/python3 (MRR_PYTHON names
    // another interpreter); checked before anything renders, so nothing is written
    {"CompareReportWithoutPython", {"compare", "--scene", "builtin:demo", "--size", "32x24", "--samples", "4", "-q",
                                    "--report", "{out}"},
     "--report needs matplotlib and Jinja2 (Debian: apt-get install python3-matplotlib python3-jinja2)",
     {.env = {"MRR_PYTHON=/nonexistent/python3"}}},
    {"BenchReportWithoutPackages", {"bench", "--quick", "--report", "{out}/report"},
     "--report needs matplotlib and Jinja2", {.env = {"MRR_PYTHON=/bin/false"}}},
};

class CliBadInputTest : public ::testing::TestWithParam<BadCase> {};

// Whether the GL path works here (an EGL device with GL 3.3 core), asked of the binary once.
bool glAvailable(const std::string& dir) {
  static const bool available = [&] {
    return runMrr({"render", "--scene", "builtin:plane", "--path", "gpu", "--size", "8x8", "--samples", "1", "-q",
                   "--out", (fs::path(dir) / "gl-probe.exr").string()},
                  dir)
               .status == 0;
  }();
  return available;
}

TEST_P(CliBadInputTest, FailsWithOneLineAndWritesNothing) {
  const BadCase& c = GetParam();
  const std::string dir = test::scratchDir();
  if (c.needsGl && !glAvailable(dir)) {
    const char* require = std::getenv("MRR_REQUIRE_GL");
    if (require && std::string(require) == "1") FAIL() << "no EGL device, and MRR_REQUIRE_GL=1";
    GTEST_SKIP() << "no EGL device with GL 3.3 core here: this case needs the GL path to start";
  }
  fs::remove(fs::path(dir) / "gl-probe.exr");
  const std::string in = (fs::path(dir) / "in").string();
  const std::string out = (fs::path(dir) / "out").string();
  fs::create_directories(in);
  fs::create_directories(out);
  writeBadInputs(in);
  const std::set<std::string> inBefore = listTree(in);

  std::vector<std::string> args;
  for (const std::string& a : c.args) args.push_back(substitute(a, in, out));
  const RunResult r = runMrr(args, dir, c.how);

  ASSERT_TRUE(r.exited) << "crashed\n" << describe(r);
  EXPECT_NE(r.status, 0) << describe(r);
  EXPECT_EQ(r.out, "") << "nothing on stdout for an error\n" << describe(r);
  const std::string expect = substitute(c.expectSubstring, in, out);
  {
    ASSERT_FALSE(r.err.empty()) << describe(r);
    EXPECT_EQ(r.err.back(), '\n') << describe(r);
    const std::string line = r.err.back() == '\n' ? r.err.substr(0, r.err.size() - 1) : r.err;
    EXPECT_EQ(line.find('\n'), std::string::npos) << "stderr is not exactly one line\n" << describe(r);
    EXPECT_EQ(line.rfind("mrr: error: ", 0), 0u) << describe(r);
    EXPECT_NE(line.find(expect), std::string::npos) << "error does not name \"" << expect << "\"\n" << describe(r);
    EXPECT_EQ(r.status, 2) << "MrrError exits with status 2\n" << describe(r);
  }
  EXPECT_EQ(listTree(out), std::set<std::string>{}) << "output left behind\n" << describe(r);
  EXPECT_EQ(listTree(in), inBefore) << "files created next to the inputs\n" << describe(r);

  // scripts/bad-inputs-doc.sh collects every case's command and message for docs/hardening.md.
  if (const char* log = std::getenv("MRR_BAD_INPUT_LOG"); log && *log) {
    auto placeholders = [&](std::string text) {
      for (auto [value, key] : {std::pair<std::string, std::string>{in, "IN"}, {out, "OUT"}})
        for (size_t p; (p = text.find(value)) != std::string::npos;) text.replace(p, value.size(), key);
      for (size_t p; (p = text.find('|')) != std::string::npos;) text.replace(p, 1, "\\|");
      return text;
    };
    std::string command = "mrr";
    for (const std::string& a : c.args) command += " " + substitute(a, "IN", "OUT");
    for (const std::string& e : c.how.env) command = e + " " + command;
    if (c.how.unprivileged) command += " (as a user without write access)";
    std::string first = r.err.substr(0, r.err.find('\n'));
    std::ofstream(log, std::ios::app) << "| " << c.name << " | `" << placeholders(command) << "` | "
                                      << r.status << " | " << placeholders(first) << " |\n";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, CliBadInputTest, ::testing::ValuesIn(kBadCases),
                         [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

// A failing render must not remove or damage an output that already exists.
TEST(CliOutputTest, FailedRunLeavesAnExistingOutputAlone) {
  const std::string dir = test::scratchDir();
  const std::string target = (fs::path(dir) / "keep.exr").string();
  writeFile(target, "previous contents");
  const RunResult r = runMrr({"render", "--scene", (fs::path(dir) / "missing.gltf").string(), "--out", target,
                              "--size", "16x16", "--samples", "4", "-q"},
                             dir);
  EXPECT_EQ(r.status, 2) << describe(r);
  EXPECT_EQ(readFile(target), "previous contents");
  expectNoTemporaries(dir);
}

// A camera inside a closed box sees only back faces at point-blank range: that is a valid
// frame, and it must render, every pixel finite, not fail.
TEST(CliOutputTest, CameraInsideGeometryRenders) {
  const std::string dir = test::scratchDir();
  const std::string out = (fs::path(dir) / "inside.exr").string();
  // builtin:boxes has a box of half-size 0.5 centred at (1.5, 0.5, 0.5).
  for (const char* effect : {"ssao", "ssm", "ssgi"}) {
    const RunResult r = runMrr(tiny({"render", "--scene", "builtin:boxes", "--eye", "1.5,0.5,0.5", "--target",
                                     "0,0.5,0", "--effect", effect, "--out", out, "--report",
                                     (fs::path(dir) / "inside.json").string()},
                                    "32x24", "4"),
                               dir);
    ASSERT_TRUE(r.exited) << describe(r);
    ASSERT_EQ(r.status, 0) << describe(r);
    const ImageF image = readImage(out);
    for (float v : image.data) ASSERT_TRUE(std::isfinite(v)) << effect;
  }
}

// The up-front estimate must track what a render really holds: the report's measured peak
// resident set, less that of a 16x16 run (libraries, the scene), within ±40% of it.
TEST(CliMemoryTest, EstimateTracksThePeakResidentSet) {
  const std::string dir = test::scratchDir();
  const std::string report = (fs::path(dir) / "r.json").string();
  auto memoryOf = [&](const std::string& effect, const std::string& size) {
    const RunResult r = runMrr({"render", "--scene", "builtin:demo", "--effect", effect, "--size", size, "--samples",
                                "16", "--stages", (fs::path(dir) / "st.exr").string(), "--report", report, "-q"},
                               dir);
    EXPECT_EQ(r.status, 0) << describe(r);
    const json j = json::parse(readFile(report));
    return std::pair{j["memory"]["estimate_bytes"].get<double>(), j["memory"]["peak_resident_bytes"].get<double>()};
  };
  const double base = memoryOf("ssao", "16x16").second;
  for (const char* effect : {"ssao", "ssgi"}) {
    const auto [estimate, peak] = memoryOf(effect, "1280x720");
    const double used = peak - base;
    EXPECT_GT(estimate, 0.6 * used) << effect << ": estimate " << estimate / 1048576 << " MiB, used " << used / 1048576;
    EXPECT_LT(estimate, 1.4 * used) << effect << ": estimate " << estimate / 1048576 << " MiB, used " << used / 1048576;
  }
}

// Kills a render with `signal` at the moment a temporary output file exists (a large
// multi-part EXR is being written), and checks the run dies of that signal leaving no file.
void killWhileWriting(int signal) {
  const std::string dir = test::scratchDir();
  const std::string out = (fs::path(dir) / "out").string();
  fs::create_directories(out);
  const std::string stages = (fs::path(out) / "stages.exr").string();
  const std::string errPath = (fs::path(dir) / "stderr.txt").string();
  for (int attempt = 0; attempt < 5; ++attempt) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const int fd = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) ::dup2(fd, 2);
      ::execl(MRR_BINARY, MRR_BINARY, "render", "--scene", "builtin:plane", "--mode", "full", "--size", "1920x1080",
              "--samples", "1", "--stages", stages.c_str(), "-q", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Poll for the temporary file: it exists only while OpenImageIO writes it.
    bool sent = false;
    int status = 0;
    for (int i = 0; i < 200000 && !sent; ++i) {
      if (::waitpid(child, &status, WNOHANG) == child) break;
      for (const std::string& name : listTree(out))
        if (name.find(".tmp-") != std::string::npos) {
          ::kill(child, signal);
          sent = true;
          break;
        }
      if (!sent) ::usleep(200);
    }
    if (!sent) {  // finished before a temporary was seen: the machine was too fast, try again
      ::waitpid(child, &status, 0);
      fs::remove_all(out);
      fs::create_directories(out);
      continue;
    }
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the run did not die of the signal; status " << status << "\n"
                                     << readFile(errPath);
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_EQ(listTree(out), std::set<std::string>{}) << "an interrupted write left a file behind";
    return;
  }
  GTEST_SKIP() << "no attempt caught the run while it was writing (five tries)";
}

TEST(CliInterruptTest, SigintWhileWritingLeavesNoFile) { killWhileWriting(SIGINT); }
TEST(CliInterruptTest, SigtermWhileWritingLeavesNoFile) { killWhileWriting(SIGTERM); }

// Killed while rendering (long before any write): nothing at all is written.
TEST(CliInterruptTest, SigtermWhileRenderingLeavesNoFile) {
  const std::string dir = test::scratchDir();
  const std::string out = (fs::path(dir) / "out").string();
  fs::create_directories(out);
  const std::string final = (fs::path(out) / "final.exr").string();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::execl(MRR_BINARY, MRR_BINARY, "render", "--scene", "builtin:demo", "--size", "1280x720", "--samples", "1024",
            "--out", final.c_str(), "-q", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::usleep(500 * 1000);
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_EQ(listTree(out), std::set<std::string>{});
}

// ---- compare: the oracle against the port, every stage (needs an EGL device) -----------------

#define MRR_REQUIRE_GL_FOR_CLI(dir)                                                                   \
  do {                                                                                              \
    if (!glAvailable(dir)) {                                                                        \
      const char* require = std::getenv("MRR_REQUIRE_GL");                                          \
      if (require && std::string(require) == "1") FAIL() << "no EGL device, and MRR_REQUIRE_GL=1"; \
      GTEST_SKIP() << "no EGL device with GL 3.3 core here";                                        \
    }                                                                                               \
  } while (0)

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

class CliCompareTest : public ::testing::TestWithParam<std::string> {};

// Every scene × the three effects × both modes, at a small size: every stage within the
// tolerance table (UPSTREAM rows, inherited differences, are allowed and shown).
TEST_P(CliCompareTest, EveryStagePassesForEveryEffectAndMode) {
  const std::string dir = test::scratchDir();
  MRR_REQUIRE_GL_FOR_CLI(dir);
  std::string scene = GetParam();
  const std::map<std::string, std::string> shared = {{"cornell", "cornell-box/CornellBox-Original.gltf"},
                                                     {"arcade", "sascha-arcade/subpass_scene_opaque.gltf"},
                                                     {"apartment", "dream-apartment/dream-apartment.glb"}};
  if (shared.count(scene) && !test::haveSharedScene(shared.at(scene)))
    GTEST_SKIP() << "shared scene missing: " << test::sharedScene(shared.at(scene));
  if (!shared.count(scene)) scene = "builtin:" + scene;
  for (const char* mode : {"multires", "full"}) {  // "multires": the old spelling, still accepted
    const RunResult r = runMrr({"compare", "--scene", scene, "--effect", "all", "--mode", mode, "--size", "96x64",
                                "--samples", "16", "--shadow-map-size", "512", "-q"},
                               dir);
    ASSERT_TRUE(r.exited) << describe(r);
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(countOf(r.out, "== compare "), 3) << describe(r);
    EXPECT_EQ(countOf(r.out, "\nPASS: "), 3) << describe(r);
    EXPECT_EQ(countOf(r.out, " FAIL "), 0) << describe(r);
    for (const char* stage : {"gbuffer.L0.depth", "raw.L0", "final"}) EXPECT_NE(r.out.find(stage), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, CliCompareTest,
                         ::testing::Values("demo", "plane", "slanted", "corner", "steps", "boxes", "shadows", "redwall",
                                           "cornell", "arcade", "apartment"),
                         [](const auto& info) { return info.param; });

// A frame whose effect is the same everywhere (a light from below the ground: every pixel in
// shadow) checks little; compare says so and how to light the view, and still judges it.
TEST(CliCompareWarnings, AConstantEffectIsNamedWithTheWayToLightTheView) {
  const std::string dir = test::scratchDir();
  MRR_REQUIRE_GL_FOR_CLI(dir);
  const std::vector<std::string> frame = {"compare", "--scene", "builtin:demo", "--effect", "ssm", "--size", "64x36",
                                          "--samples", "4", "--shadow-map-size", "256", "-q"};
  std::vector<std::string> dark = frame;
  dark.insert(dark.end(), {"--light-dir", "0,-1,0"});
  RunResult r = runMrr(dark, dir);
  ASSERT_TRUE(r.exited) << describe(r);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.err.find("mrr: warning: ssm: the oracle's effect is 0 at every surface pixel of the view"), std::string::npos)
      << describe(r);
  EXPECT_NE(r.err.find("--light-dir x,y,z"), std::string::npos) << describe(r);
  r = runMrr(frame, dir);  // the scene's own light: shadows vary, no warning
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << describe(r);
}

struct PlantedFault {
  std::string fault;   // MRR_GPU_FAULT (gpu/faults.cpp)
  std::string effect;
  std::string stage;   // the first failing stage compare must name (a prefix: the level may vary)
  std::string method = "mrr";
  std::vector<std::string> extra = {};  // more options of the compare
};
void PrintTo(const PlantedFault& f, std::ostream* os) { *os << f.fault; }

class CliPlantedFaultTest : public ::testing::TestWithParam<PlantedFault> {};

// Each planted shader bug makes compare fail, and names the stage where it starts.
TEST_P(CliPlantedFaultTest, CompareFailsAtTheStageWhereTheBugIs) {
  const PlantedFault& f = GetParam();
  const std::string dir = test::scratchDir();
  MRR_REQUIRE_GL_FOR_CLI(dir);
  std::vector<std::string> args = {"compare", "--scene", "builtin:demo", "--effect", f.effect, "--method", f.method,
                                   "--size", "96x64", "--samples", "16", "-q"};
  args.insert(args.end(), f.extra.begin(), f.extra.end());
  const RunResult r = runMrr(args, dir, {.env = {"MRR_GPU_FAULT=" + f.fault}});
  ASSERT_TRUE(r.exited) << describe(r);
  EXPECT_EQ(r.status, 1) << describe(r);
  const std::string marker = "FAIL: first failing stage ";
  const size_t at = r.out.find(marker);
  ASSERT_NE(at, std::string::npos) << describe(r);
  const std::string stage = r.out.substr(at + marker.size(), r.out.find('\n', at) - at - marker.size());
  EXPECT_EQ(stage.rfind(f.stage, 0), 0u) << "first failing stage " << stage << ", expected " << f.stage << "\n"
                                         << describe(r);
  RecordProperty("first_failing_stage", stage);
}

INSTANTIATE_TEST_SUITE_P(Faults, CliPlantedFaultTest,
                         ::testing::Values(PlantedFault{"half-pixel", "ssao", "upsample.L"},
                                           PlantedFault{"blend-weight", "ssao", "blendalpha.L"},
                                           PlantedFault{"uncorrected-blend", "ssao", "composite.L"},
                                           PlantedFault{"unmasked-bilinear", "ssao", "upsample.L"},
                                           PlantedFault{"ssao-bias-sign", "ssao", "raw.L"},
                                           PlantedFault{"pcf-one-short", "ssm", "raw.L"},
                                           PlantedFault{"ssgi-no-ndotl", "ssgi", "raw.L"},
                                           PlantedFault{"effect-reach-truncated", "ssao", "mask.L", "mrr-effect"},
                                           PlantedFault{"effect-dilate-strict", "ssm", "mask.L", "mrr-effect"},
                                           PlantedFault{"effect-only-keeps-edges", "ssao", "mask.L", "mrr-effect",
                                                        {"--effect-only"}},
                                           PlantedFault{"marks-2x2", "ssao", "marks.L", "mrr-effect",
                                                        {"--effect-posterior", "0.05"}},
                                           PlantedFault{"refine-marks-dropped", "ssgi", "mask.L", "mrr-effect",
                                                        {"--effect-posterior", "0.02"}}),
                         [](const auto& info) {
                           std::string name = info.param.fault;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

// probe --path both: on the open plane the paths agree everywhere; with the SSAO bias
// planted, the first value where they part is the coarsest level's raw AO (the plane has no
// edges, so only L3 is shaded; the rule off, which would shade so small a frame at full res).
TEST(CliProbeBothTest, MarksTheFirstStageWhereThePathsPart) {
  const std::string dir = test::scratchDir();
  MRR_REQUIRE_GL_FOR_CLI(dir);
  const std::vector<std::string> args = {"probe", "--path", "both", "--scene", "builtin:plane", "--size", "64x48",
                                         "--samples", "16", "--pixel", "31,23", "--never-slower", "off", "--json", "-q"};
  const RunResult clean = runMrr(args, dir);
  ASSERT_EQ(clean.status, 0) << describe(clean);
  const json a = json::parse(clean.out);
  EXPECT_TRUE(a["first_difference"].is_null()) << a["first_difference"];
  EXPECT_GT(a["rows"].size(), 20u);
  const RunResult faulty = runMrr(args, dir, {.env = {"MRR_GPU_FAULT=ssao-bias-sign"}});
  ASSERT_EQ(faulty.status, 0) << describe(faulty);
  const json b = json::parse(faulty.out);
  EXPECT_EQ(b["first_difference"], "L3.c_raw") << faulty.out.substr(0, 2000);
  // The text form marks it too.
  std::vector<std::string> text = args;
  text.erase(std::find(text.begin(), text.end(), "--json"));
  const RunResult shown = runMrr(text, dir, {.env = {"MRR_GPU_FAULT=ssao-bias-sign"}});
  // Grouped by step, under the shader that computes it: the level-3 effect, its raw value first.
  EXPECT_NE(shown.out.find("4. The effect, level 3 (ssao.frag)\n  c_raw "), std::string::npos) << shown.out;
  EXPECT_NE(shown.out.find("<- the first difference"), std::string::npos) << shown.out;
  EXPECT_LT(shown.out.find("1. The G-buffer at full resolution (gbuffer.frag)"), shown.out.find("2. Edges (edges.frag)"))
      << shown.out;
}

// The port's timing methods: the report names the one used, and each gives a figure for every
// stage (on llvmpipe the query figures themselves are wrong, docs/platform.md; what is tested is
// that the path runs and says so). auto picks the wall clock on llvmpipe. passes also times each
// program's draws within its stage (gpu/pass_clock.h): they lie inside their stage's time, name
// the shader that drew, and timing them changes no bit of the image.
TEST(CliGpuTimingTest, TheReportSaysWhichTimingWasUsed) {
  const std::string dir = test::scratchDir();
  MRR_REQUIRE_GL_FOR_CLI(dir);
  std::map<std::string, json> reports;
  for (const char* timing : {"wall", "query", "auto", "passes"}) {
    const std::string report = (fs::path(dir) / (std::string(timing) + ".json")).string();
    const RunResult r = runMrr({"render", "--scene", "builtin:demo", "--path", "gpu", "--size", "96x64", "--samples",
                                "8", "--never-slower", "off", "--gpu-timing", timing, "--out",
                                (fs::path(dir) / (std::string(timing) + ".exr")).string(), "--report", report, "-q"},
                               dir);
    ASSERT_EQ(r.status, 0) << describe(r);
    reports[timing] = json::parse(std::ifstream(report));
    const json& t = reports[timing]["timings_ms"];
    for (const char* stage : {"gbuffer.L0", "edges", "masks", "effect.L0", "blend", "shade", "total"})
      EXPECT_TRUE(t.contains(stage) && t[stage].is_number() && t[stage].get<double>() >= 0.0) << timing << " " << stage;
  }
  EXPECT_NE(reports["wall"]["timing_method"].get<std::string>().find("glFinish"), std::string::npos);
  EXPECT_NE(reports["query"]["timing_method"].get<std::string>().find("GL_TIME_ELAPSED"), std::string::npos);
  const std::string renderer = reports["auto"]["renderer"];
  if (renderer.find("llvmpipe") != std::string::npos)
    EXPECT_EQ(reports["auto"]["timing_method"], reports["wall"]["timing_method"]);
  EXPECT_FALSE(reports["wall"].contains("passes"));
  const json& passes = reports["passes"]["passes"];
  ASSERT_TRUE(passes.is_array() && !passes.empty()) << reports["passes"].dump();
  std::map<std::string, double> inStage;
  std::map<std::string, std::set<std::string>> shaders;
  for (const json& p : passes) {
    EXPECT_GE(p["calls"].get<int>(), 1) << p.dump();
    inStage[p["stage"]] += p["ms"].get<double>();
    shaders[p["stage"]].insert(p["shader"].get<std::string>());
  }
  const json& t = reports["passes"]["timings_ms"];
  for (const auto& [stage, ms] : inStage) {
    ASSERT_TRUE(t.contains(stage)) << "a pass in stage '" << stage << "', which the report does not time";
    EXPECT_LE(ms, t[stage].get<double>() + 1e-6) << stage;  // the stage's clock holds its draws
  }
  EXPECT_TRUE(shaders["masks"].count("masks.frag")) << reports["passes"].dump();
  EXPECT_TRUE(shaders["blend"].count("blend.frag")) << reports["passes"].dump();
  EXPECT_TRUE(shaders["gbuffer.L0"].count("gbuffer.frag")) << reports["passes"].dump();
  EXPECT_EQ(reports["passes"]["gl"]["readbacks"], 0);
  EXPECT_EQ(readImage((fs::path(dir) / "passes.exr").string()).data, readImage((fs::path(dir) / "wall.exr").string()).data)
      << "timing each draw changed the image";
}

TEST(CliOutputTest, NoSubcommandIsAnError) {
  const std::string dir = test::scratchDir();
  const RunResult r = runMrr({}, dir);
  ASSERT_TRUE(r.exited) << describe(r);
  EXPECT_NE(r.status, 0) << describe(r);
  EXPECT_FALSE(r.err.empty()) << describe(r);
}

TEST(CliOutputTest, HelpExitsZero) {
  const std::string dir = test::scratchDir();
  const RunResult r = runMrr({"render", "--help"}, dir);
  EXPECT_EQ(r.status, 0) << describe(r);
  for (const char* option : {"--scene", "--size", "--samples", "--out", "--stages", "--report", "--reference"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option << "\n" << r.out;
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

TEST(CliOutputTest, HelpSaysWhatMrrIs) {
  const std::string dir = test::scratchDir();
  const RunResult r = runMrr({"--help"}, dir);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_NE(r.out.find("the CPU oracle"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the OpenGL 3.3 port"), std::string::npos) << r.out;
  for (const char* command : {"render", "probe", "compare", "bench"})
    EXPECT_NE(r.out.find(command), std::string::npos) << command << "\n" << r.out;
}

// `--report DIR` makes DIR and its parents, as `mkdir -p` would.
TEST(CliOutputTest, CompareReportMakesItsFolder) {
  const std::string dir = test::scratchDir();
  if (!glAvailable(dir)) GTEST_SKIP() << "no EGL device with GL 3.3 core here: compare needs the GL path";
  const std::string report = (fs::path(dir) / "new" / "nested").string();
  const RunResult r = runMrr({"compare", "--scene", "builtin:plane", "--size", "16x16", "--samples", "1", "-q",
                              "--report", report},
                             dir);
  EXPECT_TRUE(r.exited) << describe(r);
  EXPECT_NE(r.status, 2) << describe(r);  // 0 or 1 is the comparison's verdict, not a usage error
  EXPECT_TRUE(fs::exists(fs::path(report) / "index.html")) << describe(r);
}

TEST(CliOutputTest, BenchReportMakesItsFolder) {
  const std::string dir = test::scratchDir();
  const std::string report = (fs::path(dir) / "new" / "nested").string();
  const RunResult r = runMrr({"bench", "--scenes", "builtin:plane", "--sizes", "16x16", "--effects", "ssao",
                              "--samples", "1", "--methods", "full", "mrr", "--cameras", "1", "--repeats", "1",
                              "--no-sweeps", "--frames", "0", "--no-stress", "--no-fovea", "--report", report},
                             dir);
  EXPECT_EQ(r.status, 0) << describe(r);
  EXPECT_TRUE(fs::exists(fs::path(report) / "index.html")) << describe(r);
}

// --cold renders full, tiles, mrr and mrr-effect (those --methods names) in fresh processes: each
// gets its cold effect time, speedup and process time (start to exit, which holds the frame); a
// method outside kColdMethods gets none; the Markdown's single-frame table shows them.
TEST(CliOutputTest, BenchColdRendersTilesMrrAndMrrEffectInFreshProcesses) {
  const std::string dir = test::scratchDir();
  const std::string json = (fs::path(dir) / "cold.json").string(), md = (fs::path(dir) / "cold.md").string();
  const RunResult r = runMrr({"bench", "--paths", "cpu", "--scenes", "builtin:demo", "--sizes", "32x24", "--effects", "ssao",
                              "--samples", "4", "--methods", "full", "uniform-1", "tiles", "mrr", "mrr-effect", "--cameras",
                              "1", "--repeats", "1", "--no-sweeps", "--frames", "0", "--no-stress", "--no-fovea", "--cold", "1", "--json",
                              json, "--markdown", md},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  std::set<std::string> cold;
  const nlohmann::json figures = nlohmann::json::parse(readFile(json));
  for (const auto& run : figures["runs"]) {
    const std::string m = run["method"].get<std::string>();
    if (run["cold_speedup"].get<double>() > 0.0) {
      cold.insert(m);
      EXPECT_GT(run["cold_process_ms"].get<double>(), run["cold_effect_ms"].get<double>()) << m << ": the process holds the frame";
    } else {
      EXPECT_EQ(run["cold_process_ms"].get<double>(), 0.0) << m;
    }
  }
  EXPECT_EQ(cold, (std::set<std::string>{"full", "tiles", "mrr", "mrr-effect"}));
  const std::string table = readFile(md);
  EXPECT_NE(table.find("cold process ms"), std::string::npos) << table;
  EXPECT_NE(table.find("| mrr-effect |"), std::string::npos) << table;
}

// The ablation's effect-only arm (+e, SPEC §12.3) on both paths of the bench: each path runs
// mrr-effect+e beside mrr-effect, the arm shades fewer pixels than both on each, and the port's
// count is the oracle's (the masks are exact). At 320×180 the never-slower rule keeps every frame
// on both paths' built-in models (at 160×90 the port's falls back to full, which would hide the arm).
TEST(CliOutputTest, BenchRunsTheEffectOnlyArmOnBothPaths) {
  const std::string dir = test::scratchDir();
  if (!glAvailable(dir)) GTEST_SKIP() << "no EGL device with GL 3.3 core here: the port's arm needs the GL path";
  const std::string json = (fs::path(dir) / "e.json").string();
  const RunResult r = runMrr({"bench", "--paths", "cpu", "gpu", "--scenes", "builtin:demo", "--sizes", "320x180",
                              "--effects", "ssao", "--methods", "mrr-effect+b0", "mrr-effect+e+b0", "--cameras", "1",
                              "--repeats", "1", "--no-sweeps", "--frames", "0", "--no-stress", "--no-fovea", "--json",
                              json},
                             dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  std::map<std::string, std::map<std::string, int64_t>> shaded;  // path → method → shaded pixels
  const nlohmann::json figures = nlohmann::json::parse(readFile(json));
  for (const auto& run : figures["runs"]) {
    const std::string path = run["path"].get<std::string>(), method = run["method"].get<std::string>();
    EXPECT_FALSE(run["fell_back_to_full"].get<bool>()) << path << " " << method;
    shaded[path][method] = run["shaded_pixels"].get<int64_t>();
  }
  // a priori (+b0): the budget prices with each path's own cost model, so its marks may differ
  for (const char* path : {"cpu", "gpu"}) {
    ASSERT_EQ(shaded[path].count("mrr-effect+e+b0"), 1u) << path << "\n" << describe(r);
    EXPECT_GT(shaded[path]["mrr-effect+e+b0"], 0) << path;
    EXPECT_LT(shaded[path]["mrr-effect+e+b0"], shaded[path]["mrr-effect+b0"]) << path;
  }
  EXPECT_EQ(shaded["gpu"], shaded["cpu"]);
}

// ---- mrr diff ------------------------------------------------------------------

// Two small PNGs that differ (a bright square moved by two pixels), and a third of another size.
class CliDiffTest : public CliRenderTest {
 protected:
  void SetUp() override {
    CliRenderTest::SetUp();
    ImageF a(64, 48, 3, 0.2f), b(64, 48, 3, 0.2f);
    for (int y = 16; y < 32; ++y)
      for (int x = 20; x < 36; ++x)
        for (int c = 0; c < 3; ++c) {
          a.at(x, y, c) = 0.9f;
          b.at(x + 2, y, c) = 0.9f;
        }
    writeImage(at("a.png"), a);
    writeImage(at("b.png"), b);
    writeImage(at("small.png"), ImageF(32, 48, 3, 0.2f));
  }
};

TEST_F(CliDiffTest, PrintsAndWritesTheFigures) {
  const RunResult r = runMrr({"diff", at("a.png"), at("b.png"), "--json", at("d.json"), "--map", at("map.png")}, dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  for (const char* word : {"RMS", "PSNR", "SSIM", "max |Δ|", "FLIP", "median", "q1", "q3", "sRGB values as stored"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << "\n" << r.out;
  const json j = json::parse(readFile(at("d.json")));
  std::set<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.insert(k);
  EXPECT_EQ(keys, (std::set<std::string>{"rms", "psnr", "ssim", "max_abs", "flip"})) << j.dump();
  std::set<std::string> flipKeys;
  for (const auto& [k, v] : j["flip"].items()) flipKeys.insert(k);
  EXPECT_EQ(flipKeys, (std::set<std::string>{"mean", "median", "q1", "q3", "max"})) << j.dump();
  EXPECT_GT(j["flip"]["mean"].get<double>(), 0.0);
  EXPECT_GT(j["rms"].get<double>(), 0.0);
  EXPECT_NEAR(j["max_abs"].get<double>(), 0.7, 1.0 / 255.0);  // 0.9 against 0.2, as bytes
  const ImageF map = readImage(at("map.png"));
  EXPECT_EQ(map.width, 64);
  EXPECT_EQ(map.height, 48);
  EXPECT_EQ(map.channels, 3);
  // --legend adds the colour bar below the map.
  const RunResult legend = runMrr({"diff", at("a.png"), at("b.png"), "--map", at("legend.png"), "--legend"}, dir);
  ASSERT_EQ(legend.status, 0) << describe(legend);
  EXPECT_GT(readImage(at("legend.png")).height, 48);
}

TEST_F(CliDiffTest, IdenticalImagesGiveZero) {
  const RunResult r = runMrr({"diff", at("a.png"), at("a.png"), "--json", at("same.json")}, dir);
  ASSERT_EQ(r.status, 0) << describe(r);
  const json j = json::parse(readFile(at("same.json")));
  EXPECT_EQ(j["rms"].get<double>(), 0.0);
  EXPECT_TRUE(j["psnr"].is_null()) << "infinite PSNR is written as null";
  EXPECT_EQ(j["flip"]["mean"].get<double>(), 0.0);
  EXPECT_EQ(j["flip"]["max"].get<double>(), 0.0);
}

TEST_F(CliDiffTest, FailAboveExitsOneWhenTheMeanIsAbove) {
  const RunResult above = runMrr({"diff", at("a.png"), at("b.png"), "--fail-above", "0.0001"}, dir);
  EXPECT_EQ(above.status, 1) << describe(above);
  EXPECT_NE(above.err.find("--fail-above"), std::string::npos) << above.err;
  const RunResult below = runMrr({"diff", at("a.png"), at("b.png"), "--fail-above", "0.9"}, dir);
  EXPECT_EQ(below.status, 0) << describe(below);
}

TEST_F(CliDiffTest, BadInputIsOneLineAndExitTwo) {
  const std::vector<std::vector<std::string>> cases = {
      {"diff", at("a.png"), at("small.png")},                        // different sizes
      {"diff", at("a.png"), at("absent.png")},                       // missing file
      {"diff", at("a.png"), at("b.png"), "--map", at("no/dir/m.png")},  // unwritable output
      {"diff", at("a.png"), at("b.png"), "--json", at("d.txt")},       // wrong extension
      {"diff", at("a.png")},                                         // usage: TEST missing
  };
  for (const auto& args : cases) {
    const RunResult r = runMrr(args, dir);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.err.rfind("mrr: error: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
  }
  const RunResult sizes = runMrr({"diff", at("a.png"), at("small.png")}, dir);
  EXPECT_NE(sizes.err.find("differ in size"), std::string::npos) << sizes.err;
}

// An EXR says how it was shown: colour is clamped (or tone-mapped) and sRGB-encoded.
TEST_F(CliDiffTest, ExrSaysHowItWasShown) {
  writeImage(at("a.exr"), ImageF(16, 16, 3, 2.0f));
  writeImage(at("b.exr"), ImageF(16, 16, 3, 0.5f));
  const RunResult clamp = runMrr({"diff", at("a.exr"), at("b.exr")}, dir);
  ASSERT_EQ(clamp.status, 0) << describe(clamp);
  EXPECT_NE(clamp.out.find("clamped to [0,1], then sRGB-encoded"), std::string::npos) << clamp.out;
  const RunResult tone = runMrr({"diff", at("a.exr"), at("b.exr"), "--tonemap", "reinhard"}, dir);
  ASSERT_EQ(tone.status, 0) << describe(tone);
  EXPECT_NE(tone.out.find("Reinhard"), std::string::npos) << tone.out;
}

}  // namespace
}  // namespace mrr
