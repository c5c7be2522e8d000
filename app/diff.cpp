#include "app/diff.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/frame_params.h"
#include "common/error.h"
#include "common/image_io.h"
#include "compare/metrics/metrics.h"
#include "compare/metrics/flip.h"

namespace mrr {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// An image as a viewer sees it: display values in [0,1], 1 channel (grey) or 3 (sRGB).
struct Displayed {
  ImageF image;
  std::string how;  // one line: what was done to show it
};

Displayed display(const std::string& path, const std::string& tonemap) {
  ImageF in = readImage(path);
  const std::string ext = lowerExtension(path);
  const bool linear = ext == ".exr" || ext == ".hdr";
  const int channels = in.channels >= 3 ? 3 : 1;  // a 2nd channel of 2, a 4th of 4: alpha, dropped
  Displayed d;
  d.image = ImageF::uninitialised(in.width, in.height, channels);
  const bool encode = linear && channels == 3;
  const bool reinhard = encode && tonemap == "reinhard";
  for (size_t p = 0; p < in.pixelCount(); ++p)
    for (int c = 0; c < channels; ++c) {
      float v = in.data[p * static_cast<size_t>(in.channels) + static_cast<size_t>(c)];
      if (std::isnan(v)) v = 0.0f;
      if (reinhard) v = std::max(v, 0.0f) / (1.0f + std::max(v, 0.0f));
      d.image.data[p * static_cast<size_t>(channels) + static_cast<size_t>(c)] = std::clamp(v, 0.0f, 1.0f);
    }
  if (encode) d.image = linearToDisplay(d.image);
  const std::string kind = ext.empty() ? "image" : ext.substr(1);
  std::string upper = kind;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (!linear)
    d.how = upper + (channels == 3 ? " RGB" : " grey") + ", sRGB values as stored";
  else if (channels == 3)
    d.how = upper + " RGB, linear: " + (reinhard ? "tone-mapped (Reinhard, x/(1+x))" : "clamped to [0,1]") +
            ", then sRGB-encoded";
  else
    d.how = upper + " 1 channel (an effect buffer): shown as grey, clamped to [0,1], as mrr's PNG preview shows it";
  return d;
}

// Grey against colour: the grey repeated in R, G and B, so the metrics compare like with like.
ImageF toRgb(const ImageF& grey) {
  ImageF out = ImageF::uninitialised(grey.width, grey.height, 3);
  for (size_t p = 0; p < grey.pixelCount(); ++p)
    for (size_t c = 0; c < 3; ++c) out.data[3 * p + c] = grey.data[p];
  return out;
}

std::string number(double v, int digits = 4) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "nan";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

}  // namespace

void addDiffCommand(CLI::App& app, DiffOptions& o) {
  o.command = app.add_subcommand(
      "diff", "compare any two images (PNG or EXR) as a viewer sees them: RMS, PSNR, SSIM, max |Δ| and FLIP");
  o.command->add_option("reference", o.reference, "the reference image (.png, .exr, or any format OpenImageIO reads)")
      ->required();
  o.command->add_option("test", o.test, "the image compared with it, of the same size")->required();
  o.command->add_option(optionName(Param::Ppd), o.ppd,
                        "viewing conditions for FLIP, pixels per degree (default 67.02: a 0.7 m wide 4K display at 0.7 m)");
  o.command->add_option("--tonemap", o.tonemap,
                        "EXR with colour, before sRGB encoding: clamp (to [0,1]) or reinhard (x/(1+x))")
      ->capture_default_str();
  o.command->add_option("--map", o.mapOut, "write the FLIP error map: .png through the magma scale, .exr as values");
  o.command->add_flag("--legend", o.legend, "with --map .png: add the colour bar (0 left, 1 right, ticks each 0.1)");
  o.command->add_option("--json", o.jsonOut, "write the figures as JSON");
  o.command->add_option("--fail-above", o.failAbove, "exit 1 when the mean FLIP exceeds this (for scripts)");
}

