#include "compare/parity/parity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "common/stage_images.h"
#include "common/stages.h"
#include "cpu_ref/oracle.h"  // the oracle's stages, run on the port's inputs

namespace mrr {

// |Δ| per pixel over the channels; `include(i)` picks the pixels compared. Sizes must match
// (a mismatch is itself a failure: every pixel counts as over).
// `band` (optional, one flag per pixel): the guard band, where a difference is allowed and
// counted apart.
DiffFigures diffImages(const ImageF& a, const ImageF& b, double threshold, const std::function<bool(size_t)>& include,
                       const std::vector<char>* band) {
  DiffFigures f;
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    f.pixels = std::max<int64_t>(static_cast<int64_t>(std::max(a.pixelCount(), b.pixelCount())), 1);
    f.maxAbs = f.rms = std::numeric_limits<double>::infinity();
    f.shareOver = 1.0;
    f.over = f.pixels;
    return f;
  }
  const size_t ch = static_cast<size_t>(a.channels);
  double sum2 = 0.0;
  int64_t over = 0;
  f.deltaMap = ImageF(a.width, a.height, 1, 0.0f);
  // Every figure (pixels, max|Δ|, over, RMS) is over the same pixels: those compared outside
  // the guard band. The band's pixels are counted apart (f.band, f.overInBand).
  for (size_t p = 0; p < a.pixelCount(); ++p) {
    if (include && !include(p)) continue;
    double worst = 0.0, pixelSum2 = 0.0;
    for (size_t c = 0; c < ch; ++c) {
      const double d = std::fabs(static_cast<double>(a.data[p * ch + c]) - static_cast<double>(b.data[p * ch + c]));
      worst = std::max(worst, std::isnan(d) ? std::numeric_limits<double>::infinity() : d);
      pixelSum2 += d * d;
    }
    f.deltaMap.data[p] = static_cast<float>(worst);
    if (band && (*band)[p]) {
      f.overInBand += worst > threshold;
      continue;
    }
    ++f.pixels;
    sum2 += pixelSum2;
    over += worst > threshold;
    if (worst > f.maxAbs || f.worstX < 0) {
      if (worst > f.maxAbs) f.maxAbs = worst;
      if (worst >= f.maxAbs) {
        f.worstX = static_cast<int>(p % static_cast<size_t>(a.width));
        f.worstY = static_cast<int>(p / static_cast<size_t>(a.width));
      }
    }
  }
  const double n = static_cast<double>(std::max<int64_t>(f.pixels, 1));
  f.rms = std::sqrt(sum2 / (n * static_cast<double>(ch)));
  f.shareOver = static_cast<double>(over) / n;
  f.over = over;
  if (band) f.band = std::count(band->begin(), band->end(), char{1});
  return f;
}

std::ostream& operator<<(std::ostream& o, const DiffFigures& f) {
  return o << "max|d| " << f.maxAbs << "  rms " << f.rms << "  over " << 100.0 * f.shareOver << "% of " << f.pixels;
}

DiffFigures diffImages(const ImageU8& a, const ImageU8& b, const std::vector<char>* band) {
  return diffImages(toFloat(a), toFloat(b), 0.5, {}, band);
}

DiffFigures diffShadowMaps(const ShadowMap& port, const ShadowMap& oracle, double thresholdTexels) {
  ImageF a = port.depth, b = oracle.depth;
  std::vector<char> covered(a.data.size(), 0);
  if (a.data.size() == b.data.size())
    for (size_t i = 0; i < a.data.size(); ++i) {
      const bool ha = a.data[i] != ShadowMap::kNoBlocker, hb = b.data[i] != ShadowMap::kNoBlocker;
      covered[i] = ha || hb;
      a.data[i] = ha ? a.data[i] / oracle.texel : 1e9f;
      b.data[i] = hb ? b.data[i] / oracle.texel : (ha ? 0.0f : 1e9f);
    }
  return diffImages(a, b, thresholdTexels, [&](size_t i) { return covered[i] != 0; });
}

