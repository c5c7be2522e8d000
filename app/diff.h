#pragma once
// `mrr diff REF TEST`: any two images, PNG or EXR, compared as a viewer sees them:
// RMS, PSNR, SSIM, max |Δ| (compare/metrics/metrics.h) and LDR-FLIP (compare/metrics/flip.h), printed and
// optionally written as JSON and as a FLIP map. docs/diff.md shows it.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace mrr {

struct DiffOptions {
  CLI::App* command = nullptr;  // set by addDiffCommand: `if (opts.command->parsed())`
  std::string reference, test;
  std::optional<double> ppd;    // absent: compare/metrics/flip.h's kFlipDefaultPpd
  std::string tonemap = "clamp";  // EXR with colour: clamp or reinhard, then sRGB-encoded
  std::string mapOut, jsonOut;
  bool legend = false;
  std::optional<double> failAbove;
};

void addDiffCommand(CLI::App& app, DiffOptions& o);
// 0: compared (and under --fail-above); 1: mean FLIP above --fail-above. Bad input throws
// MrrError (exit 2 in main).
int runDiff(const DiffOptions& o);

}  // namespace mrr
