#pragma once
// Stage 6 — the final shaded image, for viewing (SPEC §6 "Final shaded image"): full-res
// albedo and N·L combined with the effect buffer. Errors are reported on it too.
#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

// Linear RGB, W×H; background is a constant sky colour. Per effect:
//   SSAO: albedo × light × (0.45 · AO + 0.55 · N·L)
//   SSM:  albedo × light × (0.25 + 0.75 · N·L · V)
//   SSGI: albedo × (light × (0.1 + 0.9 · N·L · one-tap shadow) + indirect)
// `shadowLit` is the one-tap test (SSGI; empty otherwise).
ImageF shadeFinal(const GBuffer& g0, const ImageF& effect, const ImageU8& shadowLit, const View& view,
                  const DirectionalLight& light, Effect effectKind);

}  // namespace mrr