namespace {

// The end-to-end tolerance rule the stage list gives a part.
std::string endToEndRule(Part part) { return std::string(partInfo(part).endToEnd); }

// The stencil guard band: S_ℓ = [a_ℓ > 0], so pixels with 0 < a_ℓ ≤ kGuardBand.
std::vector<char> stencilGuardBand(const ImageF& alpha) {
  std::vector<char> band(alpha.data.size(), 0);
  for (size_t i = 0; i < band.size(); ++i) band[i] = alpha.data[i] > 0.0f && alpha.data[i] <= kGuardBand;
  return band;
}

StageCheck check(const std::string& rule, DiffFigures figures) {
  const bool pass = figures.within(tolerance(rule));
  if (pass) figures.deltaMap = {};  // only a failing check's map is shown
  return {rule, std::move(figures), pass, std::nullopt};
}

}  // namespace

std::string StageRow::verdict() const {
  if (pass()) return "PASS";
  if (sameInput && sameInput->pass) return "UPSTREAM";
  return "FAIL";
}

std::pair<int, int> StageRow::worstPixel() const {
  // The check that decided the verdict: a failing same-input check, else a failing
  // end-to-end one, else whichever saw the larger |Δ|.
  const StageCheck* c = nullptr;
  if (sameInput && !sameInput->pass) c = &*sameInput;
  else if (endToEnd && !endToEnd->pass) c = &*endToEnd;
  else if (sameInput && endToEnd) c = sameInput->figures.maxAbs >= endToEnd->figures.maxAbs ? &*sameInput : &*endToEnd;
  else if (sameInput) c = &*sameInput;
  else if (endToEnd) c = &*endToEnd;
  if (!c || c->figures.worstX < 0 || c->figures.maxAbs <= 0.0) return {-1, -1};
  if (scale == 0) return {c->figures.worstX, c->figures.worstY};  // shadow-map texels
  return {c->figures.worstX * scale + scale / 2, c->figures.worstY * scale + scale / 2};
}

bool ParityResult::pass() const { return firstFailing().empty(); }

std::string ParityResult::shaderOf(const std::string& stage) const {
  Part part;
  if (!partOf(stage, part)) return "";
  const std::string_view shaders = partInfo(part).shader;
  if (shaders.find(' ') == std::string_view::npos) return std::string(shaders);
  if (part == Part::Mask) return methodInfo(mode).masks == MaskBuilder::EffectEdges ? "effect_masks.frag" : "masks.frag";
  if (part == Part::Marks) return std::string(shaders);  // the range test's, and the budget's where it selected
  // One file per effect ("ssao.frag ssm.frag ssgi.frag"): the frame's.
  const std::string mine = toString(effect) + ".frag";
  return shaders.find(mine) != std::string_view::npos ? mine : std::string(shaders);
}

std::string ParityResult::inheritedFrom(size_t row) const {
  std::string out;
  int named = 0;
  for (size_t i = 0; i < row && i < rows.size() && named < 3; ++i) {
    const StageRow& r = rows[i];
    if (!r.endToEnd || r.verdict() != "PASS") continue;
    const DiffFigures& f = r.endToEnd->figures;
    if (f.over == 0 && f.overInBand == 0) continue;
    std::string what = f.over > 0 ? std::to_string(f.over) + " px over its threshold"
                                  : std::to_string(f.overInBand) + " px differ in its guard band";
    const auto [x, y] = r.worstPixel();
    if (f.over > 0 && x >= 0) what += std::string(", worst at ") + (r.scale == 0 ? "texel " : "") + std::to_string(x) + "," + std::to_string(y);
    out += (out.empty() ? "" : "; ") + r.stage + " (" + what + ")";
    ++named;
  }
  return out;
}

int ParityResult::inherited() const {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(), [](const StageRow& r) { return r.verdict() == "UPSTREAM"; }));
}

const StageRow* ParityResult::row(const std::string& stage) const {
  for (const StageRow& r : rows)
    if (r.stage == stage) return &r;
  return nullptr;
}

std::string ParityResult::firstFailing() const {
  for (const StageRow& r : rows)
    if (r.verdict() == "FAIL") return r.stage;
  return {};
}

namespace {

// The rows of one comparison, in pipeline order (compareFrames): the oracle's frame o, the
// port's p, and the result the steps add their rows to.
struct Rows {
  const FrameResult& o;
  const FrameResult& p;
  const Constants& c;
  ParityResult& result;
  const OracleStages& oracle;  // its stages, run on the port's inputs
  void add(StageRow row) { result.rows.push_back(std::move(row)); }

