// Images between the oracle and numpy, and the masks a frame takes from Python (docs/python.md,
// SPEC §3): what a mask rule sees, and its arrays checked and put in place of the method's.
#include "cpu_ref/masks.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <sstream>

#include "common/methods.h"
#include "common/stage_images.h"
#include "common/stages.h"
#include "python/src/module.h"

namespace mrr::python {

namespace {

// The (H, W) or (H, W, C) shape of an image, as numpy writes it.
std::vector<py::ssize_t> shapeOf(const ImageF& image) {
  if (image.channels == 1) return {image.height, image.width};
  return {image.height, image.width, image.channels};
}

// Marks an array read-only: the frame's stages are what it rendered (copy to change them).
py::array readOnly(py::array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// "(54, 96)": a shape as Python prints it.
std::string shapeText(int height, int width) {
  return "(" + std::to_string(height) + ", " + std::to_string(width) + ")";
}

// An array's shape as Python prints it: "(4,)", "(54, 96, 3)".
std::string shapeText(const py::array& a) {
  std::ostringstream out;
  out << "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) out << (i ? ", " : "") << a.shape(i) << (a.ndim() == 1 ? "," : "");
  out << ")";
  return out.str();
}

// A mask rule's array for level image `name` on a w×h grid, as floats: a numpy array of that
// shape (or with one channel more, of size 1) of bools, integers or reals.
ImageF levelArray(const py::handle& value, const std::string& name, int width, int height) {
  const std::string expected = "expected a numpy array of shape " + shapeText(height, width);
  if (!py::isinstance<py::array>(value))
    throw BadValue(name + ": " + std::string(py::str(py::type::of(value).attr("__name__"))) + ", " + expected);
  const py::array a = py::reinterpret_borrow<py::array>(value);
  const char kind = a.dtype().kind();
  if (kind != 'b' && kind != 'u' && kind != 'i' && kind != 'f')
    throw BadValue(name + ": dtype " + std::string(py::str(a.dtype())) + ", " + expected +
                   " of bool, integers or floats");
  const bool fits =
      (a.ndim() == 2 || (a.ndim() == 3 && a.shape(2) == 1)) && a.shape(0) == height && a.shape(1) == width;
  if (!fits) throw BadValue(name + ": shape " + shapeText(a) + ", " + expected + " (the level's padded grid)");
  return imageFromArray(a.ndim() == 3 ? py::array(a.attr("reshape")(height, width)) : a, name);
}

// A binary image (M_ℓ, S_ℓ) from floats that must all be 0 or 1.
ImageU8 binary(const ImageF& image, const std::string& name) {
  ImageU8 out(image.width, image.height, 1);
  for (size_t i = 0; i < image.data.size(); ++i) {
    const float v = image.data[i];
    if (v != 0.0f && v != 1.0f)
      throw BadValue(name + ": value " + py::str(py::float_(v)).cast<std::string>() + " at pixel (" +
                     std::to_string(i % static_cast<size_t>(image.width)) + ", " +
                     std::to_string(i / static_cast<size_t>(image.width)) + "); a mask or stencil holds 0 and 1 only");
    out.data[i] = v != 0.0f;
  }
  return out;
}

// "mask.L2" → (Part::Mask, 2); nullopt when the key is no per-level mask part.
std::optional<std::pair<Part, int>> maskKey(const std::string& key) {
  for (Part part : {Part::Mask, Part::Alpha, Part::Stencil})
    for (int l = 0; l < kLevelCount; ++l)
      if (key == partName(part, l)) return std::make_pair(part, l);
  return std::nullopt;
}

}  // namespace

py::array ownedArray(ImageF&& image) {
  auto* owned = new ImageF(std::move(image));
  py::capsule free(owned, [](void* p) { delete static_cast<ImageF*>(p); });
  return readOnly(py::array(py::dtype::of<float>(), shapeOf(*owned), {}, owned->data.data(), free));
}

py::array viewArray(const ImageF& image, std::shared_ptr<const void> owner) {
  auto* keep = new std::shared_ptr<const void>(std::move(owner));
  py::capsule release(keep, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
  return readOnly(py::array(py::dtype::of<float>(), shapeOf(image), {}, image.data.data(), release));
}

ImageF imageFromArray(const py::handle& value, const std::string& what) {
  if (!py::isinstance<py::array>(value) && !py::isinstance<py::list>(value))
    throw BadValue(what + ": expected a numpy array of shape (H, W) or (H, W, C)");
  py::array a = py::array::ensure(value);
  if (!a) throw BadValue(what + ": not convertible to a numpy array");
  const char kind = a.dtype().kind();
  if (kind != 'b' && kind != 'u' && kind != 'i' && kind != 'f')
    throw BadValue(what + ": dtype " + std::string(py::str(a.dtype())) + ", expected bool, integers or floats");
  if (a.ndim() != 2 && a.ndim() != 3)
    throw BadValue(what + ": shape " + shapeText(a) + ", expected (H, W) or (H, W, C)");
  if (a.shape(0) < 1 || a.shape(1) < 1 || (a.ndim() == 3 && (a.shape(2) < 1 || a.shape(2) > 16)))
    throw BadValue(what + ": shape " + shapeText(a) + ", expected H, W >= 1 and 1 to 16 channels");
  const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  ImageF image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)),
               a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1);
  std::memcpy(image.data.data(), f.data(), image.data.size() * sizeof(float));
  return image;
}

