#pragma once
// One frame, one order of stages, for both paths (after Filament's driver API and
// Falcor's render passes). renderFrame walks the pipeline's steps in the order of the stage
// list (common/stages.h), names and times each, reports progress, applies the never-slower rule
// and counts the shaded pixels; a FrameBackend does each step's work on its own images (the
// oracle's host images, the port's textures) and fills the FrameResult as far as the frame
// keeps stages. cpu_ref/pipeline.cpp and gpu/pipeline.cpp each implement one.
#include <functional>
#include <string>

#include "common/camera.h"
#include "common/frame.h"

namespace mrr {

// Runs `body` as the stage `name` (progress line, timing). Backends call it for their sub-steps.
using StageFn = std::function<void(const std::string& name, const std::function<void()>& body)>;

class FrameBackend {
 public:
  virtual ~FrameBackend() = default;

  // Times one stage's work into f.timings (default: a steady clock around `body`). The port
  // times GL work with glFinish or timer queries, resolved in endFrame.
  virtual void timeStage(FrameResult& f, const std::string& name, const std::function<void()>& body);
  virtual void endFrame(FrameResult& /*f*/) {}
  // The full-res G-buffer's hit flags, for the host's rule counts below (the oracle's own image).
  virtual const ImageU8& fullResHit(const FrameResult& f) { return f.levels[0].gbuffer.hit; }
  // SSM: what PCSS pays at each pixel of the 8×8 grid, into f.pcfSample, for the rule's H_a and
  // H_p (SPEC §11), called when the model prices PCF (e > 0). Each path asks its own PCSS:
  // cpu_ref/ssm.h pcfSample, ssm.frag with PCF_SAMPLE.
  virtual void samplePcf(FrameResult& f) = 0;
  // Mode mrr with the rule: the edge sample into f.edgeSample, for the early decision's estimate
  // of S_ℓ (SPEC §11): cpu_ref/edges.h edgeSample, edges.frag with EDGE_SAMPLE. Runs after the
  // shadow test (SSM's shadow edges count), and not at all where the floor rules the method out.
  virtual void sampleEdges(FrameResult& f) = 0;

  // SPEC §11's counts. The defaults count on the host with common/frame.h's readable functions
  // (countHits, countEdgeSample, countForRule) from the hit flags, the samples and S_ℓ; the port
  // reduces the same counts on the GPU and reads a few integers (gpu/rule.h), tested equal.
  // Before the edges: H, H_a, H_p, F and B_ℓ into f.counts; then, when `wantSample` is given and
  // says so of those counts (the floor does not already rule the method out), the edge sample
  // and Ê, R_ℓ (f.edgeSampled). Without `wantSample` the frame takes no sample.
  virtual void countEarly(FrameResult& f, const std::function<bool(const FrameCounts&)>& wantSample);
  // With the stencils known: |S_ℓ|, |S_ℓ ∩ hit| and the PCF shares into f.counts.
  virtual void countStencils(FrameResult& f, const FrameMasks& masks);
  // |S_ℓ|, their 4×2 blocks and the ideal speedups into f (FrameResult::countShadedPixels), once
  // the stencils are final; and idealSpeedupHit once the clock has stopped (countHitPixels). The
  // port counts a resident frame's on the GPU after the frame.
  virtual void countShaded(FrameResult& f) { f.countShadedPixels(); }
  // With `finalStencils` (f.counts so far), countStencils' counts on the frame's final stencils
  // (after the a-posteriori term) into it as well: SPEC §12.4's predicted time per level.
  virtual void countHitPixels(FrameResult& f, FrameCounts* finalStencils);

  // 1. The full-res G-buffer (the masks are made from it alone), then, once the stencils are
  // known, each coarser enabled level's, subsampled from it (SPEC §1).
  virtual void gbuffer(FrameResult& f) = 0;
  virtual void subsampleGBuffer(FrameResult& f, int level) = 0;
  // The light's shadow map, and the one-tap test at full res (SSM, SSGI).
  virtual void shadowMap(FrameResult& f) = 0;
  virtual void shadowTest(FrameResult& f) = 0;
  // 2. The edge image (modes mrr and tiles).
  virtual void edges(FrameResult& f) = 0;
  // 3. Each mask builder of the method table (common/methods.h MaskBuilder) on this backend; the
  // frame calls its method's (buildMasks). Each hands on the backend's own masks (FrameMasks: the
  // oracle's host images, the port's targets). full's and uniform-k's are constants of the
  // frame's size (fullModeMasks, uniformMasks: the defaults, on the host; the port draws them);
  // tiles' fill f.tileRates where the frame keeps host images; mrr-effect's widen M_ℓ by the
  // effect's footprint at the edges (docs/spec.md §12).
  virtual FrameMasks fullMasks(FrameResult& f);
  virtual FrameMasks uniformMasks(FrameResult& f);
  virtual FrameMasks tileMasks(FrameResult& f) = 0;
  virtual FrameMasks edgeMasks(FrameResult& f) = 0;
  virtual FrameMasks effectMasks(FrameResult& f) = 0;
  // The stencils the frame shades with, once the rule has decided (its method's, or full's after
  // a fallback): the port takes its targets, or uploads host images it did not draw.
  virtual void useMasks(FrameResult& /*f*/, const FrameMasks& /*masks*/, const StageFn& /*stage*/) {}
  virtual const char* pathName() const = 0;  // "cpu" or "gpu": CostModel::defaults' path
  // 4. The effect at level ℓ's stencilled pixels, and SSAO's blur (sub-steps named through `stage`).
  virtual void shadeLevel(FrameResult& f, int level, const StageFn& stage) = 0;
  // mrr-effect's a-posteriori term (SPEC §12.2): level ℓ's masks refined where its next coarser
  // enabled level's result varies, between that level's shading and ℓ's (cpu_ref/pipeline.cpp,
  // gpu/pipeline.cpp); the default refuses in one line.
  virtual void refineMasks(FrameResult& f, int level);
  // 5. Upsample and blend (the peers: their composition); 6. the shaded image.
  virtual void blend(FrameResult& f) = 0;
  // SPEC §14, the temporal term (Constants::temporal on): with the previous frame's `history` (null:
  // none), f.temporal from the blend's final image; then, either way, f.history for the next frame.
  // The default refuses in one line.
  virtual void temporal(FrameResult& f, const FrameHistory* history);
  virtual void shade(FrameResult& f) = 0;
};

// The mask builder `builder` of `backend` (FrameBackend::fullMasks … effectMasks).
FrameMasks buildMasks(FrameBackend& backend, MaskBuilder builder, FrameResult& f);

FrameResult renderFrame(FrameBackend& backend, const DirectionalLight& light, const Camera& camera,
                        const Constants& constants, const RenderOptions& options);

}  // namespace mrr