  void gbufferRows(int l);
  void shadowRows();
  void edgeRows();
  void limitRows();
  bool decisionAndMaskRows();  // false where the paths decided differently
  void effectRows();
  std::optional<StageCheck> blendRows();  // the final image's same-input check
};

// 1. A level's G-buffer: hit, relative depth, 1 − N·N' where both hit. In pipeline order:
// level 0 first (the masks are made from it), the coarser levels once the masks are known.
void Rows::gbufferRows(int l) {
  const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
  if (!lc.enabled) return;
  const GBuffer& a = p.levels[static_cast<size_t>(l)].gbuffer;
  const GBuffer& b = o.levels[static_cast<size_t>(l)].gbuffer;
  const std::string L = partName(Part::GBuffer, l);
  add({L + ".hit", l, lc.scale, check("gbuffer.hit", diffImages(a.hit, b.hit)), {}});
  const auto bothHit = [&](size_t i) { return a.hit.data.size() == b.hit.data.size() && a.hit.data[i] && b.hit.data[i]; };
  ImageF relDepth(a.width, a.height, 1, 0.0f), zero(a.width, a.height, 1, 0.0f), normalOff = zero, albedoOff = zero,
      positionOff = zero;
  if (a.depth.data.size() == b.depth.data.size())
    for (size_t i = 0; i < relDepth.data.size(); ++i) {
      if (!bothHit(i)) continue;
      relDepth.data[i] = std::fabs(a.depth.data[i] - b.depth.data[i]) / std::max(b.depth.data[i], 1e-30f);
      const glm::vec3 na(a.normal.data[3 * i], a.normal.data[3 * i + 1], a.normal.data[3 * i + 2]);
      const glm::vec3 nb(b.normal.data[3 * i], b.normal.data[3 * i + 1], b.normal.data[3 * i + 2]);
      normalOff.data[i] = 1.0f - glm::dot(na, nb);
      float albedo = 0.0f, position = 0.0f;
      for (size_t k = 0; k < 3; ++k) {
        albedo = std::max(albedo, std::fabs(a.albedo.data[3 * i + k] - b.albedo.data[3 * i + k]));
        position = std::max(position, std::fabs(a.position.data[3 * i + k] - b.position.data[3 * i + k]));
      }
      albedoOff.data[i] = albedo;
      positionOff.data[i] = position / std::max(b.depth.data[i], 1e-30f);  // relative to the depth, like depth
    }
  add({L + ".depth", l, lc.scale,
       check("gbuffer.depth", diffImages(relDepth, zero, tolerance("gbuffer.depth").pixelThreshold, bothHit)), {}});
  add({L + ".position", l, lc.scale,
       check("gbuffer.depth", diffImages(positionOff, zero, tolerance("gbuffer.depth").pixelThreshold, bothHit)), {}});
  // The crease band: where the oracle's normal turns by more than kCreaseTurn to a 4-neighbour,
  // a triangle edge runs between the pixel centres, and the rasteriser's sub-pixel snapping
  // (1/256 of a level pixel on llvmpipe) may pick the other facet than the ray does. A
  // faceted stress scene has such pixels everywhere at a coarse level (builtin:alledges at
  // 320x180: 6% of L3); differences there are allowed and counted apart, as in the edges' band.
  std::vector<char> creases(b.normal.data.size() / 3, 0);
  if (a.normal.data.size() == b.normal.data.size())
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x) {
        if (!b.hit.at(x, y)) continue;
        const glm::vec3 n = b.normalAt(x, y);
        for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= b.width || qy >= b.height || !b.hit.at(qx, qy)) continue;
          if (1.0f - glm::dot(n, b.normalAt(qx, qy)) > kCreaseTurn)
            creases[static_cast<size_t>(y) * static_cast<size_t>(b.width) + static_cast<size_t>(x)] = 1;
        }
      }
  add({L + ".normal", l, lc.scale,
       check("gbuffer.normal",
             diffImages(normalOff, zero, tolerance("gbuffer.normal").pixelThreshold, bothHit, &creases)),
       {}});
  add({L + ".albedo", l, lc.scale,
       check("gbuffer.albedo", diffImages(albedoOff, zero, tolerance("gbuffer.albedo").pixelThreshold, bothHit)), {}});
}

