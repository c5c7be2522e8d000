#include "app/frame_file.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/image_io.h"

namespace mrr {

namespace {

enum class Kind { Text, Int, Number, Triple, Flag, Levels };

struct Key {
  const char* name;  // the JSON key; the option is "--" + name with '_' → '-'
  Kind kind;
};

// In the order the words are emitted.
const Key kKeys[] = {
    {"scene", Kind::Text},           {"effect", Kind::Text},          {"method", Kind::Text},
    {"size", Kind::Text},            {"samples", Kind::Int},          {"eye", Kind::Triple},
    {"target", Kind::Triple},        {"up", Kind::Triple},            {"fov", Kind::Number},
    {"light_dir", Kind::Triple},     {"light_angle", Kind::Number},   {"shadow_map_size", Kind::Int},
    {"ao_radius", Kind::Number},     {"gi_radius", Kind::Number},     {"ao_texel_depth", Kind::Flag},
    {"tau_n", Kind::Number},         {"tau_z", Kind::Number},         {"sigma2", Kind::Text},
    {"weights", Kind::Text},         {"disable_level", Kind::Levels},
    {"never_slower", Kind::Text},    {"blend_materials", Kind::Text}, {"flip_up", Kind::Flag},
};

std::string optionOf(const std::string& key) {
  std::string option = "--" + key;
  for (char& c : option)
    if (c == '_') c = '-';
  return option;
}

glm::vec3 tripleOf(const nlohmann::json& v, const std::string& where) {
  require(v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number(),
          where + ": expected [x, y, z]");
  const glm::vec3 t(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
  require(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z), where + ": not finite");
  return t;
}

}  // namespace

std::string exactFloat(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
  return text;
}

std::string exactTriple(float x, float y, float z) { return exactFloat(x) + "," + exactFloat(y) + "," + exactFloat(z); }

float exactDegrees(float radians) {
  float degrees = glm::degrees(radians);
  for (int step = 0; step < 64 && glm::radians(degrees) != radians; ++step)
    degrees = std::nextafter(degrees, glm::radians(degrees) < radians ? 1e9f : -1e9f);
  return degrees;
}

std::vector<std::string> frameArgs(const nlohmann::json& frame, const std::string& source) {
  require(frame.is_object(), source + ": a frame is a JSON object");
  for (const auto& [key, value] : frame.items()) {
    bool known = key == "mrr_frame";
    for (const Key& k : kKeys) known = known || key == k.name;
    std::string names;
    for (const Key& k : kKeys) names += std::string(names.empty() ? "" : ", ") + k.name;
    require(known, source + ": unknown key \"" + key + "\" (a frame has: " + names + ")");
  }
  if (frame.contains("mrr_frame"))
    require(frame["mrr_frame"] == 1, source + ": mrr_frame " + frame["mrr_frame"].dump() + ": this mrr reads version 1");
  std::vector<std::string> words;  // one "--option=value" (or "--flag") each
  for (const Key& k : kKeys) {
    if (!frame.contains(k.name)) continue;
    const nlohmann::json& v = frame[k.name];
    const std::string where = source + ": \"" + k.name + "\"";
    const std::string option = optionOf(k.name);
    switch (k.kind) {
      case Kind::Text:
        require(v.is_string(), where + ": expected a string");
        words.push_back(option + "=" + v.get<std::string>());
        break;
      case Kind::Int:
        require(v.is_number_integer() && v.get<int64_t>() > 0 && v.get<int64_t>() <= 1 << 20,
                where + ": expected a positive whole number");
        words.push_back(option + "=" + std::to_string(v.get<int64_t>()));
        break;
      case Kind::Number:
        require(v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0.0,
                where + ": expected a number >= 0");
        words.push_back(option + "=" + exactFloat(v.get<float>()));
        break;
      case Kind::Triple: {
        const glm::vec3 t = tripleOf(v, where);
        if (k.name == std::string("up") || k.name == std::string("light_dir"))
          require(glm::length(t) > 0.0f, where + ": a direction of length zero");
        words.push_back(option + "=" + exactTriple(t.x, t.y, t.z));
        break;
      }
      case Kind::Flag:
        require(v.is_boolean(), where + ": expected true or false");
        if (k.name == std::string("flip_up")) words.push_back(v.get<bool>() ? "--flip-up" : "--no-flip-up");
        else if (v.get<bool>()) words.push_back(option);
        break;
      case Kind::Levels:
        require(v.is_array(), where + ": expected a list of levels");
        for (const auto& l : v) {
          require(l.is_number_integer(), where + ": expected whole numbers");
          words.push_back(option + "=" + std::to_string(l.get<int64_t>()));
        }
        break;
    }
  }
  // The view direction: eye and target must differ (a zero-length view direction has no frame).
  if (frame.contains("eye") && frame.contains("target"))
    require(glm::length(tripleOf(frame["target"], source) - tripleOf(frame["eye"], source)) > 0.0f,
            source + ": \"eye\" and \"target\" coincide: a zero-length view direction");
  if (frame.contains("size")) {
    const std::string size = frame["size"].get<std::string>();
    int w = 0, h = 0;
    char x = 0, rest = 0;
    require(std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &rest) == 3 && x == 'x' && w > 0 && h > 0,
            source + ": \"size\" " + size + ": expected WIDTHxHEIGHT, both positive");
  }
  return words;
}

nlohmann::json readFrameFile(const std::string& path) {
  return readJsonObjectFile(path, "--frame");
}

std::vector<std::string> expandFrameFile(const std::vector<std::string>& args) {
  std::string file;
  std::vector<std::string> rest;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--frame") {
      require(i + 1 < args.size(), "--frame: needs a value");
      file = args[++i];
    } else if (args[i].rfind("--frame=", 0) == 0) {
      file = args[i].substr(8);
    } else {
      rest.push_back(args[i]);
    }
  }
  if (file.empty() || rest.empty()) return args;
  std::set<std::string> given;
  for (const std::string& a : rest)
    if (a.rfind("--", 0) == 0) given.insert(a.substr(0, a.find('=')));
  // --flip-up and --no-flip-up are one choice; --camera I and --eye/--target are another.
  if (given.count("--flip-up") || given.count("--no-flip-up")) given.insert({"--flip-up", "--no-flip-up"});
  if (given.count("--camera") || given.count("--eye") || given.count("--target"))
    given.insert({"--eye", "--target", "--up"});
  const std::vector<std::string> words = frameArgs(readFrameFile(file), "--frame " + file);
  std::vector<std::string> out = {rest[0]};  // the command
  for (const std::string& w : words)
    if (!given.count(w.substr(0, w.find('=')))) out.push_back(w);
  out.insert(out.end(), rest.begin() + 1, rest.end());
  return out;
}

}  // namespace mrr
