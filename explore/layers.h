#pragma once
// `mrr explore`'s layers: every stage image of a frame as a picture the page shows, with its
// legend and the values under the cursor; each part's image, caption and display are its row's
// (common/stages.h, read by common/stage_images.h). G-buffer channels and edge kinds are
// layers of their own ("gbuffer.L1.normal", "edges.depth"; "edges" is E); per-level parts carry
// ".L<l>"; "difference" is |this frame − the full-resolution frame| and "flip" the LDR-FLIP map of
// this frame's effect buffer against the full-resolution one's (both need the reference).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "common/frame.h"
#include "common/image.h"

namespace mrr::explore {

// How a layer's values are shown.
enum class LayerKind {
  Binary,  // 0/1: black, white
  Effect,  // the effect's own values, grey (SSGI: RGB), clamped to [0, 1]
  Scalar,  // non-colour data: the false-colour ramp over [lo, hi]
  Colour,  // RGB data shown as colour (normals as 0.5 + 0.5 n, albedo, positions)
  Levels,  // a level index 0..3: one ramp colour per level
  Flip,    // an LDR-FLIP error map in [0, 1]: the magma colour map (compare/metrics/flip.h)
  Reason,  // SPEC §12.3's coverage reasons (cpu_ref/probe.h: Coverage): one fixed colour each
};

struct LayerImage {
  std::string name;
  LayerKind kind = LayerKind::Scalar;
  int scale = 1;        // full-res pixels per layer pixel (s_l; 1 for full-res layers)
  ImageF values;        // the stage's values on its own grid (padded grids included)
  std::vector<std::string> channels;  // the channel names of `values`
  int channel = 0;                    // the channel shown of several (levellimit: l_min); the rest are read out
  float lo = 0.0f, hi = 1.0f;         // the range shown (Scalar: the ramp's ends)
  std::string caption;  // what it shows and how
  std::string what;     // the stage list's line
};

// Every layer the frame has, in pipeline order. `hasReference`: "difference" and "flip" are listed.
std::vector<std::string> layerNames(const FrameResult& frame, bool hasReference);

// The layer `name`; throws MrrError when the frame has no such layer. `reference` is the
// full-resolution frame (for "difference" and "flip"; may be null), `gain` the difference's ×N.
LayerImage makeLayer(const FrameResult& frame, const std::string& name, const FrameResult* reference, float gain);

// The 8-bit picture of a layer (binary white on black, ramp, grey or colour).
ImageU8 colourise(const LayerImage& layer);

// |port − oracle| per pixel (max over channels; NaN counts as infinite) and its largest
// finite value; empty when the grids differ.
ImageF layerDifference(const LayerImage& oracle, const LayerImage& port, float* largest);

// The layer's legend for the page: name, kind, grid, scale, range, caption, count of ones
// (binary layers), the mean (flip), and the ramp's CSS gradient (flip: magma).
nlohmann::json layerMeta(const LayerImage& layer);

// The values at full-res pixel (x, y): the layer pixel under it and each channel's value.
nlohmann::json layerValueAt(const LayerImage& layer, int x, int y);

}  // namespace mrr::explore