// 2. The shadow map (in texels, over texels either path covers) and the one-tap test.
void Rows::shadowRows() {
  if (c.needsShadowMap()) {
    add({partName(Part::ShadowMap), -1, 0,
         check("shadowmap.depth", diffShadowMaps(p.shadowMap, o.shadowMap, tolerance("shadowmap.depth").pixelThreshold)),
         {}});
    const ImageU8 same = oracle.shadowTest(p);
    add({partName(Part::ShadowTest), -1, 1, check(endToEndRule(Part::ShadowTest), diffImages(p.shadowLit, o.shadowLit)),
         check("shadowtest.same_input", diffImages(p.shadowLit, same))});
  }
}

// 3. Which pixels of which level are shaded: the edges (modes mrr and tiles), the
// never-slower decision (SPEC §11), then the stencils the frame was shaded with.
// A frame that fell back early (SPEC §11) found no edges: compared only where both did.
void Rows::edgeRows() {
  const bool bothFoundEdges = !p.edges.combined.empty() && !o.edges.combined.empty();
  if (methodInfo(c.mode).findsEdges && bothFoundEdges) {
    const EdgeImages same = oracle.edges(p);
    const std::vector<char> edgeBand = oracle.edgeGuardBand(p, kGuardBand);
    // Each kind on its own, then their OR, E.
    const std::string edgesPart = partName(Part::Edges);
    const std::pair<const char*, const ImageU8 EdgeImages::*> kinds[] = {
        {".normal", &EdgeImages::normal}, {".depth", &EdgeImages::depth},
        {".background", &EdgeImages::background}, {".shadow", &EdgeImages::shadow}};
    for (const auto& [kindName, kind] : kinds) {
      if ((p.edges.*kind).data.empty() && (o.edges.*kind).data.empty()) continue;  // shadow: SSM only
      add({edgesPart + kindName, -1, 1, check(endToEndRule(Part::Edges), diffImages(p.edges.*kind, o.edges.*kind)),
           check("edges.same_input", diffImages(p.edges.*kind, same.*kind, &edgeBand))});
    }
    add({edgesPart, -1, 1, check(endToEndRule(Part::Edges), diffImages(p.edges.combined, o.edges.combined)),
         check("edges.same_input", diffImages(p.edges.combined, same.combined, &edgeBand))});
  }
}

// SPEC §13: the eccentricity (no input), the motion and the level limit, end to end and on the
// port's own G-buffer.
void Rows::limitRows() {
  if (p.levelLimit.empty() || o.levelLimit.empty()) return;
  const LevelLimit same = oracle.levelLimit(p);
  if (!p.eccentricity.empty() && !o.eccentricity.empty())
    add({partName(Part::Eccentricity), -1, 1,
         check(endToEndRule(Part::Eccentricity),
               diffImages(p.eccentricity, o.eccentricity, tolerance(endToEndRule(Part::Eccentricity)).pixelThreshold, {})),
         {}});
  if (!p.motion.empty() && !o.motion.empty())
    add({partName(Part::Motion), -1, 1,
         check(endToEndRule(Part::Motion), diffImages(p.motion, o.motion, tolerance(endToEndRule(Part::Motion)).pixelThreshold, {})),
         check("motion.same_input", diffImages(p.motion, same.motion, tolerance("motion.same_input").pixelThreshold, {}))});
  add({partName(Part::LevelLimit), -1, 1, check(endToEndRule(Part::LevelLimit), diffImages(p.levelLimit, o.levelLimit)),
       check("levellimit.same_input", diffImages(p.levelLimit, same.limit))});
}

