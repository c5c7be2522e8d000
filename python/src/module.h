#pragma once
// The Python module's shared pieces (docs/python.md): images as numpy arrays and back, and the
// masks a frame takes from Python (SPEC §3), used by module.cpp and masks.cpp.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "common/frame.h"

namespace mrr::python {

namespace py = pybind11;

// A bad value handed in from Python (a mask's shape or dtype, an array for a metric): ValueError.
struct BadValue : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A float image as a read-only float32 array of shape (H, W), or (H, W, C) for C > 1, that owns it.
py::array ownedArray(ImageF&& image);
// The same over an image that `owner` keeps alive: no copy (the frame's own pixels).
py::array viewArray(const ImageF& image, std::shared_ptr<const void> owner);
// A (H, W) or (H, W, C) array of real numbers as a float32 image; `what` names it in errors.
ImageF imageFromArray(const py::handle& array, const std::string& what);

// What a mask rule written in Python sees (SPEC §3): the frame so far by stage name: the full-res
// G-buffer "gbuffer.L0", "edges" (where the method finds them), the level limit (SPEC §13) and
// the method's own "mask.L<ℓ>", "alpha.L<ℓ>", "stencil.L<ℓ>", each as frame[...] gives it.
py::dict maskContext(const FrameResult& frame, const Masks& masks);
// Puts the rule's arrays in place of the method's: any "mask.L<ℓ>" first, after which every
// enabled level's a_ℓ and S_ℓ are made again from the pyramid (SPEC §3 steps 2–4,
// stencilsFromPyramid); then any "alpha.L<ℓ>" and "stencil.L<ℓ>" as given (a stencil without an
// alpha: a_ℓ = S_ℓ, but at the coarsest level, whose a ≡ 1). A key or an array that does not fit:
// BadValue naming the stage and the expected shape. Returns the keys it used, in order.
std::vector<std::string> applyUserMasks(const py::dict& given, const FrameResult& frame, Masks& masks);

}  // namespace mrr::python
