#pragma once
// Cameras for the benchmark: the paper averages over 8 cameras per scene, and
// stability is measured along camera paths. Both are generated deterministically from a
// scene's default camera, so every scene, built-in or shared, gets them without a camera
// file, and every run sees the same views.
#include <string>
#include <vector>

#include "common/camera.h"

namespace mrr {

// `count` views around `base` (the first is `base` itself): the camera turns in place (pan
// ±16°, tilt ±8°) and moves up to a quarter of the way towards its target. Turning in place
// and moving towards the target keep the eye where the scene's author put it, so an interior
// scene never gets a camera inside a wall.
std::vector<Camera> benchCameras(const Camera& base, int count);

// A camera path of `frames` frames, starting and ending at `base`: "orbit" swings the eye
// about the target's vertical axis, one period of a sine of ±12°; "dolly" moves it towards
// the target and back (cosine-eased), up to 30% of the distance.
std::vector<Camera> cameraPath(const Camera& base, const std::string& kind, int frames);

const std::vector<std::string>& cameraPathKinds();  // "orbit", "dolly"

}  // namespace mrr
