#pragma once
// Stage 4 — the SSAO sub-image (SPEC §4, §6): evaluated only where the stencil is set.
#include <functional>
#include <vector>

#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

// One sample's story, for `mrr probe`.
struct SsaoDetail {
  int samples = 0;
  int offscreen = 0;     // projected outside the level or behind the camera
  int background = 0;    // projected onto background
  int occluders = 0;     // depth test passed (buffer in front of the sample by > bias)
  float occlusion = 0.0f;  // Σ range-check weights of the occluders
  float rotation = 0.0f;   // per-pixel rotation angle, radians
};

// A texel as an occluder: its tangent plane, packed so one sample reads one 16-byte record.
struct OccluderPlane {
  glm::vec3 normal;  // view space
  float offset;      // N·P (≤ 0 on geometry); > 0 marks background
};
using OccluderPlanes = PixelVector<OccluderPlane>;
// Fills `planes` (resized to the level; its storage is reused from frame to frame).
void occluderPlanes(const GBuffer& g, OccluderPlanes& planes);
OccluderPlanes occluderPlanes(const GBuffer& g);

// AO at level pixel (x, y): 1 − occlusion / N; 1 on background (SPEC §1).
float ssaoAt(const GBuffer& g, const OccluderPlanes& planes, const View& view, const LevelConstants& level,
             const Constants::Ssao& ssao, int x, int y, SsaoDetail* detail = nullptr);

// The raw sub-image c_ℓ: AO where stencil = 1, 0 elsewhere (never read downstream).
// `onProgress(fraction)` is called (from any thread) each time another tenth is done.
ImageF renderSsao(const GBuffer& g, const OccluderPlanes& planes, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssao& ssao,
                  const std::function<void(double)>& onProgress = {});

}  // namespace mrr
