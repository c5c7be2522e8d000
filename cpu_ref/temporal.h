#pragma once
// SPEC §14, the temporal term: where reprojection finds the same surface in the previous frame,
// a pixel served by the coarser levels keeps a share λ of the previous frame's result. One
// function per step; gpu/shaders/temporal.frag numbers the same steps.
#include <glm/glm.hpp>

#include "common/frame.h"
#include "common/temporal.h"

namespace mrr {

// Step 1: full-res pixel p's surface point and normal in the previous view: p' = R p + t,
// n' = R n (Reprojection), its depth there z' = −p'.z and the continuous full-res point it
// projects to, q = (cx + f p'.x / z', cy − f p'.y / z'). `ok` false off geometry and where z' ≤ 0.
struct Reprojected {
  bool ok = false;
  glm::vec2 q{0.0f};
  float depth = 0.0f;
  glm::vec3 normal{0.0f};
};
Reprojected reprojectAt(const GBuffer& g, int x, int y, const Reprojection& m, const View& previous);

// Step 2: the four bilinear taps of the history around q, at u = q − ½ (pixel centres at the
// integers): (x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1), x0 = ⌊u_x⌋, with weights
// (1 − f_x)(1 − f_y), f_x (1 − f_y), (1 − f_x) f_y, f_x f_y; `inside` false off the W×H grid.
struct HistoryTaps {
  int x[4] = {}, y[4] = {};
  float w[4] = {};
  bool inside[4] = {};
};
HistoryTaps historyTaps(glm::vec2 q, int width, int height);

// Step 3: a tap shows the same surface: on geometry, |z_t − z'| ≤ δ z' and n_t · n' ≥ κ.
bool sameSurface(const FrameHistory& h, int tx, int ty, const Reprojected& r, const Constants::Temporal& c);

// Step 4: h = Σ w_t H_t / Σ w_t over the taps that are inside and the same surface, per channel
// (`value`, the effect's channels), and W = Σ w_t (`weight`; 0: no history at p).
struct HistorySample {
  float value[3] = {0.0f, 0.0f, 0.0f};
  float weight = 0.0f;
};
HistorySample historyAt(const FrameHistory& h, const Reprojected& r, const Constants::Temporal& c);

// Step 5: λ_p = λ (1 − α_0(p)) where the history has a sample (W > 0), else 0, with α_0(p) the
// level-0 blend weight of SPEC §5 at p: S_0(p) ? min(a_0(p) w_0, 1) : 0.
float levelZeroAlpha(const MaskLevel& level0, float weight0, int x, int y);
float temporalWeight(float alpha0, float lambda, float historyWeight);

// Step 6: final'(p) = c + λ_p (h − c), per channel.
inline float temporalBlend(float c, float h, float lambdaP) { return c + lambdaP * (h - c); }

// Steps 1–6 at every pixel of W×H: the reprojected history, λ_p and final', from the frame's
// blend (`final`), level-0 G-buffer and masks and the previous frame's history.
TemporalImages temporalTerm(const FrameResult& in, const ImageF& final, const FrameHistory& history);

// What this frame leaves for the next: its result (final' or the blend's), its level-0 depth and
// normal cropped to W×H, its view, and its marked candidates (SPEC §14.2).
FrameHistory makeHistory(const FrameResult& f);

}  // namespace mrr
