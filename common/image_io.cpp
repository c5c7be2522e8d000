#include "common/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

#include "common/error.h"

namespace fs = std::filesystem;

namespace mrr {

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// The directory a relative bare file name lives in, for messages and access().
fs::path parentOf(const std::string& path) {
  fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

// OIIO errors may span lines; MrrError flattens them, this only supplies a fallback text.
std::string oiioMessage(const std::string& text) {
  return text.empty() ? std::string("unknown OpenImageIO error") : text;
}

void removeQuietly(const std::string& path) {
  std::error_code ignored;
  fs::remove(path, ignored);
}

void renameIntoPlace(const std::string& temporary, const std::string& path) {
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    removeQuietly(temporary);
    throw MrrError("cannot write " + path + ": rename failed: " + ec.message());
  }
}

std::vector<std::string> defaultChannelNames(int channels) {
  switch (channels) {
    case 1: return {"Y"};
    case 3: return {"R", "G", "B"};
    case 4: return {"R", "G", "B", "A"};
    default: break;
  }
  std::vector<std::string> names;
  for (int c = 0; c < channels; ++c) {
    std::string name = "c";  // appended, not "c" + ...: avoids GCC 12's false -Wrestrict
    name += std::to_string(c);
    names.push_back(name);
  }
  return names;
}

std::vector<std::string> channelNamesFor(const std::string& path, const ImageF& image,
                                         const std::vector<std::string>& given) {
  if (given.empty()) return defaultChannelNames(image.channels);
  require(static_cast<int>(given.size()) == image.channels,
          "cannot write " + path + ": " + std::to_string(given.size()) +
              " channel names for " + std::to_string(image.channels) + " channels");
  return given;
}

void requireWellFormed(const std::string& path, const ImageF& image) {
  require(image.width > 0 && image.height > 0 && image.channels > 0,
          "cannot write " + path + ": empty image (" + std::to_string(image.width) + "x" +
              std::to_string(image.height) + "x" + std::to_string(image.channels) + ")");
  require(image.data.size() == image.pixelCount() * static_cast<size_t>(image.channels),
          "cannot write " + path + ": image data size does not match its dimensions");
}

// The standard piecewise sRGB OETF (IEC 61966-2-1).
double srgbEncode(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

uint8_t toByte(float value, bool srgb) {
  double v = std::isnan(value) ? 0.0 : std::clamp(static_cast<double>(value), 0.0, 1.0);
  if (srgb) v = std::clamp(srgbEncode(v), 0.0, 1.0);
  return static_cast<uint8_t>(std::lround(v * 255.0));
}

// PNG previews are opaque (docs/platform.md: alpha < 1 is un-premultiplied on write): 1 channel
// is grey, 2 channels go to R and G with B = 0, 3 are RGB, and a 4th (alpha) is dropped.
ImageU8 pngPreview(const std::string& path, const ImageF& image, bool srgb) {
  require(image.channels >= 1 && image.channels <= 4,
          "cannot write " + path + ": PNG takes 1 to 4 channels, image has " +
              std::to_string(image.channels) + " (use .exr)");
  const int outChannels = image.channels == 1 ? 1 : 3;
  const int copied = std::min(image.channels, 3);
  ImageU8 out(image.width, image.height, outChannels, 0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < copied; ++c) out.at(x, y, c) = toByte(image.at(x, y, c), srgb);
  return out;
}

// The temporary files being written right now, where a signal handler can find them: fixed
// slots of plain chars (nothing a handler may not touch), claimed and released atomically.
struct InFlight {
  static constexpr size_t kSlots = 32;
  static constexpr size_t kPathBytes = 4096;
  std::atomic<bool> used[kSlots] = {};
  std::atomic<bool> ready[kSlots] = {};
  char path[kSlots][kPathBytes] = {};
};
InFlight& inFlight() {
  static InFlight registry;
  return registry;
}

// Holds a temporary path in the registry for the lifetime of one write.
class InFlightGuard {
 public:
  explicit InFlightGuard(const std::string& temporary) {
    InFlight& r = inFlight();
    if (temporary.size() >= InFlight::kPathBytes) return;
    for (size_t i = 0; i < InFlight::kSlots; ++i) {
      bool expected = false;
      if (r.used[i].compare_exchange_strong(expected, true)) {
        std::memcpy(r.path[i], temporary.c_str(), temporary.size() + 1);
        r.ready[i].store(true);
        slot_ = static_cast<int>(i);
        return;
      }
    }
  }
  ~InFlightGuard() {
    if (slot_ < 0) return;
    InFlight& r = inFlight();
    r.ready[static_cast<size_t>(slot_)].store(false);
    r.used[static_cast<size_t>(slot_)].store(false);
  }
  InFlightGuard(const InFlightGuard&) = delete;
  InFlightGuard& operator=(const InFlightGuard&) = delete;

 private:
  int slot_ = -1;
};

extern "C" void removeTemporariesAndDie(int signal) {
  InFlight& r = inFlight();
  for (size_t i = 0; i < InFlight::kSlots; ++i)
    if (r.ready[i].load()) ::unlink(r.path[i]);  // async-signal-safe
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Runs `body` on a fresh temporary name and moves the file into place; any failure
// removes the temporary file so no partial output remains, and so does SIGINT or SIGTERM
// once removeTemporariesOnInterrupt() is installed.
template <class Body>
void writeAtomically(const std::string& path, Body&& body) {
  const std::string temporary = temporaryPathFor(path);
  InFlightGuard guard(temporary);
  try {
    body(temporary);
  } catch (...) {
    removeQuietly(temporary);
    throw;
  }
  renameIntoPlace(temporary, path);
}

std::unique_ptr<OIIO::ImageOutput> createOutput(const std::string& path,
                                                const std::string& temporary) {
  auto out = OIIO::ImageOutput::create(temporary);
  if (!out) throw MrrError("cannot write " + path + ": " + oiioMessage(OIIO::geterror()));
  return out;
}

[[noreturn]] void failOutput(const std::string& path, OIIO::ImageOutput& out) {
  std::string message = out.geterror();
  out.close();
  throw MrrError("cannot write " + path + ": " + oiioMessage(message));
}

OIIO::ImageSpec floatSpec(const ImageF& image, const std::vector<std::string>& names) {
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  // No alpha role unless the caller named a channel "A".
  spec.alpha_channel = -1;
  for (int c = 0; c < image.channels; ++c)
    if (names[static_cast<size_t>(c)] == "A") spec.alpha_channel = c;
  spec.attribute("compression", "zip");  // lossless, so float data round-trips bit-exactly
  // OIIO stamps the current time when no DateTime is set: the same render would then write
  // different bytes a second later. A fixed value keeps outputs byte-reproducible.
  spec.attribute("DateTime", "");
  return spec;
}

}  // namespace

// The part of checkOutputPath that does not look at the extension.
void checkOutputLocation(const std::string& path, const std::string& what) {
  const std::string prefix = what + " " + path + ": ";
  require(!path.empty(), what + ": empty path");
  std::error_code ec;
  require(!fs::is_directory(path, ec), prefix + "is a directory");
  const fs::path parent = parentOf(path);
  require(fs::exists(parent, ec), prefix + "directory " + parent.string() + " does not exist");
  require(fs::is_directory(parent, ec), prefix + parent.string() + " is not a directory");
  require(::access(parent.c_str(), W_OK) == 0,
          prefix + "directory " + parent.string() + " is not writable");
}


void checkOutputPath(const std::string& path, const std::string& what) {
  const std::string prefix = what + " " + path + ": ";
  require(!path.empty(), what + ": empty path");
  std::error_code ec;
  require(!fs::is_directory(path, ec), prefix + "is a directory");
  const std::string ext = lowerExtension(path);
  require(ext == ".exr" || ext == ".png" || ext == ".json",
          prefix + "unsupported extension \"" + ext +
              "\" (use .exr or .png for images, .json for reports)");
  checkOutputLocation(path, what);
}

void removeTemporariesOnInterrupt() {
  inFlight();  // constructed now, never inside the handler
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, removeTemporariesAndDie);
}

std::string temporaryPathFor(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  const fs::path target(path);
  const std::string name = "." + target.filename().string() + ".tmp-" +
                           std::to_string(static_cast<long>(::getpid())) + "-" +
                           std::to_string(counter.fetch_add(1)) + target.extension().string();
  return (target.parent_path() / name).string();
}

void writeImage(const std::string& path, const ImageF& image,
                const std::vector<std::string>& channelNames, bool srgb) {
  checkOutputPath(path, "output");
  requireWellFormed(path, image);
  const std::string ext = lowerExtension(path);
  require(ext == ".exr" || ext == ".png",
          "cannot write " + path + ": unsupported image extension (use .exr or .png)");

  if (ext == ".exr") {
    const OIIO::ImageSpec spec = floatSpec(image, channelNamesFor(path, image, channelNames));
    writeAtomically(path, [&](const std::string& temporary) {
      auto out = createOutput(path, temporary);
      if (!out->open(temporary, spec)) failOutput(path, *out);
      if (!out->write_image(OIIO::TypeDesc::FLOAT, image.data.data())) failOutput(path, *out);
      if (!out->close()) failOutput(path, *out);
    });
    return;
  }

  const ImageU8 preview = pngPreview(path, image, srgb);
  OIIO::ImageSpec spec(preview.width, preview.height, preview.channels, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = -1;
  if (srgb) spec.attribute("oiio:ColorSpace", "sRGB");
  writeAtomically(path, [&](const std::string& temporary) {
    auto out = createOutput(path, temporary);
    if (!out->open(temporary, spec)) failOutput(path, *out);
    if (!out->write_image(OIIO::TypeDesc::UINT8, preview.data.data())) failOutput(path, *out);
    if (!out->close()) failOutput(path, *out);
  });
}

void writeMultiPartExr(const std::string& path, const std::vector<ExrPart>& parts, int displayWidth,
                       int displayHeight, const std::vector<std::pair<std::string, std::string>>& metadata) {
  checkOutputPath(path, "output");
  require(lowerExtension(path) == ".exr",
          "cannot write " + path + ": multi-part images must be .exr");
  require(!parts.empty(), "cannot write " + path + ": no parts to write");
  require(displayWidth > 0 && displayHeight > 0,
          "cannot write " + path + ": bad display window " + std::to_string(displayWidth) +
              "x" + std::to_string(displayHeight));

  std::vector<OIIO::ImageSpec> specs;
  std::set<std::string> seen;
  for (const ExrPart& part : parts) {
    require(!part.name.empty(), "cannot write " + path + ": a part has no name");
    require(seen.insert(part.name).second,
            "cannot write " + path + ": part name \"" + part.name + "\" is used twice");
    requireWellFormed(path + " (part " + part.name + ")", part.image);
    OIIO::ImageSpec spec = floatSpec(part.image, channelNamesFor(path, part.image, part.channelNames));
    // OpenEXR requires one display window for all parts (docs/platform.md).
    spec.full_x = 0;
    spec.full_y = 0;
    spec.full_width = displayWidth;
    spec.full_height = displayHeight;
    spec.attribute("name", part.name);
    for (const auto& [key, text] : metadata) spec.attribute(key, text);
    specs.push_back(std::move(spec));
  }

  writeAtomically(path, [&](const std::string& temporary) {
    auto out = createOutput(path, temporary);
    // OpenEXR declares every part up front (open with nparts); it reports no
    // "appendsubimage" support, yet takes AppendSubimage for the declared parts.
    if (parts.size() > 1 && !out->supports("multiimage"))
      throw MrrError("cannot write " + path + ": the EXR writer does not support multiple parts");
    if (!out->open(temporary, static_cast<int>(specs.size()), specs.data()))
      failOutput(path, *out);
    for (size_t i = 0; i < parts.size(); ++i) {
      if (i > 0 && !out->open(temporary, specs[i], OIIO::ImageOutput::AppendSubimage))
        failOutput(path, *out);
      if (!out->write_image(OIIO::TypeDesc::FLOAT, parts[i].image.data.data()))
        failOutput(path, *out);
    }
    if (!out->close()) failOutput(path, *out);
  });
}

std::vector<ExrPart> readParts(const std::string& path) {
  std::error_code ec;
  require(fs::is_regular_file(path, ec), "cannot read " + path + ": no such file");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw MrrError("cannot read " + path + ": " + oiioMessage(OIIO::geterror()));

  std::vector<ExrPart> parts;
  for (int subimage = 0; in->seek_subimage(subimage, 0); ++subimage) {
    const OIIO::ImageSpec& spec = in->spec();
    require(spec.width > 0 && spec.height > 0 && spec.nchannels > 0 && spec.depth <= 1,
            "cannot read " + path + ": subimage " + std::to_string(subimage) +
                " is empty or not a 2D image");
    ExrPart part;
    part.name = spec.get_string_attribute("name");
    // Channel order as OIIO reports it (it may sort extra channels): callers look up by name.
    part.channelNames.assign(spec.channelnames.begin(), spec.channelnames.end());
    part.image = ImageF(spec.width, spec.height, spec.nchannels);
    if (!in->read_image(subimage, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                        part.image.data.data())) {
      std::string message = in->geterror();
      throw MrrError("cannot read " + path + ": " + oiioMessage(message));
    }
    parts.push_back(std::move(part));
  }
  // seek_subimage past the last part sets an error we do not want to leak into later calls.
  (void)in->geterror();
  require(!parts.empty(), "cannot read " + path + ": no images in file");
  return parts;
}

ImageF readImage(const std::string& path) { return std::move(readParts(path).front().image); }

nlohmann::json readJsonObjectFile(const std::string& path, const std::string& option) {
  std::ifstream in(path);
  if (!in.good()) throw MrrError(option + " " + path + ": cannot read the file");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw MrrError(option + " " + path + ": not a JSON object");
  return j;
}

void writeTextFile(const std::string& path, const std::string& text) {
  checkOutputLocation(path, "output");  // any extension: callers check theirs
  writeAtomically(path, [&](const std::string& temporary) {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw MrrError("cannot write " + path + ": " + std::strerror(errno));
    stream.write(text.data(), static_cast<std::streamsize>(text.size()));
    stream.flush();
    if (!stream) throw MrrError("cannot write " + path + ": write failed");
    stream.close();
    if (stream.fail()) throw MrrError("cannot write " + path + ": close failed");
  });
}

}  // namespace mrr
