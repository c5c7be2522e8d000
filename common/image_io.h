#pragma once
// Image and file output through OpenImageIO. Every write goes to a temporary file in the
// same directory and is renamed into place, so an interrupted run never leaves a partial
// output (brief: "never leaves a half-written output").
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/image.h"

namespace mrr {

// Fails early, with one line, when `path` cannot be written: its directory is missing or
// not writable, or the path is a directory. `what` names the option ("--out").
void checkOutputPath(const std::string& path, const std::string& what);
// The same checks without the extension rule (for text outputs of any kind).
void checkOutputLocation(const std::string& path, const std::string& what);

// Writes an image by extension: .exr as float32 with `channelNames` (one per channel;
// empty = R,G,B,A or Y), .png as an opaque 8-bit preview (values clamped to [0,1],
// sRGB-encoded when `srgb`). Throws MrrError on failure.
void writeImage(const std::string& path, const ImageF& image,
                const std::vector<std::string>& channelNames = {}, bool srgb = false);

// One part of a multi-part EXR: its own size, named channels.
struct ExrPart {
  std::string name;
  ImageF image;
  std::vector<std::string> channelNames;
};

// Writes all parts into one multi-part EXR (`oiiotool -a --info` lists them). Every part
// shares the display window displayWidth×displayHeight, as OpenEXR requires.
// `metadata` (name, text) goes into every part's header (e.g. "mrr:frame", the frame file).
void writeMultiPartExr(const std::string& path, const std::vector<ExrPart>& parts,
                       int displayWidth, int displayHeight,
                       const std::vector<std::pair<std::string, std::string>>& metadata = {});

// Reads every part of an EXR (or the single image of any other format).
std::vector<ExrPart> readParts(const std::string& path);
ImageF readImage(const std::string& path);

// Writes text (JSON reports) atomically.
void writeTextFile(const std::string& path, const std::string& text);

// Reads a JSON object from `path` (a frame file, a cost model, a sweep): throws MrrError
// "OPTION PATH: cannot read the file" or "OPTION PATH: not a JSON object".
nlohmann::json readJsonObjectFile(const std::string& path, const std::string& option);

// On SIGINT, SIGTERM or SIGHUP: removes the temporary files of the writes in flight, then
// dies of that signal as usual (a shell sees 128 + n). main() installs it once, so an
// interrupted run leaves no partial file behind (tests/cli: the kill tests).
void removeTemporariesOnInterrupt();

// The temporary name used for `path` (same directory, same extension); exposed for tests.
std::string temporaryPathFor(const std::string& path);

}  // namespace mrr
