#pragma once
// `mrr probe`: follows one full-res pixel through every stage of a rendered frame — the
// per-pixel mask debugger. Values are read from the FrameResult, and the decisions that
// produced them (edge derivatives, bilinear taps, SSAO sample counts) are recomputed by the
// same functions the stages use, so what it prints is what the pipeline did.
#include <nlohmann/json.hpp>

#include <string>

#include "cpu_ref/pipeline.h"

namespace mrr {

nlohmann::json probePixel(const FrameResult& frame, int x, int y);
std::string formatProbe(const nlohmann::json& probe);

}  // namespace mrr
