#include "common/error.h"

#include <algorithm>

namespace mrr {

namespace {
std::string oneLine(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}
}  // namespace

MrrError::MrrError(const std::string& message) : std::runtime_error(oneLine(message)) {}

void require(bool condition, const std::string& message) {
  if (!condition) throw MrrError(message);
}

}  // namespace mrr
