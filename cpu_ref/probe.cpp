#include "cpu_ref/probe.h"

#include "common/frame_params.h"

#include "common/stages.h"

#include <cstdio>
#include <sstream>

#include "common/error.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/edges.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/foveation.h"
#include "cpu_ref/ssao.h"
#include "cpu_ref/ssgi.h"
#include "cpu_ref/ssm.h"
#include "cpu_ref/temporal.h"
#include "common/effect_budget.h"

namespace mrr {

const char* coverageName(Coverage c) {
  switch (c) {
    case Coverage::None: return "none";
    case Coverage::Geometry: return "geometry";
    case Coverage::Effect: return "effect";
    case Coverage::Marks: return "marks";
    case Coverage::Closure: return "closure";
    case Coverage::Coarsest: return "coarsest";
    case Coverage::Fallback: return "fallback";
    case Coverage::Limit: return "limit";
    case Coverage::Trim: return "trim";
  }
  return "?";
}

CoverageArms coverageArms(const FrameResult& f) {
  CoverageArms arms;
  const Constants& c = f.constants;
  const MethodInfo& method = methodInfo(c.mode);
  const bool effect = method.masks == MaskBuilder::EffectEdges;
  if (f.edges.combined.empty() || !method.blurredMasks()) return arms;
  arms.active = true;
  if (effect)
    arms.footprint = effectFootprint(f.levels[0].gbuffer, f.edges.combined, f.view,
                                     c.needsShadowMap() ? &f.shadowMap : nullptr, c);
  arms.stages = maskStages(f.edges.combined, c, effect ? &arms.footprint : nullptr);
  // 1. the arms: geometry (E's pyramid; nothing in the effect-only arm), widened (M'_ℓ) and the
  // a-posteriori marks (from the frame's own coarser results, as refineMasks made them)
  Masks geometry, marks;
  for (size_t l = 0; l < kLevelCount; ++l) {
    const ImageU8& g = arms.stages.geometry[l];
    geometry[l].mask = effect && c.effectMask.effectOnly ? ImageU8(g.width, g.height, 1, 0) : g;
    arms.widened[l].mask = effect ? arms.stages.widened[l] : g;
  }
  const bool posterior = method.aPosteriori && c.effectMask.refines() && !f.fallback.fellBack;
  for (int l = 0; l < kLevelCount; ++l) {
    const int next = c.nextCoarserEnabled(l);
    if (!posterior || !c.levels[static_cast<size_t>(l)].enabled || next < 0 || l < c.effectMask.posteriorFinest) continue;
    const LevelResult& coarser = f.levels[static_cast<size_t>(next)];
    const ImageU8& m = arms.widened[static_cast<size_t>(l)].mask;
    const ImageU8& marked = f.levels[static_cast<size_t>(l)].marked;  // SPEC §12.4: the budget's selection
    marks[static_cast<size_t>(l)].mask =
        f.refinement[static_cast<size_t>(l)].budgeted && !marked.empty()
            ? parentMarks(marked, 1 << (next - l), m.width, m.height)
            : refinementMarks(coarser.sub, coarser.masks.stencil, coarser.gbuffer.hit, 1 << (next - l), m.width,
                              m.height, c.effectMask.posterior);
  }
  // 2. their blurs, before and after SPEC §13's limit
  arms.limited = !f.levelLimit.empty();
  Masks geometryLimited = geometry, widenedLimited = arms.widened, marksLimited = marks;
  if (arms.limited)
    for (Masks* m : {&geometryLimited, &widenedLimited, &marksLimited}) applyLevelLimit(*m, f.levelLimit, c);
  for (int l = 0; l < kLevelCount; ++l) {
    const size_t li = static_cast<size_t>(l);
    const LevelConstants& lc = c.levels[li];
    if (!lc.enabled || l == c.coarsestEnabled) continue;
    arms.aGeometry[li] = blurMask(geometryLimited[li].mask, lc.gaussian);
    arms.aWidened[li] = blurMask(widenedLimited[li].mask, lc.gaussian);
    if (arms.limited) {
      arms.aGeometryUnlimited[li] = blurMask(geometry[li].mask, lc.gaussian);
      arms.aWidenedUnlimited[li] = blurMask(arms.widened[li].mask, lc.gaussian);
    }
    if (!marks[li].mask.empty()) {
      arms.marks[li] = marks[li].mask;
      ImageU8 both = widenedLimited[li].mask;
      for (size_t i = 0; i < both.data.size(); ++i) both.data[i] = both.data[i] | marksLimited[li].mask.data[i];
      arms.aMarks[li] = blurMask(both, lc.gaussian);
    }
  }
  return arms;
}

Coverage coverageReason(const CoverageArms& arms, const FrameResult& f, int l, int qx, int qy) {
  const Constants& c = f.constants;
  const size_t li = static_cast<size_t>(l);
  // SPEC §12.5: mrr-effect's trim cut it, whatever covered it: the blend does not read it
  const ImageU8& read = f.levels[li].masks.read;
  if (!read.empty() && !read.at(qx, qy)) return Coverage::Trim;
  if (l == c.coarsestEnabled) return f.fallback.fellBack ? Coverage::Fallback : Coverage::Coarsest;
  if (arms.aGeometry[li].at(qx, qy) > 0.0f) return Coverage::Geometry;
  if (arms.aWidened[li].at(qx, qy) > 0.0f) return Coverage::Effect;
  if (!arms.aMarks[li].empty() && arms.aMarks[li].at(qx, qy) > 0.0f) return Coverage::Marks;
  const ImageU8& s = f.levels[li].masks.stencil;
  if (!s.empty() && s.at(qx, qy)) return Coverage::Closure;
  if (arms.limited &&
      (arms.aGeometryUnlimited[li].at(qx, qy) > 0.0f || arms.aWidenedUnlimited[li].at(qx, qy) > 0.0f))
    return Coverage::Limit;
  return Coverage::None;
}

namespace {
nlohmann::json vec(const ImageF& img, int x, int y) {
  nlohmann::json v = nlohmann::json::array();
  for (int c = 0; c < img.channels; ++c) v.push_back(img.at(x, y, c));
  return v;
}
nlohmann::json scalarOrVec(const ImageF& img, int x, int y) {
  return img.channels == 1 ? nlohmann::json(img.at(x, y)) : vec(img, x, y);
}
std::string fmt(const nlohmann::json& v) {
  if (v.is_array()) {
    std::string s = "(";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + fmt(v[i]);
    return s + ")";
  }
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
    return buf;
  }
  return v.dump();
}
// SPEC §12.3: why each level covers (x, y), for modes mrr and mrr-effect; null for a disabled
// level (and for other modes). The arms are the oracle's, on the frame's own inputs; S is the frame's.
std::array<nlohmann::json, kLevelCount> coverageWhy(const FrameResult& f, int x, int y) {
  std::array<nlohmann::json, kLevelCount> why{};
  const Constants& c = f.constants;
  const CoverageArms arms = coverageArms(f);
  if (!arms.active) return why;
  for (int l = 0; l < kLevelCount; ++l) {
    const size_t li = static_cast<size_t>(l);
    const LevelConstants& lc = c.levels[li];
    if (!lc.enabled) continue;
    const int qx = x / lc.scale, qy = y / lc.scale;
    nlohmann::json j;
    const Coverage reason = coverageReason(arms, f, l, qx, qy);
    j["reason"] = coverageName(reason);
    j["M_geometry"] = arms.stages.geometry[li].at(qx, qy);
    if (!arms.stages.reach[li].empty()) {
      j["footprint"] = arms.stages.footprintMax[li].at(qx, qy);
      j["reach"] = arms.stages.reach[li].at(qx, qy);
    }
    j["M_widened"] = arms.widened[li].mask.at(qx, qy);
    if (arms.limited) j["l_min"] = f.levelLimit.at(levelSamplePixel(qx, lc.scale), levelSamplePixel(qy, lc.scale), kLimitLevel);
    if (l != c.coarsestEnabled) {
      j["a_geometry"] = arms.aGeometry[li].at(qx, qy);
      j["a_widened"] = arms.aWidened[li].at(qx, qy);
    }
    if (!arms.marks[li].empty()) {
      const int next = c.nextCoarserEnabled(l), ratio = 1 << (next - l);
      const LevelResult& coarser = f.levels[static_cast<size_t>(next)];
      const int px = std::min(qx / ratio, coarser.sub.width - 1), py = std::min(qy / ratio, coarser.sub.height - 1);
      j["mark"] = arms.marks[li].at(qx, qy);
      j["mark_parent"] = {next, px, py};
      j["mark_range"] = localRange(coarser.sub, coarser.masks.stencil, coarser.gbuffer.hit, px, py);
      j["tau"] = c.effectMask.posterior;
      j["a_marks"] = arms.aMarks[li].at(qx, qy);
      const RefinementRecord& budget = f.refinement[li];
      if (budget.budgeted) {  // SPEC §12.4: the parent's price and the level's budget
        const std::vector<uint32_t>& prices = budget.candidatePrices;
        const size_t at = static_cast<size_t>(py) * static_cast<size_t>(coarser.sub.width) + static_cast<size_t>(px);
        if (at < prices.size()) {
          j["mark_price_units"] = prices[at];
          j["mark_price_ns"] = static_cast<double>(prices[at]) * budget.unitNs;
        }
        j["budget_ns"] = budget.budgetNs();
        j["budget_spent_ns"] = budget.spentNs();
        j["budget_threshold_key"] = budget.threshold;
      }
    }
    if (reason == Coverage::Effect && arms.widened[li].mask.at(qx, qy) && !arms.stages.reach[li].empty()) {
      // the nearest edge pixel whose square of side 2K + 1 holds q (SPEC §12 step 3)
      const Image<int16_t>& k = arms.stages.reach[li];
      bool found = false;
      for (int d = 0; d <= c.effectMask.cap && !found; ++d)
        for (int v = qy - d; v <= qy + d && !found; ++v)
          for (int u = qx - d; u <= qx + d && !found; ++u) {
            if (std::max(std::abs(u - qx), std::abs(v - qy)) != d || u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
            if (k.at(u, v) >= d) {
              j["reached_from"] = {u, v};
              j["reached_from_reach"] = k.at(u, v);
              found = true;
            }
          }
    }
    if (reason == Coverage::Closure)  // the next finer enabled level with S = 1 inside q's block
      for (int k = l - 1; k >= 0; --k) {
        if (!c.levels[static_cast<size_t>(k)].enabled) continue;
        const int ratio = 1 << (l - k);
        const ImageU8& s = f.levels[static_cast<size_t>(k)].masks.stencil;
        bool any = false;
        for (int v = qy * ratio; v < std::min((qy + 1) * ratio, s.height) && !any; ++v)
          for (int u = qx * ratio; u < std::min((qx + 1) * ratio, s.width) && !any; ++u) any = s.at(u, v) != 0;
        if (any) {
          j["closure_from"] = k;
          break;
        }
      }
    why[li] = j;
  }
  return why;
}
}  // namespace

nlohmann::json probePixel(const FrameResult& f, int x, int y) {
  const Constants& c = f.constants;
  require(x >= 0 && y >= 0 && x < c.width && y < c.height,
          "--pixel " + std::to_string(x) + "," + std::to_string(y) + ": outside the " + std::to_string(c.width) +
              "x" + std::to_string(c.height) + " image");
  nlohmann::json j;
  j["pixel"] = {x, y};
  j["size"] = {c.width, c.height};
  j["effect"] = toString(c.effect);
  j["mode"] = toString(c.mode);

  const GBuffer& g0 = f.levels[0].gbuffer;
  j[partName(Part::GBuffer)] = {{"hit", g0.hit.at(x, y) != 0}, {"depth", g0.depth.at(x, y)},
                  {"position", vec(g0.position, x, y)}, {"normal", vec(g0.normal, x, y)},
                  {"albedo", vec(g0.albedo, x, y)}};

  if (!f.edges.combined.empty()) {  // modes mrr and tiles
    const EdgeDecision e = edgeAt(g0, c.edges, x, y, c.effect == Effect::Ssm ? &f.shadowLit : nullptr);
    j[partName(Part::Edges)] = {{"normal", {{"edge", e.normal}, {"max_1_minus_dot", e.normalMax}, {std::string(paramInfo(Param::TauN).key), c.edges.normalThreshold}}},
                  {"depth",
                   {{"edge", e.depth},
                    {"second_diff_x", e.takenX ? nlohmann::json(e.depthSecondX) : nlohmann::json("n/a")},
                    {"second_diff_y", e.takenY ? nlohmann::json(e.depthSecondY) : nlohmann::json("n/a")},
                    {std::string(paramInfo(Param::TauZ).key), c.edges.depthThreshold}}},
                  {"background", {{"edge", e.background}, {"background_neighbour", e.backgroundNeighbour}}},
                  {"E", e.normal || e.depth || e.background || e.shadow}};
    if (e.lit >= 0)
      j[partName(Part::Edges)]["shadow"] = {{"edge", e.shadow}, {"lit", e.lit}, {"neighbour_differs", e.shadowNeighbourDiffers}};
    // The measures are the oracle's on the frame's G-buffer; the decisions are the frame's own
    // edge images (the port's, or another renderer's stages: compare --against).
    nlohmann::json& je = j[partName(Part::Edges)];
    const auto own = [&](const ImageU8& image) { return !image.empty() && image.at(x, y) != 0; };
    je["normal"]["edge"] = own(f.edges.normal);
    je["depth"]["edge"] = own(f.edges.depth);
    je["background"]["edge"] = own(f.edges.background);
    if (je.contains("shadow")) je["shadow"]["edge"] = own(f.edges.shadow);
    je["E"] = own(f.edges.combined);
  }

  const std::array<nlohmann::json, kLevelCount> why = coverageWhy(f, x, y);
  nlohmann::json levels = nlohmann::json::array();
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const LevelResult& lr = f.levels[static_cast<size_t>(l)];
    nlohmann::json lj = {{"level", l}, {"scale", lc.scale}, {"enabled", lc.enabled}};
    if (!lc.enabled) {
      levels.push_back(lj);
      continue;
    }
    const int lx = x / lc.scale, ly = y / lc.scale;
    lj["level_pixel"] = {lx, ly};
    // the full-res pixel it holds (SPEC §0): its G-buffer is level 0's there
    lj["sample_pixel"] = {levelSamplePixel(lx, lc.scale), levelSamplePixel(ly, lc.scale)};
    if (!lr.masks.mask.empty()) lj["M"] = lr.masks.mask.at(lx, ly);
    lj["a"] = lr.masks.alpha.at(lx, ly);
    lj["S"] = lr.masks.stencil.at(lx, ly);
    if (!why[static_cast<size_t>(l)].is_null()) lj["why"] = why[static_cast<size_t>(l)];
    lj["sigma2"] = lc.sigma2;
    lj["w"] = lc.weight;
    if (lr.masks.stencil.at(lx, ly)) {
      lj["c_raw"] = scalarOrVec(lr.raw, lx, ly);
      lj["c"] = scalarOrVec(lr.sub, lx, ly);
      switch (c.effect) {
        case Effect::Ssao: {
          SsaoDetail d;
          ssaoAt(lr.gbuffer, occluderPlanes(lr.gbuffer), f.view, lc, c.ssao, lx, ly, &d);
          lj["ssao"] = {{"samples", d.samples}, {"occluders", d.occluders}, {"occlusion", d.occlusion},
                        {"offscreen", d.offscreen}, {"background", d.background}, {"rotation_rad", d.rotation}};
          break;
        }
        case Effect::Ssm: {
          SsmDetail d;
          ssmAt(lr.gbuffer, f.shadowMap, f.view, c.ssm, lx, ly, &d);
          lj["ssm"] = {{"faces_light", d.facesLight}, {"receiver_depth", d.receiverDepth}, {"search_texels", d.searchTexels},
                       {"blockers", d.blockers}, {"search_taps", d.searchTaps}, {"blocker_depth", d.blockerDepth},
                       {"penumbra_width", d.penumbraWorld}, {"filter_texels", d.filterTexels},
                       {"lit_taps", d.litTaps}, {"pcf_taps", d.pcfTaps}};
          if (d.facesLight && lr.gbuffer.hit.at(lx, ly)) {  // SPEC §11: how far its neighbours search, on the map
            const Receiver r = receiverAt(f.shadowMap, f.view.toWorld(lr.gbuffer.positionAt(lx, ly)),
                                          f.view.directionToWorld(lr.gbuffer.normalAt(lx, ly)), c.ssm.biasTexels);
            lj["ssm"]["map_footprint_texels"] = mapFootprintAt(lr.gbuffer, f.shadowMap, f.view, c.ssm.biasTexels, lx, ly, r);
          }
          break;
        }
        case Effect::Ssgi: {
          SsgiDetail d;
          const ImageF direct = directLight(lr.gbuffer, f.shadowMap, f.view, f.light, c.ssm.biasTexels);
          ssgiAt(lr.gbuffer, direct, f.view, lc, c.ssgi, lx, ly, &d);
          lj["ssgi"] = {{"samples", d.samples}, {"senders", d.senders}, {"offscreen", d.offscreen},
                        {"background", d.background},
                        {"strongest_sender", {d.strongestTexel.x, d.strongestTexel.y}},
                        {"strongest_contribution", {d.strongest.x, d.strongest.y, d.strongest.z}}};
          break;
        }
      }
    }
    const BilinearTaps t = bilinearTaps(x, y, lc);
    nlohmann::json taps = nlohmann::json::array();
    for (int k = 0; k < 4; ++k) {
      const bool s = lr.masks.stencil.at(t.x[k], t.y[k]) != 0;
      taps.push_back({{"q", {t.x[k], t.y[k]}}, {"b", t.weight[k]}, {"S", s},
                      {"c", s ? scalarOrVec(lr.sub, t.x[k], t.y[k]) : nlohmann::json(nullptr)},
                      {"a", lr.masks.alpha.at(t.x[k], t.y[k])}});
    }
    lj["taps"] = taps;
    lj["c_hat"] = scalarOrVec(f.blend.upsampled[static_cast<size_t>(l)], x, y);
    // â = Σ b_q a(q), from the readable reference (cpu_ref/blend.h): what α = min(â·w, 1) is made of
    lj["a_hat"] = upsampleReference(lr.sub, lr.masks.stencil, lr.masks.alpha, lc, x, y).alphaHat;
    lj["alpha"] = f.blend.alpha[static_cast<size_t>(l)].at(x, y);
    lj[partName(Part::Composite)] = scalarOrVec(f.blend.composite[static_cast<size_t>(l)], x, y);
    levels.push_back(lj);
  }
  j["levels"] = levels;
  if (!f.levelLimit.empty()) {  // SPEC §13: what the eye and motion allow here, and the limit
    const Constants::Foveation& fv = c.foveation;
    nlohmann::json lj = {{"ppd", fv.ppd},
                         {"fovea_level", f.levelLimit.at(x, y, kLimitFovea)},
                         {"motion_level", f.levelLimit.at(x, y, kLimitMotion)},
                         {"limit", f.levelLimit.at(x, y, kLimitLevel)}};
    if (fv.gaze) {
      lj["gaze"] = {fv.gazeX, fv.gazeY};
      lj["foveate"] = fv.foveate;
      lj["eccentricity_degrees"] = eccentricityAt(x, y, fv);
    }
    if (fv.motion) {
      lj["motion_pixels"] = f.motion.at(x, y);
      lj["motion_cap"] = fv.motionCap;
    }
    j[partName(Part::LevelLimit)] = lj;
  }
  j["finest_contributing_level"] = f.blend.levelMap.at(x, y);
  j[partName(Part::Final)] = scalarOrVec(f.blend.final, x, y);
  if (!f.temporal.empty()) {  // SPEC §14: whether the pixel kept the previous frame's result, and how much
    const float lambdaP = f.temporal.weight.at(x, y);
    j[partName(Part::Temporal)] = {{"kept_history", lambdaP > 0.0f},
                                   {"lambda", c.temporal.lambda},
                                   {"alpha0", levelZeroAlpha(f.levels[0].masks, c.levels[0].weight, x, y)},
                                   {"lambda_p", lambdaP},
                                   {"history", scalarOrVec(f.temporal.history, x, y)},
                                   {"result", scalarOrVec(f.temporal.result, x, y)}};
  }
  return j;
}