int runDiff(const DiffOptions& o) {
  const double ppd = o.ppd.value_or(kFlipDefaultPpd);
  require(std::isfinite(ppd) && ppd > 0.0 && ppd <= 1000.0, "--ppd: must be in (0, 1000]");
  require(o.tonemap == "clamp" || o.tonemap == "reinhard", "--tonemap " + o.tonemap + ": expected clamp or reinhard");
  require(!o.failAbove || (std::isfinite(*o.failAbove) && *o.failAbove >= 0.0), "--fail-above: must be a number >= 0");
  // Outputs are checked before any work, each with its option's name.
  if (!o.mapOut.empty()) {
    const std::string ext = lowerExtension(o.mapOut);
    require(ext == ".png" || ext == ".exr", "--map " + o.mapOut + ": expected a .png or .exr file");
    checkOutputLocation(o.mapOut, "--map");
  }
  if (!o.jsonOut.empty()) {
    require(lowerExtension(o.jsonOut) == ".json", "--json " + o.jsonOut + ": expected a .json file");
    checkOutputLocation(o.jsonOut, "--json");
  }
  require(o.mapOut.empty() || o.mapOut != o.jsonOut, "--map and --json name the same file " + o.mapOut);

  Displayed ref = display(o.reference, o.tonemap);
  Displayed test = display(o.test, o.tonemap);
  require(ref.image.width == test.image.width && ref.image.height == test.image.height,
          o.reference + " (" + std::to_string(ref.image.width) + "x" + std::to_string(ref.image.height) + ") and " +
              o.test + " (" + std::to_string(test.image.width) + "x" + std::to_string(test.image.height) +
              ") differ in size");
  if (ref.image.channels != test.image.channels) {
    if (ref.image.channels == 1) ref.image = toRgb(ref.image);
    if (test.image.channels == 1) test.image = toRgb(test.image);
  }

  const FlipResult f = flip(ref.image, test.image, ppd);
  const double rms = rmsError(test.image, ref.image);
  const double psnrDb = psnr(test.image, ref.image);
  const double ssimValue = ssim(test.image, ref.image);
  const double maxAbs = maxAbsError(test.image, ref.image);

  std::ostringstream text;
  text << "== diff " << o.reference << " (reference) against " << o.test << ", " << ref.image.width << "x"
       << ref.image.height << "\n"
       << "reference: " << ref.how << "\n"
       << "test:      " << test.how << "\n"
       << "RMS        " << number(rms, 6) << "\n"
       << "PSNR       " << (std::isfinite(psnrDb) ? number(psnrDb, 2) + " dB" : std::string("inf (identical)")) << "\n"
       << "SSIM       " << number(ssimValue, 6) << "\n"
       << "max |Δ|    " << number(maxAbs, 6) << "\n"
       << "FLIP       mean " << number(f.stats.mean, 6) << ", median " << number(f.stats.median, 6) << ", q1 "
       << number(f.stats.q1, 6) << ", q3 " << number(f.stats.q3, 6) << ", max " << number(f.stats.max, 6)
       << " (LDR-FLIP at " << number(ppd, 2) << " pixels per degree)\n";
  std::cout << text.str();

  if (!o.jsonOut.empty()) {
    const nlohmann::json j = {
        {"rms", rms},
        {"psnr", std::isfinite(psnrDb) ? nlohmann::json(psnrDb) : nlohmann::json(nullptr)},  // null: identical
        {"ssim", ssimValue},
        {"max_abs", maxAbs},
        {"flip",
         nlohmann::json(f.stats)}};
    writeTextFile(o.jsonOut, j.dump(2) + "\n");
  }
  if (!o.mapOut.empty()) {
    if (lowerExtension(o.mapOut) == ".exr")
      writeImage(o.mapOut, f.errorMap, {"Y"});
    else
      writeImage(o.mapOut, flipColourMap(f.errorMap, o.legend));
  }
  if (o.failAbove && f.stats.mean > *o.failAbove) {
    std::cerr << "mrr diff: mean FLIP " << number(f.stats.mean, 6) << " is above --fail-above " << *o.failAbove
              << "\n";
    return 1;
  }
  return 0;
}

}  // namespace mrr