py::dict maskContext(const FrameResult& f, const Masks& masks) {
  py::dict ctx;
  for (Part part : {Part::GBuffer, Part::ShadowTest, Part::Edges, Part::Eccentricity, Part::Motion, Part::LevelLimit}) {
    const PartImageAccess& access = *partInfo(part).image;
    if (access.holds(f, 0)) ctx[py::str(partName(part, 0))] = ownedArray(access.read(f, 0));
  }
  const Constants& c = f.constants;
  for (int l = 0; l < kLevelCount; ++l) {
    if (!c.levels[static_cast<size_t>(l)].enabled) continue;
    const MaskLevel& m = masks[static_cast<size_t>(l)];
    if (!m.mask.empty()) ctx[py::str(partName(Part::Mask, l))] = ownedArray(toFloat(m.mask));
    if (!m.alpha.empty()) ctx[py::str(partName(Part::Alpha, l))] = ownedArray(ImageF(m.alpha));
    if (!m.stencil.empty()) ctx[py::str(partName(Part::Stencil, l))] = ownedArray(toFloat(m.stencil));
  }
  return ctx;
}

std::vector<std::string> applyUserMasks(const py::dict& given, const FrameResult& f, Masks& masks) {
  const Constants& c = f.constants;
  // Every key checked, and every array converted, before anything is replaced.
  struct Entry {
    std::string key;
    Part part;
    int level;
    ImageF image;
  };
  std::vector<Entry> entries;
  for (const auto& [k, v] : given) {
    const std::string key = py::str(k);
    const auto parsed = maskKey(key);
    if (!parsed)
      throw BadValue("masks: unknown stage " + key +
                     "; a mask rule gives mask.L<l> (M_l, before the blur), "
                     "alpha.L<l> (a_l) or stencil.L<l> (S_l), l in 0.." +
                     std::to_string(kLevelCount - 1));
    const auto [part, level] = *parsed;
    const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
    if (!lc.enabled)
      throw BadValue(key + ": level " + std::to_string(level) + " is disabled in this frame (method " +
                     toString(c.mode) + ")");
    ImageF image = levelArray(v, key, lc.width, lc.height);
    if (part != Part::Alpha) binary(image, key);  // checks the values
    entries.push_back({key, part, level, std::move(image)});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return std::make_pair(static_cast<int>(a.part), a.level) < std::make_pair(static_cast<int>(b.part), b.level);
  });
  // SPEC §3 steps 2–4 on the pyramid with the given M_ℓ: every level the blur reads needs one.
  bool pyramid = false;
  for (Entry& e : entries)
    if (e.part == Part::Mask) {
      masks[static_cast<size_t>(e.level)].mask = binary(e.image, e.key);
      pyramid = true;
    }
  if (pyramid) {
    for (int l = 0; l < kLevelCount; ++l) {
      const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
      if (lc.enabled && l != c.coarsestEnabled && masks[static_cast<size_t>(l)].mask.empty())
        throw BadValue(partName(Part::Mask, l) + ": method " + toString(c.mode) +
                       " has no M_l there; give it too (shape " + shapeText(lc.height, lc.width) +
                       "), or give stencils");
    }
    stencilsFromPyramid(masks, c);
  }
  for (Entry& e : entries) {
    MaskLevel& m = masks[static_cast<size_t>(e.level)];
    if (e.part == Part::Alpha) m.alpha = e.image;
    if (e.part != Part::Stencil) continue;
    m.stencil = binary(e.image, e.key);
    const bool alphaGiven = std::any_of(entries.begin(), entries.end(),
                                        [&](const Entry& o) { return o.part == Part::Alpha && o.level == e.level; });
    if (!alphaGiven && e.level != c.coarsestEnabled) m.alpha = e.image;             // a hard mask: a_ℓ = S_ℓ
    if (m.alpha.empty()) m.alpha = ImageF(e.image.width, e.image.height, 1, 1.0f);  // the coarsest: a ≡ 1
  }
  std::vector<std::string> keys;
  for (const Entry& e : entries) keys.push_back(e.key);
  return keys;
}

}  // namespace mrr::python
