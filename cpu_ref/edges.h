#pragma once
// Stage 2 — edge image E (SPEC §2), on the full-res (level 0) G-buffer, each kind kept apart.
#include "common/image.h"
#include "common/params.h"
#include "common/frame.h"

namespace mrr {

// Everything that decided one pixel: printed by `mrr probe`.
struct EdgeDecision {
  bool hit = false;
  float normalMax = 0.0f;      // max over 4-neighbours of 1 − N(p)·N(q)
  float depthSecondX = 0.0f;   // |d(p−x̂) − 2d(p) + d(p+x̂)| / d(p), 0 if not taken
  float depthSecondY = 0.0f;   // same along y
  bool takenX = false, takenY = false;  // whether each second difference was computable
  bool backgroundNeighbour = false;
  int lit = -1;                          // the one-tap shadow test (1 lit, 0 shadowed), -1 if not used
  bool shadowNeighbourDiffers = false;
  bool normal = false, depth = false, background = false, shadow = false;
};

// `shadowLit` (the one-tap test per pixel) enables the shadow kind; null for SSAO and SSGI.
EdgeDecision edgeAt(const GBuffer& g, const EdgeSettings& settings, int x, int y, const ImageU8* shadowLit = nullptr);
EdgeImages detectEdges(const GBuffer& g, const EdgeSettings& settings, const ImageU8* shadowLit = nullptr);
// The never-slower rule's edge sample (SPEC §11), on the ⌈W/8⌉×⌈H/8⌉ grid of kEdgeSampleStep²
// blocks: 1 where edgeAt finds an edge of any kind (E) at a pixel of the block's diagonal (8 of
// its 64 pixels, (8x + i, 8y + i)). The port's twin: edges.frag with EDGE_SAMPLE.
ImageU8 edgeSample(const GBuffer& g, const EdgeSettings& settings, const ImageU8* shadowLit = nullptr);

}  // namespace mrr
