// The never-slower rule's built-in cost models (docs/spec.md §11): common/cost_models/*.json,
// compiled in and parsed by CostModel::defaults. Each parses, holds every figure the writer
// writes and no other, finite, and is byte for byte what `mrr bench --calibrate` would write of
// it; a figure survives the writer and the reader bit for bit.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "common/cost_model.h"
#include "common/error.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

const std::string kModelDir = std::string(MRR_SOURCE_DIR) + "/common/cost_models";

// Every number of a cost model's JSON by its key path ("effects.ssm.sparse_factor",
// "stencil_fill[1]"); strings by theirs in `strings`.
void flatten(const nlohmann::json& j, const std::string& at, std::map<std::string, double>& numbers,
             std::map<std::string, std::string>& strings) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) flatten(value, at.empty() ? key : at + "." + key, numbers, strings);
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) flatten(j[i], at + "[" + std::to_string(i) + "]", numbers, strings);
  } else if (j.is_number()) {
    numbers[at] = j.get<double>();
  } else if (j.is_string()) {
    strings[at] = j.get<std::string>();
  } else {
    ADD_FAILURE() << at << ": neither a number nor a string: " << j.dump();
  }
}

struct Flat {
  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
};
Flat flatten(const nlohmann::json& j) {
  Flat f;
  flatten(j, "", f.numbers, f.strings);
  return f;
}

std::set<std::string> keys(const Flat& f) {
  std::set<std::string> k;
  for (const auto& [key, v] : f.numbers) k.insert(key);
  for (const auto& [key, v] : f.strings) k.insert(key);
  return k;
}

// a and b hold the same figures, bit for bit (0.0 and -0.0 differ), and the same strings.
void expectBitIdentical(const CostModel& a, const CostModel& b, const std::string& what) {
  const Flat fa = flatten(a.toJson()), fb = flatten(b.toJson());
  ASSERT_EQ(keys(fa), keys(fb)) << what;
  for (const auto& [key, value] : fa.numbers)
    EXPECT_EQ(std::bit_cast<uint64_t>(value), std::bit_cast<uint64_t>(fb.numbers.at(key)))
        << what << ": " << key << " " << value << " vs " << fb.numbers.at(key);
  EXPECT_EQ(fa.strings, fb.strings) << what;
}

// The files in common/cost_models/, by path name ("cpu" for cpu.json).
std::map<std::string, std::string> modelFiles() {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(kModelDir))
    if (entry.path().extension() == ".json") files[entry.path().stem().string()] = entry.path().string();
  return files;
}

TEST(CostModelDefaults, OneFileForEachPath) {
  const std::map<std::string, std::string> files = modelFiles();
  std::set<std::string> paths;
  for (const auto& [path, file] : files) paths.insert(path);
  EXPECT_EQ(paths, (std::set<std::string>{"cpu", "gpu"}));
}

TEST(CostModelDefaults, ParseCompleteAndFinite) {
  // the figures the writer writes: those of any model
  const std::set<std::string> expected = keys(flatten(CostModel{}.toJson()));
  ASSERT_GT(expected.size(), 40u);
  for (const auto& [path, file] : modelFiles()) {
    SCOPED_TRACE(file);
    // the file as it is: every key the writer writes, and no other (a misspelt key would be
    // ignored by the reader and its figure left at 0)
    const nlohmann::json text = nlohmann::json::parse(test::readFile(file));
    const Flat onDisk = flatten(text);
    EXPECT_EQ(keys(onDisk), expected);
    for (const auto& [key, value] : onDisk.numbers) {
      EXPECT_TRUE(std::isfinite(value)) << key;
      EXPECT_GE(value, 0.0) << key << ": a cost, a fill or a spread is never negative";
    }
    EXPECT_FALSE(onDisk.strings.at("source").empty());
    // the model the rule uses is that file's
    const CostModel model = CostModel::defaults(path);
    EXPECT_EQ(model.source, onDisk.strings.at("source"));
    for (const EffectCost& e : model.effect) {
      EXPECT_GE(e.sparseFactor, kMinSparseFactor);
      EXPECT_LE(e.sparseFactor, kMaxSparseFactor);
      EXPECT_GT(e.nsPerShadedPixel, 0.0) << "every effect costs something per pixel";
    }
    for (double band : model.edgeBandFill) EXPECT_GT(band, 0.0);
  }
}

// The built-in file is exactly what `mrr bench --calibrate` writes of the model it holds
// (app/bench_command.cpp: toJson().dump(2) and a newline), so it can be replaced by a calibration
// run's output as is; and the compiled-in text is the file's (the model parsed from it writes
// the file back).
TEST(CostModelDefaults, AreTheWritersOutputByteForByte) {
  for (const auto& [path, file] : modelFiles()) {
    const CostModel model = CostModel::defaults(path);
    EXPECT_EQ(model.toJson().dump(2) + "\n", test::readFile(file)) << file << ": not in the writer's format, or stale";
  }
}

// Writer then reader, by value and through a file (`--cost-model FILE`), keeps every figure bit
// for bit.
TEST(CostModelDefaults, RoundTripThroughWriterAndReaderBitForBit) {
  const std::string dir = test::scratchDir();
  for (const char* path : {"cpu", "gpu"}) {
    const CostModel model = CostModel::defaults(path);
    expectBitIdentical(CostModel::fromJson(model.toJson()), model, std::string(path) + " by value");
    const std::string file = dir + "/" + path + ".json";
    std::ofstream(file) << model.toJson().dump(2) << "\n";
    expectBitIdentical(CostModel::fromFile(file), model, std::string(path) + " through " + file);
    expectBitIdentical(CostModel::fromFile(kModelDir + "/" + path + ".json"), model, std::string(path) + " from the repo's file");
  }
  // the comparison sees one bit
  CostModel a = CostModel::defaults("cpu"), b = a;
  b.nsPerBlendPixel = std::nextafter(a.nsPerBlendPixel, 1e9);
  EXPECT_NE(std::bit_cast<uint64_t>(a.nsPerBlendPixel), std::bit_cast<uint64_t>(b.nsPerBlendPixel));
  EXPECT_NE(flatten(a.toJson()).numbers.at("ns_per_blend_pixel"), flatten(b.toJson()).numbers.at("ns_per_blend_pixel"));
}

TEST(CostModelDefaults, ThePathsDiffer) {
  // two measurements, not one file twice
  EXPECT_NE(CostModel::defaults("cpu").toJson(), CostModel::defaults("gpu").toJson());
  EXPECT_NE(CostModel::defaults("cpu").source.find("cpu"), std::string::npos);
  EXPECT_NE(CostModel::defaults("gpu").source.find("gpu"), std::string::npos);
}

TEST(CostModelDefaults, AnotherPathIsRefusedNamingTheFiles) {
  try {
    CostModel::defaults("tpu");
    FAIL() << "no built-in model for tpu";
  } catch (const MrrError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tpu"), std::string::npos) << what;
    EXPECT_NE(what.find("common/cost_models/"), std::string::npos) << what;
    EXPECT_NE(what.find("cpu, gpu"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace mrr
