#include "cpu_ref/foveation.h"

#include <algorithm>
#include <cmath>

#include "common/parallel.h"

namespace mrr {

namespace {
int64_t gazeDistance2(int x, int y, const Constants::Foveation& f) {
  const int64_t dx = x - f.gazeX, dy = y - f.gazeY;
  return dx * dx + dy * dy;
}
}  // namespace

float eccentricityAt(int x, int y, const Constants::Foveation& f) {
  if (!f.gaze) return 0.0f;
  return std::sqrt(static_cast<float>(gazeDistance2(x, y, f))) / f.ppd;
}

int foveationLevel(int x, int y, const Constants::Foveation& f) {
  if (!f.gaze || !f.foveate) return 0;
  const int64_t d2 = gazeDistance2(x, y, f);
  int level = 0;
  for (int l = 1; l < kLevelCount; ++l)
    if (d2 >= f.radius2[static_cast<size_t>(l)]) level = l;
  return level;
}

glm::vec2 motionAt(const GBuffer& g, int x, int y, const View& view, const View& previous, float scale) {
  if (!g.hit.at(x, y)) return {0.0f, 0.0f};
  const glm::vec3 world = view.toWorld(g.positionAt(x, y));
  const glm::vec3 p = previous.toView(world);
  if (!(-p.z > 0.0f)) return {kMotionBehind, kMotionBehind};
  const glm::vec2 q = previous.project(p);
  const glm::vec2 d = q - glm::vec2(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
  return {scale * d.x, scale * d.y};
}

int motionLevel(const glm::vec2& v, const Constants::Foveation& f) {
  if (!f.motion) return 0;
  const float v2 = v.x * v.x + v.y * v.y;
  int level = 0;
  for (int l = 1; l <= f.motionCap; ++l)
    if (v2 >= f.speed2[static_cast<size_t>(l)]) level = l;
  return level;
}

LevelLimit levelLimit(const GBuffer& g, const View& view, const Constants& c) {
  const Constants::Foveation& f = c.foveation;
  const int w = c.paddedWidth, h = c.paddedHeight;
  LevelLimit out;
  if (f.gaze) out.eccentricity = ImageF::uninitialised(w, h);
  if (f.motion) out.motion = ImageF::uninitialised(w, h);
  out.limit = ImageU8(w, h, kLimitChannels);
  const View previous = f.motion ? previousView(c, view) : View{};
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      // 1–2. the eye
      int fovea = 0;
      if (f.gaze) {
        out.eccentricity.at(x, y) = eccentricityAt(x, y, f);
        fovea = foveationLevel(x, y, f);
      }
      // 3–4. motion
      int moving = 0;
      if (f.motion) {
        const glm::vec2 v = motionAt(g, x, y, view, previous, f.motionScale);
        out.motion.at(x, y) = v.x == kMotionBehind ? kMotionBehind : std::sqrt(v.x * v.x + v.y * v.y);
        moving = motionLevel(v, f);
      }
      // 5. the limit
      out.limit.at(x, y, kLimitFovea) = static_cast<uint8_t>(fovea);
      out.limit.at(x, y, kLimitMotion) = static_cast<uint8_t>(moving);
      out.limit.at(x, y, kLimitLevel) = static_cast<uint8_t>(std::min(c.coarsestEnabled, std::max(fovea, moving)));
    }
  });
  return out;
}

void applyLevelLimit(Masks& masks, const ImageU8& limit, const Constants& c) {
  for (int l = 0; l < c.coarsestEnabled; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    ImageU8& m = masks[static_cast<size_t>(l)].mask;
    parallelFor(0, m.height, [&](int y) {
      const int py = levelSamplePixel(y, lc.scale);
      for (int x = 0; x < m.width; ++x)
        if (l < limit.at(levelSamplePixel(x, lc.scale), py, kLimitLevel)) m.at(x, y) = 0;
    });
  }
}

}  // namespace mrr
