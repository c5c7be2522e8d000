#pragma once
// Stage 4 for soft shadows — PCSS (Fernando 2005) on the directional light's shadow map
// (SPEC §6 SSM): blocker search, penumbra width, then PCF over an n×n grid. Output: the
// visibility V in [0, 1], evaluated only where the stencil is set.
#include "common/camera.h"
#include "common/image.h"
#include "common/kernels.h"
#include "common/params.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/shadowmap.h"

namespace mrr {

// What decided one pixel, for `mrr probe`.
struct SsmDetail {
  float receiverDepth = 0.0f;   // biased distance from the light plane
  bool facesLight = false;      // false: V = 0, no taps (the surface shadows itself)
  float searchTexels = 0.0f;    // blocker-search half-width
  int blockers = 0;             // blocker-search taps in front of the receiver
  int searchTaps = 0;
  float blockerDepth = 0.0f;    // their mean distance from the light plane
  float penumbraWorld = 0.0f;   // penumbra width, world units (full width)
  float filterTexels = 0.0f;    // PCF half-width
  int litTaps = 0, pcfTaps = 0;
};

float ssmAt(const GBuffer& g, const ShadowMap& map, const View& view, const Constants::Ssm& ssm, int x, int y,
            SsmDetail* detail = nullptr);

// SPEC §11: the map footprint of pixel (x, y) on geometry, whose receiver is r: how far its
// neighbours' receivers lie from r on the shadow map, in texels, the mean over the two axes (along
// each, the next pixel on geometry, else the previous; an axis with neither is left out, and with
// none the footprint is 0). Neighbouring searches share the map's cache lines less the farther
// apart they land, so a search costs more the larger it is (docs/figures.md).
float mapFootprintAt(const GBuffer& g, const ShadowMap& map, const View& view, float biasTexels, int x, int y,
                     const Receiver& r);
// The footprint in the sample's steps (kFootprintSteps a texel), rounded, at most kMaxFootprintTexels.
int footprintSteps(float texels);

// The never-slower rule's view of PCSS's cost (SPEC §11): PCF is paid only where the blocker
// search finds a blocker, which the one-tap test cannot tell (the search reaches up to 64 texels
// around a lit pixel). One pixel in kPcfSampleStep² is asked, (x·8 + 4, y·8 + 4) on the
// full-res G-buffer, the level-3 grid: kPcfSamplePcf where ssmAt would filter, kPcfSampleSearch
// where it searches and finds no blocker (and on sky, where a block's pixels on geometry are
// assumed to search), kPcfSampleNone where it returns at once (a surface facing away from the
// light). Where it searches on geometry, the byte's high bits hold its map footprint
// (footprintSteps; common/shader_constants.h). The searches cost about 1/64 of a full frame's.
ImageU8 pcfSample(const GBuffer& g, const ShadowMap& map, const View& view, const Constants::Ssm& ssm);

ImageF renderSsm(const GBuffer& g, const ShadowMap& map, const ImageU8& stencil, const View& view,
                 const Constants::Ssm& ssm);

}  // namespace mrr
