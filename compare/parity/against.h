#pragma once
// Another renderer's stages against the oracle (`mrr compare --against FILE`). FILE is
// a multi-part EXR with the parts and channels `mrr render --stages` writes (any subset; `final`
// alone is enough), or a folder of single-part PART.exr files. Each part present takes the place
// of the oracle's in a copy of the oracle's frame, and that frame goes through the one
// comparison (compare/parity/parity.cpp): end to end against the oracle's stage, and same-input where
// the file holds the stage's own inputs (edges on its G-buffer, masks on its edges, the effect on
// its G-buffer and stencils, the blend on its sub-images). Stages the file lacks are not checked.
#include <set>
#include <string>
#include <vector>

#include "compare/parity/parity.h"

namespace mrr {

struct ForeignStages {
  std::string source;              // FILE, as given
  FrameResult frame;               // the oracle's frame with the file's parts in place of its own
  std::set<std::string> supplied;  // the parts the file holds ("gbuffer.L0", "final", ...)
  std::vector<std::string> absent; // the oracle's parts the file lacks, in pipeline order
  std::vector<std::string> ignored;  // parts of the file that name no stage (kept out, a warning)
};

// Reads FILE against the oracle's frame (rendered with keepStages, with the same options the
// stages were made with). Throws MrrError, one line: FILE missing, not a stages file (no part
// names a stage), a part the oracle's frame has no stage for, a part of the wrong size or
// missing a channel.
ForeignStages readForeignStages(const std::string& path, const FrameResult& oracle);

// The comparison of the file's stages with the oracle's: compareFrames' rows, only those of
// stages the file holds, and each same-input check only where the file holds one of that
// check's inputs (else the stage is judged end to end alone; a stage with no end-to-end rule
// keeps its check, which then runs on the oracle's inputs).
ParityResult compareForeign(const FrameResult& oracle, const ForeignStages& foreign, const DirectionalLight& light);

}  // namespace mrr
