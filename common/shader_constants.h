#pragma once
// Numbers both paths use, defined once (issue 16: "constants defined once"). The oracle reads
// these C++ constants; the port's shaders see the same values as GLSL `const float`
// declarations that gpu/program.cpp pastes after each shader's #version line, printed with
// enough digits (%.9g) that the GLSL compiler rounds them back to the same float.
// Per-frame numbers (thresholds, radii, kernels) are uniforms made from Constants instead.
#include <cstdint>

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

struct ShaderConstant {
  const char* name;  // the same identifier in C++ and GLSL
  float value;
};
inline constexpr ShaderConstant kShaderConstants[] = {
    {"kGrazingCosine2", kGrazingCosine2},
    {"kNoBlocker", kNoBlocker},
    {"kReceiverMinCosine", kReceiverMinCosine},
    {"kSkyRed", kSkyRed},
    {"kSkyGreen", kSkyGreen},
    {"kSkyBlue", kSkyBlue},
    {"kPcfSampleStep", static_cast<float>(kPcfSampleStep)},
    {"kPcfSampleNone", kPcfSampleNone},
    {"kPcfSampleSearch", kPcfSampleSearch},
    {"kPcfSamplePcf", kPcfSamplePcf},
    {"kPcfSampleClassBits", static_cast<float>(kPcfSampleClassBits)},
    {"kFootprintSteps", kFootprintSteps},
    {"kMaxFootprintTexels", kMaxFootprintTexels},
    {"kEdgeSampleStep", static_cast<float>(kEdgeSampleStep)},
};

}  // namespace mrr
