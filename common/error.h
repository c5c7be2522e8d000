#pragma once
// mrr reports every bad input as one MrrError with a one-line message; app/main.cpp prints
// it as "mrr: error: <message>" and exits with status 2. Nothing else is thrown on purpose.
#include <stdexcept>
#include <string>

namespace mrr {

class MrrError : public std::runtime_error {
 public:
  explicit MrrError(const std::string& message);
};

// Throws MrrError when `condition` is false. The message must name the file or option and
// the problem, on one line.
void require(bool condition, const std::string& message);

}  // namespace mrr
