#pragma once
// Stage 4 for indirect light — SSGI after Ritschel et al. 2009 (SPEC §6): N samples in the
// normal-oriented hemisphere of radius R; the pixel each sample projects to is a small sender
// patch (area πR²/N) carrying that pixel's direct light. Output: indirect RGB.
#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/shadowmap.h"

namespace mrr {

// The direct light each pixel of a level sends: albedo × max(N·L, 0) × one-tap shadow ×
// light colour (RGB, background 0).
ImageF directLight(const GBuffer& g, const ShadowMap& map, const View& view, const DirectionalLight& light,
                   float biasTexels);

struct SsgiDetail {
  int samples = 0;
  int offscreen = 0, background = 0;
  int senders = 0;                 // samples that contributed
  glm::vec3 strongest{0.0f};       // the largest single contribution
  glm::ivec2 strongestTexel{-1};   // its sender's level pixel
};

glm::vec3 ssgiAt(const GBuffer& g, const ImageF& direct, const View& view, const LevelConstants& level,
                 const Constants::Ssgi& ssgi, int x, int y, SsgiDetail* detail = nullptr);

ImageF renderSsgi(const GBuffer& g, const ImageF& direct, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssgi& ssgi);

}  // namespace mrr
