#pragma once
// Frame files: everything that makes one frame, so that it reproduces. A frame file
// is JSON whose keys are the frame-parameter table's keys (common/frame_params.h: the rows
// marked for frame files), the command line's option names without "--", with `_` for `-`:
//   {"mrr_frame": 1, "scene": "builtin:demo", "effect": "ssao", "method": "mrr",
//    "size": "1280x720", "samples": 64, "eye": [x, y, z], "target": [x, y, z], "up": [x, y, z],
//    "fov": 60, "light_dir": [x, y, z], "light_angle": 0.05, "shadow_map_size": 2048,
//    "ao_radius": 0, "gi_radius": 0, "ao_texel_depth": false, "tau_n": 0.1, "tau_z": 0.02,
//    "sigma2": "0,0.924,1.848,0", "weights": "1000,1000,1000,1", "disable_level": [], "never_slower": "on", "blend_materials": "opaque", "flip_up": false}
// `render --frame-out F.json` writes one (the camera and light as resolved, numbers that round-trip
// exactly); `--frame F.json` on render, probe and compare reads it; options given on the command
// line win over the file's. Every report JSON and stages EXR carries the same object.
#include <nlohmann/json.hpp>

#include "common/frame_params.h"  // exactFloat

#include <set>
#include <string>
#include <vector>

namespace mrr {

// The command-line words a frame object stands for ("--size=1280x720", "--eye=1,2,3", ...),
// in the order of the keys above. Unknown keys and impossible values (a zero-length view
// direction, a size that is not positive, a wrong type): MrrError naming the key and `source`.
std::vector<std::string> frameArgs(const nlohmann::json& frame, const std::string& source);

// Reads a frame file; a missing file, bad JSON or a non-object: MrrError.
nlohmann::json readFrameFile(const std::string& path);

// Replaces "--frame F" (or "--frame=F") in a command line by the words F stands for, inserted
// right after the command, less the options the command line gives itself.
std::vector<std::string> expandFrameFile(const std::vector<std::string>& args);

// "x,y,z" with enough digits that parsing gives the same floats back.
std::string exactTriple(float x, float y, float z);
// The field of view in degrees whose conversion to radians (as the scene request does it) gives
// exactly `radians` back.
float exactDegrees(float radians);

}  // namespace mrr
