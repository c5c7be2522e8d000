#include "frontend/frame_file.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/frame_params.h"
#include "common/image_io.h"

namespace mrr {

namespace {

glm::vec3 tripleOf(const nlohmann::json& v, const std::string& where) {
  require(v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number(),
          where + ": expected [x, y, z]");
  const glm::vec3 t(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
  require(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z), where + ": not finite");
  return t;
}

}  // namespace

std::string exactTriple(float x, float y, float z) { return exactFloat(x) + "," + exactFloat(y) + "," + exactFloat(z); }

float exactDegrees(float radians) {
  float degrees = glm::degrees(radians);
  for (int step = 0; step < 64 && glm::radians(degrees) != radians; ++step)
    degrees = std::nextafter(degrees, glm::radians(degrees) < radians ? 1e9f : -1e9f);
  return degrees;
}

std::vector<std::string> frameArgs(const nlohmann::json& frame, const std::string& source) {
  require(frame.is_object(), source + ": a frame is a JSON object");
  std::string names;  // the keys a frame has, for the message
  for (const FrameParamInfo& p : frameParams())
    if (p.frameFile) names += std::string(names.empty() ? "" : ", ") + std::string(p.key);
  for (const auto& [key, value] : frame.items()) {
    const FrameParamInfo* p = key == "mrr_frame" ? nullptr : findParam(key);
    require(key == "mrr_frame" || (p && p->frameFile && p->key == key),
            source + ": unknown key \"" + key + "\" (a frame has: " + names + ")");
  }
  if (frame.contains("mrr_frame"))
    require(frame["mrr_frame"] == 1, source + ": mrr_frame " + frame["mrr_frame"].dump() + ": this mrr reads version 1");
  std::vector<std::string> words;  // one "--option=value" (or "--flag") each
  for (const FrameParamInfo& k : frameParams()) {
    const std::string key(k.key);
    if (!k.frameFile || !frame.contains(key)) continue;
    const nlohmann::json& v = frame[key];
    const std::string where = source + ": \"" + key + "\"";
    const std::string option = optionName(k.param);
    switch (k.kind) {
      case ParamKind::Text:
      case ParamKind::Switch:    // "on" or "off"
      case ParamKind::PerLevel:  // "v0,v1,v2,v3", as the command line takes it
        require(v.is_string(), where + ": expected a string");
        words.push_back(option + "=" + v.get<std::string>());
        break;
      case ParamKind::Int:
        // each parameter's own range: its row's, checked as the value is set (setParam)
        require(v.is_number_integer() && std::abs(v.get<int64_t>()) <= int64_t{1} << 40, where + ": expected a whole number");
        words.push_back(option + "=" + std::to_string(v.get<int64_t>()));
        break;
      case ParamKind::Number:
        require(v.is_number() && std::isfinite(v.get<double>()), where + ": expected a finite number");
        words.push_back(option + "=" + exactFloat(v.get<float>()));
        break;
      case ParamKind::Triple: {
        const glm::vec3 t = tripleOf(v, where);
        if (k.param == Param::Up || k.param == Param::LightDir)
          require(glm::length(t) > 0.0f, where + ": a direction of length zero");
        words.push_back(option + "=" + exactTriple(t.x, t.y, t.z));
        break;
      }
      case ParamKind::Flag:
        require(v.is_boolean(), where + ": expected true or false");
        // flip_up: false is a choice too (--no-flip-up), not the absence of one.
        if (k.param == Param::FlipUp) words.push_back(v.get<bool>() ? option : optionName(Param::NoFlipUp));
        else if (v.get<bool>()) words.push_back(option);
        break;
      case ParamKind::Levels:
        require(v.is_array(), where + ": expected a list of levels");
        for (const auto& l : v) {
          require(l.is_number_integer(), where + ": expected whole numbers");
          words.push_back(option + "=" + std::to_string(l.get<int64_t>()));
        }
        break;
    }
  }
  // The view direction: eye and target must differ (a zero-length view direction has no frame).
  const std::string eye(paramInfo(Param::Eye).key), target(paramInfo(Param::Target).key);
  if (frame.contains(eye) && frame.contains(target))
    require(glm::length(tripleOf(frame[target], source) - tripleOf(frame[eye], source)) > 0.0f,
            source + ": \"eye\" and \"target\" coincide: a zero-length view direction");
  if (const std::string key(paramInfo(Param::Size).key); frame.contains(key)) {
    const std::string size = frame[key].get<std::string>();
    int w = 0, h = 0;
    char x = 0, rest = 0;
    require(std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &rest) == 3 && x == 'x' && w > 0 && h > 0,
            source + ": \"size\" " + size + ": expected WIDTHxHEIGHT, both positive");
  }
  return words;
}

nlohmann::json readFrameFile(const std::string& path) {
  return readJsonObjectFile(path, optionName(Param::Frame));
}

std::vector<std::string> expandFrameFile(const std::vector<std::string>& args) {
  const std::string frameOption = optionName(Param::Frame);
  std::string file;
  std::vector<std::string> rest;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == frameOption) {
      require(i + 1 < args.size(), frameOption + ": needs a value");
      file = args[++i];
    } else if (args[i].rfind(frameOption + "=", 0) == 0) {
      file = args[i].substr(frameOption.size() + 1);
    } else {
      rest.push_back(args[i]);
    }
  }
  if (file.empty() || rest.empty()) return args;
  std::set<std::string> given;
  for (const std::string& a : rest)
    if (a.rfind("--", 0) == 0) given.insert(a.substr(0, a.find('=')));
  // --flip-up and --no-flip-up are one choice; --camera I and --eye/--target are another.
  const auto o = [](Param p) { return optionName(p); };
  if (given.count(o(Param::FlipUp)) || given.count(o(Param::NoFlipUp))) given.insert({o(Param::FlipUp), o(Param::NoFlipUp)});
  if (given.count(o(Param::Camera)) || given.count(o(Param::Eye)) || given.count(o(Param::Target)))
    given.insert({o(Param::Eye), o(Param::Target), o(Param::Up)});
  const std::vector<std::string> words = frameArgs(readFrameFile(file), frameOption + " " + file);
  std::vector<std::string> out = {rest[0]};  // the command
  for (const std::string& w : words)
    if (!given.count(w.substr(0, w.find('=')))) out.push_back(w);
  out.insert(out.end(), rest.begin() + 1, rest.end());
  return out;
}

}  // namespace mrr