std::string formatWhy(const nlohmann::json& w) {
  const std::string reason = w["reason"].get<std::string>();
  std::ostringstream o;
  if (reason == "coarsest") {
    o << "coarsest: the coarsest enabled level covers every pixel (a = 1)";
  } else if (reason == "fallback") {
    o << "fallback: the never-slower rule fell back to full";
  } else if (reason == "geometry") {
    o << "geometry: "
      << (w["M_geometry"].get<int>() ? "an edge inside this pixel's block (M 1)"
                                     : "within the blur of an edge block (a from edges alone " + fmt(w["a_geometry"]) + ")");
  } else if (reason == "effect") {
    o << "effect: no edge within the blur (a from edges alone 0); ";
    if (w.contains("reached_from"))
      o << "within reach of the edge pixel " << fmt(w["reached_from"]) << " (K " << w["reached_from_reach"]
        << " level pixels) -> M' 1";
    else
      o << "within the blur of the widened mask (a " << fmt(w["a_widened"]) << ")";
  } else if (reason == "marks") {
    const auto& p = w["mark_parent"];
    o << "marks: no edge or reach within the blur; "
      << (w["mark"].get<int>() ? "marked" : "within the blur of a mark") << " (its level-" << p[0] << " parent ("
      << p[1] << ", " << p[2] << ") varies by " << fmt(w["mark_range"]) << ", tau " << fmt(w["tau"]) << "; a "
      << fmt(w["a_marks"]) << ")";
  } else if (reason == "closure") {
    o << "closure: no edge, reach or mark within the blur; level " << w.value("closure_from", -1)
      << " shades inside this pixel's block";
  } else if (reason == "limit") {
    o << "not covered: the level limit clears M here (l_min " << w["l_min"] << "), which "
      << (w["M_geometry"].get<int>() || w.value("a_geometry", 0.0) > 0.0 ? "the edges" : "the effect's reach") << " set";
  } else {
    o << "not covered: no edge" << (w.contains("reach") ? ", reach" : "") << (w.contains("mark") ? " or mark" : "")
      << " within the blur";
  }
  if (w.contains("mark") && reason != "marks")
    o << "; a-posteriori range of the level-" << w["mark_parent"][0] << " parent " << fmt(w["mark_range"]) << " (tau "
      << fmt(w["tau"]) << ")";
  return o.str();
}

