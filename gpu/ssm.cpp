#include "gpu/ssm.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <vector>

#include "common/error.h"
#include "common/kernels.h"
#include "common/shader_constants.h"  // kMaxBlockerGrid, kMaxPcfGrid: ssm.frag's array sizes
#include "gpu/program.h"
#include "gpu/shadowmap.h"
#include "gpu/stencil.h"

namespace mrr::gpu {

namespace {
// The n tap factors of a grid (common/kernels.h: gridTapFactor) as a uniform array.
void setTapFactors(unsigned program, const char* name, int n) {
  std::vector<float> factors(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) factors[static_cast<size_t>(i)] = gridTapFactor(i, n);
  glUniform1fv(uniform(program, name), n, factors.data());
}

// ssm.frag's inputs up to the blocker search: for the effect and for the rule's sample (whose
// PCF_SAMPLE variant stops there, so the PCF grid's uniforms are not active in it).
void setBlockerSearchInputs(unsigned program, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                            const View& view, const Constants::Ssm& ssm) {
  bindTextures(program, {{"positionHit", gbuffer.texture(0)}, {"normalDepth", gbuffer.texture(1)}});
  bindShadowMap(program, map, mapTexture, 2, view, ssm.biasTexels);
  glUniform1f(uniform(program, "tanHalfAngle"), ssm.tanHalfAngle);
  glUniform1i(uniform(program, "blockerGrid"), ssm.blockerGrid);
  setTapFactors(program, "blockerFactors", ssm.blockerGrid);
}
}  // namespace

Target drawSsm(const GpuScene& scene, const Framebuffer& gbuffer, unsigned stencil, const ShadowMap& map,
               unsigned mapTexture, const View& view, const Constants::Ssm& ssm,
               const Cover& fill) {
  require(ssm.blockerGrid >= 1 && ssm.blockerGrid <= kMaxBlockerGrid && ssm.grid >= 1 && ssm.grid <= kMaxPcfGrid,
          "gpu: ssm grid sizes outside the shader's arrays");
  const unsigned program = scene.program("ssm", "fullscreen.vert", "ssm.frag");
  return drawStencilled(scene, stencil, gbuffer.width(), gbuffer.height(), Texel::R32f, program, "ssm",
                        [&] {
                          setBlockerSearchInputs(program, gbuffer, map, mapTexture, view, ssm);
                          glUniform1i(uniform(program, "grid"), ssm.grid);
                          setTapFactors(program, "pcfFactors", ssm.grid);
                        },
                        fill);
}

Target drawPcfSample(const GpuScene& scene, const Framebuffer& gbuffer0, const ShadowMap& map, unsigned mapTexture,
                     const View& view, const Constants::Ssm& ssm) {
  const unsigned program = scene.program("pcfsample", "fullscreen.vert", "ssm.frag", "#define PCF_SAMPLE\n");
  Target target = scene.target((gbuffer0.width() + kPcfSampleStep - 1) / kPcfSampleStep,
                               (gbuffer0.height() + kPcfSampleStep - 1) / kPcfSampleStep, 1, false, Texel::R8);
  target->bind();
  glUseProgram(program);
  setBlockerSearchInputs(program, gbuffer0, map, mapTexture, view, ssm);
  scene.drawFullscreen();
  checkGl("pcfsample");
  return target;
}

ImageU8 readPcfSample(const Framebuffer& sample) { return sample.readBytes(0); }

ImageF renderSsm(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const ShadowMap& map,
                 unsigned mapTexture, const View& view, const LevelConstants& /*level: S_ℓ has its size*/,
                 const Constants::Ssm& ssm) {
  return withHostStencil(stencil, 1,
                         [&](unsigned s) { return drawSsm(scene, gbuffer, s, map, mapTexture, view, ssm); });
}

}  // namespace mrr::gpu
