#pragma once
// SPEC §14, the temporal term: what a frame keeps for the next one (FrameHistory), and the images
// the term makes (TemporalImages). Both paths fill them from their own frame (cpu_ref/temporal.h,
// gpu/temporal.h); the bench's camera paths, `render --prev-frame`/`--pan` and `compare` carry a
// history from one frame to the next through RenderOptions::history.
#include <array>
#include <memory>

#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// The previous frame, as the next one reads it (W×H, the padding cropped). Copies of its own
// images, bit for bit: the temporal term's result and its level-0 G-buffer's depth and
// view-space normal (background: depth 0), with the view they were made in.
struct FrameHistory {
  View view;
  ImageF result;  // its effect buffer after the temporal term (FrameResult::final())
  ImageF depth;   // its view depth z (0: background)
  ImageF normal;  // its view-space normal, 3 channels
  // SPEC §14.2: its a-posteriori candidates that were marked, per level (its level grids;
  // empty where it refined nothing), for the marks' hysteresis.
  std::array<ImageU8, kLevelCount> marked;
  bool empty() const { return result.data.empty(); }
};

// What the term made in a frame that had a history: the reprojected history h (the effect's
// channels), the weight λ_p it was given at each pixel, and the result, final'
// (FrameResult::final() returns it). W×H.
struct TemporalImages {
  ImageF history;
  ImageF weight;
  ImageF result;
  // With RenderOptions::keepStages, the previous frame's history the term read (compare's
  // same-input check and probe run the oracle's steps on it).
  std::shared_ptr<const FrameHistory> previous;
  bool empty() const { return result.data.empty(); }
};

// SPEC §14 step 1's transform from this frame's view space to the previous frame's: p' = R p + t
// (points), n' = R n (normals). Made once on the host in double from the two views and rounded to
// float, so both paths reproject with the same nine and three numbers.
struct Reprojection {
  float r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // r[i] is row i
  float t[3] = {0, 0, 0};
};
Reprojection makeReprojection(const View& current, const View& previous);

}  // namespace mrr