std::string formatProbe(const nlohmann::json& j) {
  std::ostringstream o;
  o << "pixel " << fmt(j["pixel"]) << " of " << j["size"][0] << "x" << j["size"][1] << ", effect "
    << j["effect"].get<std::string>() << ", mode " << j["mode"].get<std::string>() << "\n";
  const auto& g = j[partName(Part::GBuffer)];
  o << "G-buffer L0   hit " << g["hit"] << "  z " << fmt(g["depth"]) << "  N " << fmt(g["normal"]) << "  albedo "
    << fmt(g["albedo"]) << "\n";
  if (j.contains(partName(Part::Edges))) {
    const auto& e = j[partName(Part::Edges)];
    if (e.contains("shadow"))
      o << "shadow test   lit " << e["shadow"]["lit"] << "  (a 4-neighbour differs: " << e["shadow"]["neighbour_differs"]
        << ") -> shadow edge " << e["shadow"]["edge"] << "\n";
    o << "edges         normal " << e["normal"]["edge"] << "  (max 1-N.N " << fmt(e["normal"]["max_1_minus_dot"])
      << " vs " << paramInfo(Param::TauN).key << " " << fmt(e["normal"][std::string(paramInfo(Param::TauN).key)]) << ")\n"
      << "              depth  " << e["depth"]["edge"] << "  (|d2(1/z)|/(1/z) x " << fmt(e["depth"]["second_diff_x"])
      << ", y " << fmt(e["depth"]["second_diff_y"]) << " vs " << paramInfo(Param::TauZ).key << " " << fmt(e["depth"][std::string(paramInfo(Param::TauZ).key)]) << ")\n"
      << "              background " << e["background"]["edge"] << "  (background 4-neighbour: "
      << e["background"]["background_neighbour"] << ")\n"
      << "              E = " << e["E"] << "\n";
  }
  if (j.contains(partName(Part::LevelLimit))) {
    const auto& l = j[partName(Part::LevelLimit)];
    o << "level limit   ";
    if (l.contains("gaze"))
      o << "eccentricity " << fmt(l["eccentricity_degrees"]) << " deg (gaze " << fmt(l["gaze"]) << ", ppd "
        << fmt(l["ppd"]) << ") -> the eye allows level " << l["fovea_level"]
        << (l["foveate"].get<bool>() ? "" : " (--foveate off: measured only)") << "\n              ";
    if (l.contains("motion_pixels"))
      o << "motion " << fmt(l["motion_pixels"]) << " px since the previous frame -> "
        << "motion allows level " << l["motion_level"] << " (cap " << l["motion_cap"] << ")\n              ";
    const int limit = l["limit"].get<int>();
    o << "l_min " << limit << (limit == 0 ? ": nothing cleared here" : ": M_l cleared here for l < " + std::to_string(limit)) << "\n";
  }
  o << "levels, fine to coarse (the blend runs coarse to fine: c'_l = alpha * c_hat_l + (1 - alpha) * c'_coarser)\n";
  for (const auto& l : j["levels"]) {
    o << "level " << l["level"] << " (1/" << l["scale"] << ")";
    if (!l["enabled"].get<bool>()) {
      o << "  disabled\n";
      continue;
    }
    o << "  level pixel " << fmt(l["level_pixel"]);
    if (l["scale"].get<int>() > 1) o << " = full-res " << fmt(l["sample_pixel"]);
    if (l.contains("M")) o << "  M " << l["M"];
    o << "  a " << fmt(l["a"]) << "  S " << l["S"] << "  (sigma2 " << fmt(l["sigma2"]) << ", w " << fmt(l["w"]) << ")\n";
    if (l.contains("why")) o << "    why: " << formatWhy(l["why"]) << "\n";
    if (l.contains("c")) {
      o << "    shaded: c_raw " << fmt(l["c_raw"]) << " -> c " << fmt(l["c"]) << "   ";
      if (l.contains("ssao")) {
        const auto& s = l["ssao"];
        o << "(" << s["occluders"] << "/" << s["samples"] << " samples occlude, weight " << fmt(s["occlusion"]) << "; "
          << s["offscreen"] << " off-screen, " << s["background"] << " on background)\n";
      } else if (l.contains("ssm")) {
        const auto& s = l["ssm"];
        if (!s["faces_light"].get<bool>())
          o << "(faces away from the light: in its own shadow, V = 0, no taps)\n";
        else
          o << "(receiver depth " << fmt(s["receiver_depth"]) << "; blocker search +-" << fmt(s["search_texels"])
          << " texels: " << s["blockers"] << "/" << s["search_taps"] << " blockers, mean depth " << fmt(s["blocker_depth"])
          << "; penumbra " << fmt(s["penumbra_width"]) << " -> PCF +-" << fmt(s["filter_texels"]) << " texels, "
          << s["lit_taps"] << "/" << s["pcf_taps"] << " taps lit"
          << (s.contains("map_footprint_texels") ? "; neighbours " + fmt(s["map_footprint_texels"]) + " texels away on the map" : "")
          << ")\n";
      } else if (l.contains("ssgi")) {
        const auto& s = l["ssgi"];
        o << "(" << s["senders"] << "/" << s["samples"] << " samples are senders; " << s["offscreen"] << " off-screen, "
          << s["background"] << " on background; strongest sender " << fmt(s["strongest_sender"]) << " gives "
          << fmt(s["strongest_contribution"]) << ")\n";
      } else {
        o << "\n";
      }
    } else {
      o << "    not shaded at this level\n";
    }
    o << "    taps:";
    for (const auto& t : l["taps"]) {
      o << "  " << fmt(t["q"]) << " b " << fmt(t["b"]) << (t["S"].get<bool>() ? " c " + fmt(t["c"]) : std::string(" [S=0]"));
    }
    o << "\n    c_hat " << fmt(l["c_hat"]) << "  a_hat " << fmt(l["a_hat"]) << "  alpha "
      << fmt(l["alpha"]) << "  -> composite c' " << fmt(l[partName(Part::Composite)]) << "\n";
  }
  o << "finest contributing level " << j["finest_contributing_level"] << ", final " << fmt(j[partName(Part::Final)]) << "\n";
  if (j.contains(partName(Part::Temporal))) {  // SPEC §14
    const auto& t = j[partName(Part::Temporal)];
    if (t["kept_history"].get<bool>())
      o << "temporal (SPEC 14): kept the previous frame's result: lambda_p = lambda " << fmt(t["lambda"]) << " x (1 - alpha_0 "
        << fmt(t["alpha0"]) << ") = " << fmt(t["lambda_p"]) << " of its reprojected h " << fmt(t["history"]) << " -> "
        << fmt(t["result"]) << "\n";
    else
      o << "temporal (SPEC 14): no history kept here (off geometry, at full res, or no tap of the previous frame shows "
           "the same surface) -> "
        << fmt(t["result"]) << "\n";
  }
  return o.str();
}

}  // namespace mrr
