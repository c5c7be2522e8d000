#include "gpu/faults.h"

#include <cstdlib>

#include "common/error.h"
#include "common/stages.h"
#include "gpu/program.h"

namespace mrr::gpu {

const std::vector<ShaderFault>& shaderFaults() {
  static const std::vector<ShaderFault> faults = {
      {"compile-error", "gbuffer.frag", "if (transparentAt(surfaceTexcoord)) discard;",
       "if (transparentAt(surfaceTexcoord)) discard; planted syntax error",
       "a syntax error: the driver refuses the G-buffer shader", "compile"},
      {"half-pixel", "blend.frag", "vec2 u = vec2(p - scale / 2) / float(scale);",
       "vec2 u = vec2(p) / float(scale);", "upsampling taps off by half a level pixel (the −⌊s/2⌋ dropped)",
       partName(Part::Upsample)},
      {"blend-weight", "blend.frag", "alpha = min(alphaHat * weight, 1.0);", "alpha = min(alphaHat * weight * 0.5, 1.0);",
       "the blend weight w_ℓ halved", partName(Part::BlendAlpha)},
      {"uncorrected-blend", "blend.frag", "vec3 below = coarsest ? vec3(0.0) : texelFetch(coarser, p, 0).rgb;",
       "vec3 below = vec3(0.0);",
       "the paper's printed Eq. 1: blends with c'_{i-1}, the finer composite, not yet written (0)", partName(Part::Composite)},
      {"unmasked-bilinear", "blend.frag", "if (texelFetch(stencilMask, q, 0).r < 0.5) continue;", "",
       "bilinear upsampling that ignores S_ℓ (reads unrendered texels)", partName(Part::Upsample)},
      {"ssao-bias-sign", "ssao.frag", "if (bufferDepth < sampleDepth - bias)", "if (bufferDepth < sampleDepth + bias)",
       "the SSAO depth bias with its sign flipped", partName(Part::Raw)},
      {"pcf-one-short", "ssm.frag", "if (receiverDepthAt(r, du, dv) <= depthAt(r.u + du, r.v + dv)) ++litTaps;",
       "if (receiverDepthAt(r, du, dv) <= depthAt(r.u + du, r.v + dv) && !(i == grid - 1 && j == grid - 1)) ++litTaps;",
       "a PCF grid one sample short (the last tap never counts as lit)", partName(Part::Raw)},
      {"ssgi-no-ndotl", "ssgi.frag", "float nl = max(dot(n, toLight), 0.0);", "float nl = 1.0;",
       "SSGI senders without the N·L term", partName(Part::Raw)},
      {"effect-reach-truncated", "effect_masks.frag", "return min(CAP, int(floor(levelPixels + 0.5)));",
       "return min(CAP, int(floor(levelPixels)));",
       "mrr-effect's reach K truncated, not rounded (the + 1/2 dropped): squares one level pixel too small",
       partName(Part::Mask)},
      {"effect-dilate-strict", "effect_masks.frag",
       "if (texelFetch(source, ivec2(p.x, y), 0).r >= float(abs(d))) widened = 1.0;",
       "if (texelFetch(source, ivec2(p.x, y), 0).r > float(abs(d))) widened = 1.0;",
       "mrr-effect's dilation along y with > for >=: each square loses its top and bottom rows", partName(Part::Mask)},
      {"effect-only-keeps-edges", "effect_masks.frag",
       "result = vec4(widened && !edge ? 1.0 : 0.0, 0.0, 0.0, 1.0);", "result = vec4(widened ? 1.0 : 0.0, 0.0, 0.0, 1.0);",
       "the ablation's effect-only arm without the AND NOT M_l (SPEC 12.3): each widened level keeps its edges too",
       partName(Part::Mask)},
      {"marks-2x2", "refinement_marks.frag",
       "for (int d = -1; d <= 1; ++d) {\n    ivec2 q = ivec2(p.x + d, p.y);",
       "for (int d = 0; d <= 1; ++d) {\n    ivec2 q = ivec2(p.x + d, p.y);",
       "mrr-effect's a-posteriori range over 2 columns of the 3x3 neighbourhood (SPEC 12.2 step 1; the separable "
       "pass along x)", partName(Part::Marks)},
      {"budget-key-octaves", "refinement_budget.frag",
       "return uint(top) * (1u << uint(kBudgetKeyBits)) + (below & ((1u << uint(kBudgetKeyBits)) - 1u));",
       "return uint(top) * (1u << uint(kBudgetKeyBits));",
       "mrr-effect's budget keys a price by its octave alone, without the bits below its top bit (SPEC 12.4 step 3)",
       partName(Part::Marks)},
      {"budget-last-round-skipped", "refinement_budget.frag", "      if (t < st.x) {",
       "      if (t < st.x && stride > 1) {",
       "mrr-effect's budget stops its threshold search a round early: the threshold is a multiple of 16 keys "
       "(SPEC 12.4 step 4)",
       partName(Part::Marks)},
      {"temporal-keeps-level-zero", "temporal.frag", "float lambdaP = weight > 0.0 ? lambda * (1.0 - a0) : 0.0;",
       "float lambdaP = weight > 0.0 ? lambda : 0.0;",
       "the temporal term without its (1 - alpha_0): pixels level 0 shades keep the history too (SPEC 14 step 5)",
       partName(Part::Temporal)},
      {"marks-inclusive", "refinement_marks.frag", "marked = range > tau ? 1.0 : 0.0;",
       "marked = range >= tau ? 1.0 : 0.0;",
       "mrr-effect's a-posteriori test with >= for >: a range of exactly tau_v is marked", partName(Part::Marks)},
      {"refine-marks-dropped", "refine_masks.frag",
       "value = max(texelFetch(source, p, 0)[SOURCE_CHANNEL] > 0.5 ? 1.0 : 0.0, texelFetch(marks, p, 0).r);",
       "value = max(texelFetch(source, p, 0)[SOURCE_CHANNEL] > 0.5 ? 1.0 : 0.0, texelFetch(marks, p, 0).r > 1.5 ? 1.0 : 0.0);",
       "mrr-effect's refinement without the marks: M_l, a_l and S_l stay the a priori ones", partName(Part::Mask)},
      {"refine-stencil-replaced", "refine_masks.frag",
       "value = texelFetch(source, p, 0).r > 0.5 || texelFetch(alpha, p, 0).r > 0.0 ? 1.0 : 0.0;",
       "value = texelFetch(source, p, 0).r > 1.5 || texelFetch(alpha, p, 0).r > 0.0 ? 1.0 : 0.0;",
       "mrr-effect's refined S_l = [a_l > 0] alone: what the closure gave S_l from finer levels is lost",
       partName(Part::Stencil)},
      {"trim-window-short", "trim.frag",
       "for (int px = max(0, q.x * s - s / 2); px < min(frame.x, q.x * s + 3 * s / 2); ++px)",
       "for (int px = max(0, q.x * s); px < min(frame.x, q.x * s + 3 * s / 2); ++px)",
       "mrr-effect's trim with the taps' window along x starting s/2 late: a level pixel the blend reads is cut",
       partName(Part::Stencil)},
      {"tiles-no-dilation", "peers.frag",
       "near = max(near, texelFetch(source, ivec2(i, j), 0).r);", "near = max(near, texelFetch(source, p, 0).r);",
       "tiles' rate without the 8-neighbourhood: no tile is ever shaded at 2×2", partName(Part::TileRates)},
      {"jbu-no-depth", "peers.frag", "return b * exp(-dz * dz) * normalSimilarity(cosine, normalPower);",
       "return b * normalSimilarity(cosine, normalPower);",
       "uniform-k's joint bilateral upsampling without its depth term", partName(Part::Upsample)},
  };
  return faults;
}

const ShaderFault* plantedFault() {
  const char* name = std::getenv("MRR_GPU_FAULT");
  if (!name || !*name) return nullptr;
  std::string known;
  for (const ShaderFault& f : shaderFaults()) {
    if (f.name == name) return &f;
    known += (known.empty() ? "" : ", ") + f.name;
  }
  throw MrrError(std::string("MRR_GPU_FAULT=") + name + ": no such planted fault (known: " + known + ")");
}

std::string applyPlantedFault(const std::string& file, const std::string& text) {
  const ShaderFault* fault = plantedFault();
  if (!fault || fault->file != file) return text;
  const size_t at = text.find(fault->find);
  require(at != std::string::npos, "MRR_GPU_FAULT=" + fault->name + ": its text is no longer in gpu/shaders/" +
                                       file + " (update gpu/faults.cpp)");
  std::string out = text;
  out.replace(at, fault->find.size(), fault->replace);
  return out;
}

}  // namespace mrr::gpu
