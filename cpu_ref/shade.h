#pragma once
// Stage 7 — the final shaded image, for viewing (SPEC §6 "Final shaded image"): full-res
// albedo and N·L combined with the effect buffer. Errors are reported on it too.
#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

// Linear RGB, W×H: albedo × light × (kAmbient · AO + kDirect · max(N·L, 0)); background is
// a constant sky colour.
ImageF shadeFinal(const GBuffer& g0, const ImageF& effect, const View& view, const DirectionalLight& light,
                  Effect effectKind);

}  // namespace mrr
