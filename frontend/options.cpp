#include "frontend/options.h"

#include <charconv>
#include <cmath>
#include <vector>

#include "common/error.h"

namespace mrr {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t i = 0; i <= s.size(); ++i)
    if (i == s.size() || s[i] == sep) {
      out.push_back(s.substr(start, i - start));
      start = i + 1;
    }
  return out;
}

namespace {

bool toInt(const std::string& s, int& v) {
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, v);
  return ec == std::errc() && p == end;
}
}  // namespace

std::pair<int, int> parseSize(const std::string& text) {
  const auto parts = split(text, 'x');
  int w = 0, h = 0;
  require(parts.size() == 2 && toInt(parts[0], w) && toInt(parts[1], h),
          "--size " + text + ": expected WIDTHxHEIGHT with whole numbers, e.g. 1280x720");
  return {w, h};
}

std::pair<int, int> parsePixel(const std::string& text) {
  const auto parts = split(text, ',');
  int x = 0, y = 0;
  require(parts.size() == 2 && toInt(parts[0], x) && toInt(parts[1], y),
          "--pixel " + text + ": expected X,Y with whole numbers, e.g. 640,360");
  return {x, y};
}

glm::vec3 parseVec3(const std::string& text, const std::string& option) {
  const auto parts = split(text, ',');
  glm::vec3 v(0.0f);
  bool ok = parts.size() == 3;
  for (size_t i = 0; ok && i < 3; ++i) {
    try {
      size_t used = 0;
      v[static_cast<int>(i)] = std::stof(parts[i], &used);
      ok = used == parts[i].size() && std::isfinite(v[static_cast<int>(i)]);
    } catch (const std::exception&) {
      ok = false;
    }
  }
  require(ok, option + " " + text + ": expected three finite numbers x,y,z");
  return v;
}

}  // namespace mrr