// The decision comes right after the masks in the pipeline, but it chooses the stencils the
// frame keeps: when the paths decide differently, their frames differ in kind from here on
// and nothing later can be compared.
bool Rows::decisionAndMaskRows() {
  if (o.fallback.evaluated || p.fallback.evaluated) {
    // one "pixel" each, 0 or 1 (float: GCC 12 warns falsely on a 1×1 byte image, PR 106199)
    const ImageF portDecision(1, 1, 1, p.fallback.fellBack ? 1.0f : 0.0f),
        oracleDecision(1, 1, 1, o.fallback.fellBack ? 1.0f : 0.0f);
    add({"fallback", -1, 1, check("fallback", diffImages(portDecision, oracleDecision, 0.5)), {}});
    if (p.fallback.fellBack != o.fallback.fellBack) return false;
  }
  // The oracle's mask builder of the frame's method (full's where it fell back), on the port's
  // own inputs; tiles' stencils from the port's own rates, which are judged first.
  const MethodInfo& method = methodInfo(c.mode);
  const bool multires = method.blurredMasks() && !o.fallback.fellBack;
  Masks masks;
  if (o.fallback.fellBack) {
    masks = fullModeMasks(c);
  } else if (method.masks == MaskBuilder::Tiles) {
    add({partName(Part::TileRates), -1, kTileSize, check(endToEndRule(Part::Stencil), diffImages(p.tileRates, o.tileRates)),
         check("masks.same_input", diffImages(p.tileRates, oracle.tileRates(p)))});
    masks = oracle.tileStencils(p);
  } else {
    masks = oracle.masks(p, method.masks);
  }
  // SPEC §12.2, mrr-effect with τ_v: the marks from the port's own coarser result, stencil and
  // G-buffer, limited by its own level limit; each refined level's masks refined with the port's
  // own marks (the levels are judged apart: a level's marks read the coarser level as refined).
  std::array<ImageU8, kLevelCount> sameMarks;
  const bool posterior = multires && method.aPosteriori && c.effectMask.refines();
  for (int l = 0; posterior && l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled || l == c.coarsestEnabled || l < c.effectMask.posteriorFinest) continue;
    sameMarks[static_cast<size_t>(l)] = oracle.marks(p, l);
    const ImageU8& portMarks = p.levels[static_cast<size_t>(l)].marks;
    if (portMarks.width == lc.width && portMarks.height == lc.height)
      oracle.refine(masks[static_cast<size_t>(l)], portMarks, lc);
  }
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!sameMarks[static_cast<size_t>(l)].empty())
      add({partName(Part::Marks, l), l, lc.scale, {},
           check("marks.same_input", diffImages(p.levels[static_cast<size_t>(l)].marks, sameMarks[static_cast<size_t>(l)]))});
    const MaskLevel& pm = p.levels[static_cast<size_t>(l)].masks;
    const MaskLevel& om = o.levels[static_cast<size_t>(l)].masks;
    const MaskLevel& sm = masks[static_cast<size_t>(l)];
    if (!pm.mask.data.empty() || !sm.mask.data.empty())
      add({partName(Part::Mask, l), l, lc.scale, {}, check("masks.same_input", diffImages(pm.mask, sm.mask))});
    if (!lc.enabled) continue;
    add({partName(Part::Alpha, l), l, lc.scale, {},
         check("alpha.same_input", diffImages(pm.alpha, sm.alpha, tolerance("alpha.same_input").pixelThreshold, {}))});
    // Only the method's S_ℓ = [a_ℓ > 0] has a cutoff to guard; the others are exact.
    const std::vector<char> stencilBand = multires ? stencilGuardBand(sm.alpha) : std::vector<char>{};
    add({partName(Part::Stencil, l), l, lc.scale, check(endToEndRule(Part::Stencil), diffImages(pm.stencil, om.stencil)),
         check("masks.same_input", diffImages(pm.stencil, sm.stencil, multires ? &stencilBand : nullptr))});
  }
  return true;
}

// 4. The effect per level, on the port's own inputs, and the bilateral blur (SSAO).
void Rows::effectRows() {
  const std::string effect = toString(c.effect);
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled || !lc.shaded) continue;  // uniform-k's level 0 shades nothing
    const LevelResult& pl = p.levels[static_cast<size_t>(l)];
    const LevelResult& ol = o.levels[static_cast<size_t>(l)];
    const ImageF same = oracle.raw(p, l);
    const auto portShaded = [&](size_t i) { return pl.masks.stencil.data[i] != 0; };
    const auto bothShaded = [&](size_t i) {
      return pl.masks.stencil.data.size() == ol.masks.stencil.data.size() && pl.masks.stencil.data[i] &&
             ol.masks.stencil.data[i];
    };
    const ToleranceRule& end = tolerance(effect);
    const ToleranceRule& sameRule = tolerance(effect + ".same_input");
    add({partName(Part::Raw, l), l, lc.scale, check(effect, diffImages(pl.raw, ol.raw, end.pixelThreshold, bothShaded)),
         check(effect + ".same_input", diffImages(pl.raw, same, sameRule.pixelThreshold, portShaded))});
    if (c.effect == Effect::Ssao) {
      const ImageF blurred = oracle.sub(p, l, pl.raw);
      add({partName(Part::Sub, l), l, lc.scale, {},
           check("bilateral.same_input",
                 diffImages(pl.sub, blurred, tolerance("bilateral.same_input").pixelThreshold, portShaded))});
    }
  }
}

