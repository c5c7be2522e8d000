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
  const int targets = perBlock->targetCount();
  require(targets >= 1 && targets <= 4 && textures_.size() + static_cast<size_t>(targets) <= kMaxTargets,
          "gpu: counts: too many targets in one batch");
  const size_t first = textures_.size() * 4;
  // 1. Sum FACTOR×FACTOR tiles, every target at once, until each is at most 16×16 texels.
  const unsigned program = scene_.program("counts.reduce." + std::to_string(targets), "fullscreen.vert", "counts.frag",
                                          "#define STEP 1\n#define FACTOR " + std::to_string(kFactor) +
                                              "\n#define TARGETS " + std::to_string(targets) + "\n");
  Target input = std::move(perBlock);
  while (input->width() > kGathered || input->height() > kGathered) {
    const int w = (input->width() + kFactor - 1) / kFactor, h = (input->height() + kFactor - 1) / kFactor;
    Target next = scene_.target(w, h, std::vector<Texel>(static_cast<size_t>(targets), Texel::Rgba32ui), false);
    next->bind();
    glUseProgram(program);
    for (int t = 0; t < targets; ++t) {
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(t));
      glBindTexture(GL_TEXTURE_2D, input->texture(t));
      glUniform1i(uniform(program, ("values" + std::to_string(t)).c_str()), t);
    }
    scene_.drawFullscreen();
    checkGl("counts");
    input = std::move(next);
  }
  for (int t = 0; t < targets; ++t) textures_.push_back(input->texture(t));
  kept_.push_back(std::move(input));
  return first;
}

std::vector<int64_t> CountBatch::read() {
  const int sources = static_cast<int>(textures_.size());
  std::vector<int64_t> values(textures_.size() * 4, 0);
  if (sources == 0) return values;
  // 2. One texel per queued target, in one row: a few integers, one small read.
  const unsigned program = scene_.program("counts.gather." + std::to_string(sources), "fullscreen.vert", "counts.frag",
                                          "#define STEP 2\n#define SOURCES " + std::to_string(sources) + "\n");
  const Target row = scene_.target(sources, 1, {Texel::Rgba32ui}, false);
  row->bind();
  glUseProgram(program);
  for (int k = 0; k < sources; ++k) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(k));
    glBindTexture(GL_TEXTURE_2D, textures_[static_cast<size_t>(k)]);
    glUniform1i(uniform(program, ("source" + std::to_string(k)).c_str()), k);
  }
  scene_.drawFullscreen();
  checkGl("counts");
  std::vector<uint32_t> sums(static_cast<size_t>(sources) * 4);
  row->bind();
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  readCounts(sources, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, sums.data(), sums.size() * sizeof(uint32_t));
  checkGl("counts readback");
  for (size_t i = 0; i < sums.size(); ++i) values[i] = sums[i];
  textures_.clear();
  kept_.clear();
  return values;
}

}  // namespace mrr::gpu
