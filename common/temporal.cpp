#include "common/temporal.h"

namespace mrr {

Reprojection makeReprojection(const View& current, const View& previous) {
  // View space: x right, y up, looking down −z; world = eye + right·x + up·y − forward·z.
  // previous view of a world point w: (right'·(w − eye'), up'·(w − eye'), −forward'·(w − eye')).
  const auto d3 = [](const glm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); };
  const glm::dvec3 axes[3] = {d3(current.right), d3(current.up), -d3(current.forward)};  // columns: view → world
  const glm::dvec3 rows[3] = {d3(previous.right), d3(previous.up), -d3(previous.forward)};  // world → previous view
  const glm::dvec3 offset = d3(current.eye) - d3(previous.eye);
  Reprojection m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.r[i][j] = static_cast<float>(glm::dot(rows[i], axes[j]));
    m.t[i] = static_cast<float>(glm::dot(rows[i], offset));
  }
  return m;
}

}  // namespace mrr