// 5. Upsample and blend, coarse to fine. Each step on the port's own inputs: ĉ_ℓ and α_ℓ
// from the port's c_ℓ, S_ℓ and a_ℓ; c'_ℓ from the port's ĉ_ℓ, α_ℓ and c'_coarser. The peers
// compose their own way (SPEC §9): the oracle's composePeer on the port's sub-images,
// G-buffers and tile rates gives every ĉ_ℓ, α_ℓ, c'_ℓ and the final image at once.
std::optional<StageCheck> Rows::blendRows() {
  const double blendThreshold = tolerance("blend.same_input").pixelThreshold;
  const BlendResult same = oracle.blendStepwise(p);
  for (int l = kLevelCount - 1; l >= 0; --l) {
    const size_t i = static_cast<size_t>(l);
    if (!c.levels[i].enabled || p.blend.upsampled[i].data.empty() || same.upsampled[i].data.empty()) continue;
    add({partName(Part::Upsample, l), l, 1, {},
         check("blend.same_input", diffImages(p.blend.upsampled[i], same.upsampled[i], blendThreshold, {}))});
    add({partName(Part::BlendAlpha, l), l, 1, {},
         check("blend.same_input", diffImages(p.blend.alpha[i], same.alpha[i], blendThreshold, {}))});
    add({partName(Part::Composite, l), l, 1, {},
         check("blend.same_input", diffImages(p.blend.composite[i], same.composite[i], blendThreshold, {}))});
  }
  if (same.final.data.empty()) return std::nullopt;
  // the blend's own final image (SPEC §14's temporal term, where it ran, is judged apart)
  return check("blend.same_input", diffImages(p.blend.final, same.final, blendThreshold, {}));
}

}  // namespace

ParityResult compareFrames(const FrameResult& o, const FrameResult& p, const DirectionalLight& light) {
  const Constants& c = o.constants;
  ParityResult result;
  result.effect = c.effect;
  result.mode = c.mode;
  const OracleStages oracle(light);
  Rows rows{o, p, c, result, oracle};
  // 1. The full-res G-buffer (the masks are made from it); 2. the shadow map and test; 3. the
  // edges, the never-slower decision and the stencils (when the paths decide differently,
  // nothing later can be compared); 1, continued: the coarser levels' G-buffers; 4. the
  // effect; 5. upsample and blend.
  rows.gbufferRows(0);
  rows.shadowRows();
  rows.edgeRows();
  rows.limitRows();
  if (!rows.decisionAndMaskRows()) return result;
  for (int l = 1; l < kLevelCount; ++l) rows.gbufferRows(l);
  rows.effectRows();
  const std::optional<StageCheck> finalSame = rows.blendRows();
  // The final image is the finest composite; end to end it carries everything above.
  rows.add({partName(Part::Final), -1, 1,
       check(endToEndRule(Part::Final), diffImages(p.final(), o.final(), tolerance(endToEndRule(Part::Final)).pixelThreshold, {})), finalSame});

  // SPEC §14: the temporal term, end to end and on the port's own blend, level-0 G-buffer and masks
  // and the history it read (the port's previous frame). The final row above judged the result.
  if (!p.temporal.empty() && p.temporal.previous && !p.levels[0].gbuffer.depth.empty()) {
    const TemporalImages same = oracle.temporal(p, *p.temporal.previous);
    const ImageF portPart = temporalPartImage(p.temporal);
    std::optional<StageCheck> endToEnd;
    if (!o.temporal.empty())
      endToEnd = check(endToEndRule(Part::Temporal),
                       diffImages(portPart, temporalPartImage(o.temporal), tolerance(endToEndRule(Part::Temporal)).pixelThreshold, {}));
    rows.add({partName(Part::Temporal), -1, 1, endToEnd,
              check("temporal.same_input", diffImages(portPart, temporalPartImage(same), tolerance("temporal.same_input").pixelThreshold, {}))});
  }

  // 6. The shaded image: end to end, and the oracle's shadeFinal on the port's own level-0
  // G-buffer, final image and one-tap test (shade.frag's arithmetic alone).
  if (!p.shaded.empty() && !o.shaded.empty() && !p.levels[0].gbuffer.depth.empty()) {
    const ImageF same = oracle.shaded(p);
    rows.add({partName(Part::Shaded), -1, 1,
         check(endToEndRule(Part::Shaded), diffImages(p.shaded, o.shaded, tolerance(endToEndRule(Part::Shaded)).pixelThreshold, {})),
         check("shaded.same_input",
               diffImages(p.shaded, same, tolerance("shaded.same_input").pixelThreshold, {}))});
  }
  return result;
}

