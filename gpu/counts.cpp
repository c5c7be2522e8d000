#include "gpu/counts.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "common/error.h"
#include "gpu/program.h"
#include "gpu/traffic.h"

namespace mrr::gpu {

namespace {
constexpr int kFactor = 16;  // texels a side summed per fragment (counts.frag STEP 1)
constexpr int kGathered = 16;  // the gather pass sums an input of at most this many texels a side
}  // namespace

size_t CountBatch::add(Target perBlock) {
  size_t queued = 0;
  for (const Target& t : kept_) queued += static_cast<size_t>(t->targetCount());
  require(queued + static_cast<size_t>(perBlock->targetCount()) <= kMaxTargets, "gpu: counts: too many targets in one batch");
  kept_.push_back(std::move(perBlock));
  return queued * 4;
}

Target CountBatch::take(size_t i) {
  require(i < summed_.size() && summed_[i], "gpu: counts: no such summed target");
  return std::move(summed_[i]);
}

std::vector<int64_t> CountBatch::read() {
  // 1. Every texture to sum, each ≤ 16×16 texels after FACTOR×FACTOR tiles are summed, those of
  // one size together (one pass per step for all of them).
  std::vector<unsigned> textures;
  std::vector<std::pair<int, int>> sizes;
  for (const Target& t : kept_)
    for (int i = 0; i < t->targetCount(); ++i) {
      textures.push_back(t->texture(i));
      sizes.emplace_back(t->width(), t->height());
    }
  std::vector<Target> partial;
  std::vector<bool> done(textures.size(), false);
  for (size_t first = 0; first < textures.size(); ++first) {
    if (done[first]) continue;
    std::vector<size_t> group;  // the inputs of this size
    for (size_t k = first; k < textures.size(); ++k)
      if (!done[k] && sizes[k] == sizes[first]) group.push_back(k);
    for (size_t k : group) done[k] = true;
    int w = sizes[first].first, h = sizes[first].second;
    const int n = static_cast<int>(group.size());
    const unsigned program = scene_.program("counts.reduce." + std::to_string(n), "fullscreen.vert", "counts.frag",
                                            "#define STEP 1\n#define FACTOR " + std::to_string(kFactor) +
                                                "\n#define TARGETS " + std::to_string(n) + "\n");
    while (w > kGathered || h > kGathered) {
      w = (w + kFactor - 1) / kFactor;
      h = (h + kFactor - 1) / kFactor;
      Target next = scene_.target(w, h, std::vector<Texel>(static_cast<size_t>(n), Texel::Rgba32ui), false);
      next->bind();
      glUseProgram(program);
      for (int t = 0; t < n; ++t) {
        glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(t));
        glBindTexture(GL_TEXTURE_2D, textures[group[static_cast<size_t>(t)]]);
        glUniform1i(uniform(program, ("values" + std::to_string(t)).c_str()), t);
      }
      scene_.drawFullscreen();
      checkGl("counts");
      for (int t = 0; t < n; ++t) textures[group[static_cast<size_t>(t)]] = next->texture(t);
      partial.push_back(std::move(next));
    }
  }
  const int sources = static_cast<int>(textures.size());
  std::vector<int64_t> values(textures.size() * 4, 0);
  if (sources == 0) return values;
  // 2. One texel per queued target, in one row: a few integers, one small read.
  const unsigned program = scene_.program("counts.gather." + std::to_string(sources), "fullscreen.vert", "counts.frag",
                                          "#define STEP 2\n#define SOURCES " + std::to_string(sources) + "\n");
  const Target row = scene_.target(sources, 1, {Texel::Rgba32ui}, false);
  row->bind();
  glUseProgram(program);
  for (int k = 0; k < sources; ++k) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(k));
    glBindTexture(GL_TEXTURE_2D, textures[static_cast<size_t>(k)]);
    glUniform1i(uniform(program, ("source" + std::to_string(k)).c_str()), k);
  }
  scene_.drawFullscreen();
  checkGl("counts");
  std::vector<uint32_t> sums(static_cast<size_t>(sources) * 4);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  readCounts(sources, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, sums.data(), sums.size() * sizeof(uint32_t));
  checkGl("counts readback");
  for (size_t i = 0; i < sums.size(); ++i) values[i] = sums[i];
  summed_ = std::move(kept_);
  kept_.clear();
  return values;
}

}  // namespace mrr::gpu
