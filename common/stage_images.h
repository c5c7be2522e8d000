#pragma once
// The stage list's images in a frame: what the rows of kParts (common/stages.h) point to, and what
// the stages EXR (compare/report/report.cpp), `compare --against` (compare/parity/against.cpp),
// the compare page (compare/parity/html_report.cpp) and explore's layers (explore/layers.cpp)
// build from the rows. Each part's accessor (PartImageAccess, defined in stage_images.cpp) reads
// its image in its EXR channel layout and writes it back; nothing else knows where a part lies
// in a FrameResult.
#include <string>
#include <vector>

#include "common/frame.h"
#include "common/stages.h"

namespace mrr {

// A part at a level (-1 for a part not per level), named as the stages EXR names it.
struct PartRef {
  Part part;
  int level = -1;
  std::string name() const { return partName(part, level); }
};

// Every part `frame` holds, in the stages EXR's order: the table's order, each run of per-level
// rows taken level by level, finest first, over the frame's enabled levels (the G-buffers first;
// then the parts not per level; then per level marks … composite; then levelmap, final, shaded).
std::vector<PartRef> heldParts(const FrameResult& frame);

// The row's accessor (PartImageAccess): whether the frame holds the part, its image in its EXR
// channel layout (empty when not held), and that image written back in place of the frame's own.
inline bool holdsPart(const FrameResult& frame, Part part, int level = -1) {
  return partInfo(part).image->holds(frame, level);
}
inline ImageF readPart(const FrameResult& frame, Part part, int level = -1) {
  return partInfo(part).image->read(frame, level);
}
inline void writePart(FrameResult& frame, Part part, int level, const ImageF& image) {
  partInfo(part).image->write(frame, level, image);
}

// The EXR channel names of `image`, the part's image as read: the row's `channels` for its channel
// count (an effect part has 1, or 3 for SSGI's RGB), trailing channels it lacks left out (edges
// without the shadow kind). Throws MrrError when the image has more channels than the row names.
std::vector<std::string> partChannels(Part part, const ImageF& image);

// Whether a same-input check reads an input marked `when` in a frame of `c`.
bool inputApplies(InputWhen when, const Constants& c);
// The parts the same-input check of `part` at `level` reads in a frame of `c`, by name, from the
// row's inputs ("gbuffer.L0", "shadowmap"; the next coarser enabled level's, every coarser
// level's, every level's as the rows say).
std::vector<std::string> partInputNames(Part part, int level, const Constants& c);

// The row's caption with how its display shows an image of `channels` channels, the words the
// compare page and explore both show ("the stencil S_ℓ: shaded at this level: 1 white, 0 black").
std::string viewCaption(Part part, int channels);

// Channel `c` of `image`, as a one-channel image.
ImageF imageChannel(const ImageF& image, int c);

}  // namespace mrr
