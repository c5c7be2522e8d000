#include "cpu_ref/temporal.h"

#include <algorithm>
#include <cmath>

#include "common/parallel.h"

namespace mrr {

namespace {
// R v + t (or R v), one row at a time, in the order the shader writes it.
float row(const Reprojection& m, int i, const glm::vec3& v) {
  return m.r[i][0] * v.x + m.r[i][1] * v.y + m.r[i][2] * v.z;
}
}  // namespace

Reprojected reprojectAt(const GBuffer& g, int x, int y, const Reprojection& m, const View& previous) {
  Reprojected r;
  if (!g.hit.at(x, y)) return r;
  // 1. p' = R p + t, n' = R n; z' = −p'.z; q = (cx + f p'.x / z', cy − f p'.y / z')
  const glm::vec3 p = g.positionAt(x, y), n = g.normalAt(x, y);
  const glm::vec3 pp(row(m, 0, p) + m.t[0], row(m, 1, p) + m.t[1], row(m, 2, p) + m.t[2]);
  const float z = -pp.z;
  if (!(z > 0.0f)) return r;
  r.ok = true;
  r.depth = z;
  r.q = {previous.cx + previous.focal * pp.x / z, previous.cy - previous.focal * pp.y / z};
  r.normal = {row(m, 0, n), row(m, 1, n), row(m, 2, n)};
  return r;
}

HistoryTaps historyTaps(glm::vec2 q, int width, int height) {
  // 2. the bilinear taps around q, pixel centres at the integers of u = q − ½
  HistoryTaps t;
  const float ux = q.x - 0.5f, uy = q.y - 0.5f;
  const float fx0 = std::floor(ux), fy0 = std::floor(uy);
  const float fx = ux - fx0, fy = uy - fy0;
  // far off screen the floor does not fit an int: every tap is then outside
  const bool near = std::fabs(fx0) < 1.0e8f && std::fabs(fy0) < 1.0e8f;
  const int x0 = near ? static_cast<int>(fx0) : -2, y0 = near ? static_cast<int>(fy0) : -2;
  const float wx[2] = {1.0f - fx, fx}, wy[2] = {1.0f - fy, fy};
  for (int k = 0; k < 4; ++k) {
    const int i = k & 1, j = k >> 1;
    t.x[k] = x0 + i;
    t.y[k] = y0 + j;
    t.w[k] = wx[i] * wy[j];
    t.inside[k] = near && t.x[k] >= 0 && t.y[k] >= 0 && t.x[k] < width && t.y[k] < height;
  }
  return t;
}

bool sameSurface(const FrameHistory& h, int tx, int ty, const Reprojected& r, const Constants::Temporal& c) {
  // 3. on geometry, the same depth within δ z' and the same facing within κ
  const float zt = h.depth.at(tx, ty);
  if (!(zt > 0.0f)) return false;
  if (!(std::fabs(zt - r.depth) <= c.depthTolerance * r.depth)) return false;
  const float facing =
      h.normal.at(tx, ty, 0) * r.normal.x + h.normal.at(tx, ty, 1) * r.normal.y + h.normal.at(tx, ty, 2) * r.normal.z;
  return facing >= c.normalCos;
}

HistorySample historyAt(const FrameHistory& h, const Reprojected& r, const Constants::Temporal& c) {
  // 4. the taps that show the same surface, their weights normalised
  HistorySample s;
  if (!r.ok) return s;
  const HistoryTaps taps = historyTaps(r.q, h.result.width, h.result.height);
  const int ch = std::min(h.result.channels, 3);
  for (int k = 0; k < 4; ++k) {
    if (!taps.inside[k] || !sameSurface(h, taps.x[k], taps.y[k], r, c)) continue;
    s.weight += taps.w[k];
    for (int i = 0; i < ch; ++i) s.value[i] += taps.w[k] * h.result.at(taps.x[k], taps.y[k], i);
  }
  if (s.weight > 0.0f)
    for (int i = 0; i < ch; ++i) s.value[i] = s.value[i] / s.weight;
  return s;
}

float levelZeroAlpha(const MaskLevel& level0, float weight0, int x, int y) {
  if (!level0.stencil.at(x, y)) return 0.0f;
  return std::min(level0.alpha.at(x, y) * weight0, 1.0f);
}

float temporalWeight(float alpha0, float lambda, float historyWeight) {
  // 5. the coarser levels' share of the pixel keeps λ of the history, where there is one
  return historyWeight > 0.0f ? lambda * (1.0f - alpha0) : 0.0f;
}

TemporalImages temporalTerm(const FrameResult& in, const ImageF& final, const FrameHistory& history) {
  const Constants& c = in.constants;
  const int w = c.width, h = c.height, ch = final.channels;
  const GBuffer& g = in.levels[0].gbuffer;
  const MaskLevel& m0 = in.levels[0].masks;
  const float w0 = c.levels[0].weight;
  const Reprojection m = makeReprojection(in.view, history.view);
  TemporalImages out;
  out.history = ImageF(w, h, ch, 0.0f);
  out.weight = ImageF(w, h, 1, 0.0f);
  out.result = ImageF::uninitialised(w, h, ch);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const Reprojected r = reprojectAt(g, x, y, m, history.view);
      const HistorySample s = historyAt(history, r, c.temporal);
      const float lambdaP = temporalWeight(levelZeroAlpha(m0, w0, x, y), c.temporal.lambda, s.weight);
      out.weight.at(x, y) = lambdaP;
      for (int i = 0; i < ch; ++i) {
        out.history.at(x, y, i) = s.value[i];
        // 6. final' = c + λ_p (h − c)
        out.result.at(x, y, i) = lambdaP > 0.0f ? temporalBlend(final.at(x, y, i), s.value[i], lambdaP) : final.at(x, y, i);
      }
    }
  });
  return out;
}

FrameHistory makeHistory(const FrameResult& f) {
  const Constants& c = f.constants;
  FrameHistory h;
  h.view = f.view;
  h.result = f.final();
  const GBuffer& g = f.levels[0].gbuffer;
  h.depth = crop(g.depth, c.width, c.height);
  h.normal = crop(g.normal, c.width, c.height);
  for (size_t l = 0; l < kLevelCount; ++l) h.marked[l] = f.levels[l].marked;  // SPEC §14.2
  return h;
}

}  // namespace mrr
