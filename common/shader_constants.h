#pragma once
// Numbers both paths use, defined once. The oracle reads these C++ constants; the port's shaders
// see the same values as GLSL `const int` and `const float` declarations (kShaderConstants below,
// the GLSL type following the C++ one) that gpu/program.cpp pastes after each shader's #version
// line, floats printed with enough digits (%.9g) that the GLSL compiler rounds them back to the
// same float (docs/shader-contract.md lists them). A shader must not declare these names itself.
// Per-frame numbers (thresholds, radii, kernels) are uniforms made from Constants instead.
#include <cstdint>
#include <cstdio>
#include <string>

#include "common/params.h"  // kLevelCount, kTileSize

namespace mrr {

// SSAO, occluderDepth (docs/spec.md §6.1): below this |cos|² between the sample ray and the
// texel's normal the tangent plane is too grazing to intersect, and the texel depth is used.
inline constexpr float kGrazingCosine2 = 0.01f;  // |cos| <= 0.1

// A shadow-map texel no surface covers: nothing blocks there (ShadowMap::kNoBlocker).
inline constexpr float kNoBlocker = 3.0e38f;

// The receiver plane's depth slope in the shadow map (docs/spec.md §6.4) is capped where the
// surface is within about 1° of grazing the light: |n·l| is taken as at least this.
inline constexpr float kReceiverMinCosine = 0.0175f;  // cos 89°

// The shaded image's sky colour on background pixels (SPEC §6, cpu_ref/shade.cpp).
inline constexpr float kSkyRed = 0.62f, kSkyGreen = 0.70f, kSkyBlue = 0.80f;

// The never-slower rule's sample of what SSM pays (SPEC §11, cpu_ref/ssm.h pcfSample, ssm.frag
// with PCF_SAMPLE): one pixel in kPcfSampleStep², whose value says what PCSS pays there. The
// port writes the value as a byte of an R8 target (value / 255).
inline constexpr int kPcfSampleStep = 8;
inline constexpr uint8_t kPcfSampleNone = 0;    // nothing: a surface facing away from the light
inline constexpr uint8_t kPcfSampleSearch = 1;  // the blocker search, which finds no blocker (and sky)
inline constexpr uint8_t kPcfSamplePcf = 2;     // the search and PCF's N taps
// The byte holds the class above in its low 2 bits and, where the pixel searches on geometry, its
// map footprint in its high 6 (SPEC §11): how far its neighbours' receivers lie from its own on
// the shadow map, in quarter texels, rounded, at most 63 (15.75 texels: past a 64-byte line of
// 16 texels no neighbour shares a line anyway). A search's memory cost grows with it.
inline constexpr int kPcfSampleClassBits = 2;
inline constexpr float kFootprintSteps = 4.0f;        // steps a texel
inline constexpr float kMaxFootprintTexels = 15.75f;  // 63 steps
inline constexpr uint8_t pcfSampleClass(uint8_t value) { return static_cast<uint8_t>(value & 3u); }
inline constexpr int pcfSampleFootprintSteps(uint8_t value) { return value >> kPcfSampleClassBits; }

// The never-slower rule's edge sample (SPEC §11, cpu_ref/edges.h edgeSample, edges.frag with
// EDGE_SAMPLE): per kEdgeSampleStep² block of the full-res grid, whether SPEC §2's rule finds an
// edge on the block's diagonal.
inline constexpr int kEdgeSampleStep = 8;

// SSM, PCSS (docs/spec.md §6.4): the blocker search's half-width, and so the penumbra's, is at
// most this many shadow-map texels.
inline constexpr float kMaxSearchTexels = 64.0f;
// The port's SSM pass takes the grid tap factors as uniform arrays of these sizes (ssm.frag:
// blockerFactors, pcfFactors): the blocker search's grid side is at most kMaxBlockerGrid
// (validateSettings: [1, 16]), PCF's at most kMaxPcfGrid (kMaxSsmSamples = 1024 = 32²).
inline constexpr int kMaxBlockerGrid = 16;
inline constexpr int kMaxPcfGrid = 32;

// SSGI (docs/spec.md §6.3): senders within ~0.06° of either surface's tangent plane count as
// coplanar: their form factor is zero up to rounding, and a plane must not light itself.
inline constexpr float kGrazingCosine = 1e-3f;

// The level limit's motion (docs/spec.md §13, cpu_ref/foveation.h motionAt): the screen motion
// of a surface point behind the previous camera, in full-res pixels (so fast that motion alone
// allows the coarsest level motionCap allows).
inline constexpr float kMotionBehind = 1.0e9f;
// The port's passes over a block map (gpu/gbuffer.cpp GpuScene::draw, blocks.geom): one point per
// row of the map and segment of this many blocks, each becoming the rectangles of its runs, cut
// every 32 blocks (at most one per two blocks: blocks.geom's max_vertices = 2 · 128 is a literal,
// as GLSL 3.30 wants, and 1,024 components, the least GL 3.3 allows). A segment's blocks are the
// four 32-bit words of one texel (blocks.frag STEP 4 packs them).
inline constexpr int kBlockSegment = 128;

// mrr-effect's budget (docs/spec.md §12.4, common/effect_budget.h, refinement_budget.frag): a
// candidate's priority is a key in [0, kBudgetKeys): the bits of v above its top kBudgetKeyBits
// mantissa bits, less the same of its whole-number price, plus kBudgetKeyOffset (kBudgetKeyBits
// steps an octave of v / price); kBudgetKeys − 1 is a free candidate's. The port finds the
// selection's threshold among the keys kBudgetRadix at a time (log_kBudgetRadix kBudgetKeys passes).
inline constexpr int kBudgetKeys = 4096;
inline constexpr int kBudgetKeyBits = 3;
inline constexpr int kBudgetKeyOffset = 256;
inline constexpr int kBudgetRadix = 16;

// A constant as the shaders see it: GLSL `const int` where the C++ constant is an integer
// (kTileSize, kPcfSampleStep: array sizes, strides and loop bounds), `const float` where it is a
// float. The constructor picks the type from the C++ value's (an 8-bit class byte promotes to int).
struct ShaderConstant {
  const char* name;  // the same identifier in C++ and GLSL
  bool isInt;
  int intValue;
  float floatValue;
  constexpr ShaderConstant(const char* n, int v) : name(n), isInt(true), intValue(v), floatValue(0.0f) {}
  constexpr ShaderConstant(const char* n, float v) : name(n), isInt(false), intValue(0), floatValue(v) {}
  const char* glslType() const { return isInt ? "int" : "float"; }
  // The GLSL literal: an int, or a float with enough digits (%.9g) to round back to the same
  // float, and always a point or an exponent, so it is a float literal.
  std::string glslValue() const {
    char text[32];
    if (isInt) {
      std::snprintf(text, sizeof text, "%d", intValue);
      return text;
    }
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(floatValue));
    std::string literal = text;
    if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
    return literal;
  }
  // "const float kNoBlocker = 2.99999995e+38;"
  std::string glslDeclaration() const { return std::string("const ") + glslType() + " " + name + " = " + glslValue() + ";"; }
};
inline constexpr ShaderConstant kShaderConstants[] = {
    {"kLevelCount", kLevelCount},
    {"kTileSize", kTileSize},
    {"kGrazingCosine2", kGrazingCosine2},
    {"kNoBlocker", kNoBlocker},
    {"kReceiverMinCosine", kReceiverMinCosine},
    {"kSkyRed", kSkyRed},
    {"kSkyGreen", kSkyGreen},
    {"kSkyBlue", kSkyBlue},
    {"kPcfSampleStep", kPcfSampleStep},
    {"kPcfSampleNone", kPcfSampleNone},
    {"kPcfSampleSearch", kPcfSampleSearch},
    {"kPcfSamplePcf", kPcfSamplePcf},
    {"kPcfSampleClassBits", kPcfSampleClassBits},
    {"kFootprintSteps", kFootprintSteps},
    {"kMaxFootprintTexels", kMaxFootprintTexels},
    {"kEdgeSampleStep", kEdgeSampleStep},
    {"kMaxSearchTexels", kMaxSearchTexels},
    {"kMaxBlockerGrid", kMaxBlockerGrid},
    {"kMaxPcfGrid", kMaxPcfGrid},
    {"kGrazingCosine", kGrazingCosine},
    {"kMotionBehind", kMotionBehind},
    {"kBlockSegment", kBlockSegment},
    {"kBudgetKeys", kBudgetKeys},
    {"kBudgetKeyBits", kBudgetKeyBits},
    {"kBudgetKeyOffset", kBudgetKeyOffset},
    {"kBudgetRadix", kBudgetRadix},
};

}  // namespace mrr
