#pragma once
// The port's mrr-effect masks (SPEC §12; gpu/shaders/effect_masks.frag), mirroring
// cpu_ref/effect_masks.h function by function: the footprint at full res, then each level's
// reach and its two-pass dilation. gpu/masks.cpp calls the dilation between the pyramid and
// the blur.
#include "common/camera.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Step 1, effectFootprint: F on the padded full-res grid (R32F), from level 0's G-buffer and
// E (channel `edgeChannel` of `edges`). SSM reads the light's map (`map`, `mapTexture`); the
// others pass 0.
Target drawFootprint(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned edges, int edgeChannel,
                     const ShadowMap* map, unsigned mapTexture, const View& view, const Constants& constants);

// Steps 2–3, levelReach and dilateByReach: M'_ℓ (R8) from M_ℓ (channel `maskChannel` of `mask`)
// and F_ℓ (`footprint`, R32F at level ℓ's size), widened by at most `cap` level pixels.
Target drawDilateByReach(const GpuScene& scene, unsigned mask, int maskChannel, unsigned footprint, int width,
                         int height, int levelScale, int cap);

}  // namespace mrr::gpu
