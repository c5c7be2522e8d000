#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "common/paths.h"

namespace fs = std::filesystem;

namespace mrr::test {

std::string scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "misc";
  for (char& c : name)
    if (c == '/') c = '_';
  fs::path dir = fs::path(MRR_TEST_TMP) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string sharedScene(const std::string& relative) {
  return (fs::path(sharedScenesDir()) / relative).string();
}

bool haveSharedScene(const std::string& relative) { return fs::exists(sharedScene(relative)); }

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i];
    const uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0u;
    const uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0u;
    const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

std::string glbFile(const std::string& json, const std::vector<uint8_t>& bin) {
  auto appendU32 = [](std::string& out, uint32_t value) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFFu);
  };
  std::string text = json;
  while (text.size() % 4 != 0) text += ' ';
  std::string data(bin.begin(), bin.end());
  while (data.size() % 4 != 0) data += '\0';
  std::string out;
  appendU32(out, 0x46546C67u);  // "glTF"
  appendU32(out, 2);
  appendU32(out, static_cast<uint32_t>(12 + 8 + text.size() + (data.empty() ? 0 : 8 + data.size())));
  appendU32(out, static_cast<uint32_t>(text.size()));
  appendU32(out, 0x4E4F534Au);  // "JSON"
  out += text;
  if (!data.empty()) {
    appendU32(out, static_cast<uint32_t>(data.size()));
    appendU32(out, 0x004E4942u);  // "BIN\0"
    out += data;
  }
  return out;
}

}  // namespace mrr::test
