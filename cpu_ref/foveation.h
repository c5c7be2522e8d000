#pragma once
// Foveation and motion (SPEC §13): a per-pixel level limit ℓ_min from the eye's
// eccentricity (the gaze) and from each pixel's screen motion against the previous frame's
// camera. The masks M_ℓ of every level ℓ < ℓ_min are cleared before the blur, so the pixel is
// served by a coarser level; where ℓ_min = 0 nothing changes.
#include <glm/glm.hpp>

#include "common/camera.h"
#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"
#include "common/shader_constants.h"

namespace mrr {

// Step 1: the eccentricity of full-res pixel (x, y), in degrees: d / ppd with d the distance from
// the gaze pixel in full-res pixels (both pixel centres). 0 without a gaze.
float eccentricityAt(int x, int y, const Constants::Foveation& f);
// Step 2: the coarsest level the eye allows at (x, y): the largest ℓ with d² ≥ radius2[ℓ]
// (Guenter et al. 2012's ω(e) = m·e + ω0, two level pixels per ω; exact integer thresholds).
int foveationLevel(int x, int y, const Constants::Foveation& f);
// Step 3: the screen motion of (x, y), full-res pixels, from this frame to the previous one:
// its surface point (the level-0 G-buffer's position) projected by the previous camera, less the
// pixel's centre, times motionScale. Background: 0. A point behind the previous camera:
// kMotionBehind on both axes (common/shader_constants.h, shared with limit.frag).
glm::vec2 motionAt(const GBuffer& g, int x, int y, const View& view, const View& previous, float scale);
// Step 4: the coarsest level motion allows: the largest ℓ ≤ motionCap with |v|² ≥ speed2[ℓ]
// (a box blur of width |v| holds k = 2 level pixels of level ℓ).
int motionLevel(const glm::vec2& v, const Constants::Foveation& f);

struct LevelLimit {
  ImageF eccentricity;  // step 1, degrees, padded full-res grid (empty without a gaze)
  ImageF motion;        // step 3, |v| in full-res pixels (empty without a previous frame)
  ImageU8 limit;        // steps 2, 4, 5: kLimitChannels channels, padded full-res grid
};
// Steps 1–5 on the padded full-res grid: ℓ_min = min(coarsest enabled, max(fovea, motion)).
LevelLimit levelLimit(const GBuffer& g, const View& view, const Constants& c);

// Step 6: M_ℓ(q) = 0 for every enabled level ℓ below the coarsest where ℓ < ℓ_min at the full-res
// pixel q holds (levelSamplePixel). Before the blur (cpu_ref/masks.cpp: buildMasks).
void applyLevelLimit(Masks& masks, const ImageU8& limit, const Constants& c);
// Step 6 for tiles: limitTileRates (common/frame.h), shared with the port.

}  // namespace mrr
