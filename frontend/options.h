#pragma once
// Parsing of the command line's compound values, with one-line errors naming the option.
#include <glm/glm.hpp>

#include <string>
#include <utility>
#include <vector>

namespace mrr {

std::pair<int, int> parseSize(const std::string& text);    // "WxH"
std::pair<int, int> parsePixel(const std::string& text);   // "X,Y"
glm::vec3 parseVec3(const std::string& text, const std::string& option);  // "x,y,z"
// The pieces of `s` between the separators (empty pieces kept: "a,,b" is three).
std::vector<std::string> split(const std::string& s, char sep);

}  // namespace mrr