std::string formatParityTable(const ParityResult& result, const std::string& owner) {
  std::string out;
  char line[320];
  std::snprintf(line, sizeof line, "%-20s %-8s  %-24s %9s %10s %8s %10s   %-24s %9s %10s %8s %10s   %s\n", "stage",
                "verdict", "end to end: rule", "pixels", "max|d|", "over%", "rms", "same input: rule", "pixels",
                "max|d|", "over%", "rms", "worst at (full-res x,y); guard band");
  out += line;
  auto cells = [&](const std::optional<StageCheck>& c) {
    char text[160];
    if (!c) {
      std::snprintf(text, sizeof text, "%-24s %9s %10s %8s %10s", "-", "", "", "", "");
    } else {
      char ruleText[64];
      std::snprintf(ruleText, sizeof ruleText, "%s%s", c->rule.c_str(), c->pass ? "" : " !");
      std::snprintf(text, sizeof text, "%-24s %9lld %10.3g %8.3f %10.3g", ruleText,
                    static_cast<long long>(c->figures.pixels), c->figures.maxAbs, 100.0 * c->figures.shareOver,
                    c->figures.rms);
    }
    return std::string(text);
  };
  for (const StageRow& r : result.rows) {
    std::string worst;
    const auto [wx, wy] = r.worstPixel();
    if (wx >= 0 && r.scale > 0) worst = std::to_string(wx) + "," + std::to_string(wy);
    if (wx >= 0 && r.scale == 0) worst = "texel " + std::to_string(wx) + "," + std::to_string(wy);
    if (r.sameInput && r.sameInput->figures.band >= 0)
      worst += (worst.empty() ? "" : "  ") + std::string("band ") + std::to_string(r.sameInput->figures.band) + " px, " +
               std::to_string(r.sameInput->figures.overInBand) + " differ in it";
    std::snprintf(line, sizeof line, "%-20s %-8s  %s   %s   %s\n", r.stage.c_str(), r.verdict().c_str(),
                  cells(r.endToEnd).c_str(), cells(r.sameInput).c_str(), worst.c_str());
    out += line;
  }
  out += "rules (common/tolerance.h): a check passes when over% <= its allowed share and rms <= its bound; '!' marks a "
         "failed check.\n";
  out += "UPSTREAM: end to end over its rule while the stage on " + owner + " own inputs passes: inherited, not this "
         "stage's bug.\n";
  bool noise = false;
  for (const StageRow& r : result.rows) {
    if (!r.endToEnd || !r.endToEnd->noise) continue;
    if (!noise)
      out += "noise-aware (docs/spec.md 8.1): stochastic stages judged against the oracle's " +
             std::to_string(r.endToEnd->noise->seeds) +
             " seeds: per pixel (columns: pixels tested, |d| of the worst pixel from the seeds' mean, % rejected, "
             "|bias| over the frame), and the bias per region with its interval:\n";
    noise = true;
    out += "  " + r.stage + " " + (r.endToEnd->pass ? "pass" : "FAIL") + ": " + r.endToEnd->noise->describe() + "\n";
  }
  const std::string first = result.firstFailing();
  const int inherited = result.inherited();
  for (size_t i = 0; i < result.rows.size(); ++i) {
    if (result.rows[i].verdict() != "UPSTREAM") continue;
    const std::string from = result.inheritedFrom(i);
    out += "UPSTREAM " + result.rows[i].stage + ": inherits " +
           (from.empty() ? "differences below every earlier stage's threshold" : "what earlier stages let through: " + from) + "\n";
  }
  const std::string firstShader = result.shaderOf(first);
  if (!result.pass())
    out += "FAIL: first failing stage " + first + (firstShader.empty() ? "" : " (" + firstShader + ")") + "\n";
  else if (inherited > 0)
    out += "PASS: every stage's own computation within tolerance; " + std::to_string(inherited) +
           " stage(s) over their end-to-end rule only by what they inherit (UPSTREAM)\n";
  else
    out += "PASS: every stage within tolerance\n";
  return out;
}

}  // namespace mrr
