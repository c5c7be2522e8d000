#pragma once
// The port's SPEC §14 temporal term (gpu/shaders/temporal.frag), mirroring cpu_ref/temporal.h
// step by step: the previous frame's result reprojected where it shows the same surface, and
// blended into the pixels the coarser levels serve.
#include "common/frame.h"
#include "common/temporal.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Steps 1–6 over W×H: `final` the blend's result (W×H), `gbuffer0` level 0's targets, `stencil0`
// and `alpha0` level 0's S_0 and a_0, `history` the previous frame's (uploaded here). Target 0 holds
// final' (the effect's channels), target 1 h in rgb and λ_p in a.
Target drawTemporal(const GpuScene& scene, unsigned final, const Framebuffer& gbuffer0, unsigned stencil0,
                    unsigned alpha0, const FrameHistory& history, const View& view, const Constants& constants);

// The history this frame leaves for the next: `result` (W×H), level 0's depth and normal read back
// from its G-buffer and cropped to W×H, the view.
FrameHistory readHistory(const Framebuffer& gbuffer0, const ImageF& result, const View& view, const Constants& constants);

}  // namespace mrr::gpu
