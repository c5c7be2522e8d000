#!/usr/bin/env python3
"""Where a method's flicker comes from (docs/spec.md §10), pixel by pixel, on the first frames of the orbit.

Flicker is the mean over frames t >= 1 of |e_t - e_{t-1}|, e_t = X_t - R_t the error against `full`
of the same camera (compare/metrics/metrics.h: FlickerMeter). This splits its sum by what the pixel did
between the two frames, from each frame's level map and level-0 blend weight (`render --stages`):
  - level changed: the finest level with alpha > 0 differs between t-1 and t (a mask moved);
  - same level 0, alpha_0 < 1: blended with a coarser level both times;
  - same level 0, alpha_0 = 1: shaded at full resolution both times (the bilateral blur's border);
  - same coarser level: interpolated from a coarse level both times.
The orbit is scenes/cameras.cpp's: the eye turned about the target's vertical axis by 12 deg
sin(2 pi t / (T - 1)), T = 60, frames 0..F-1 (the steepest part). Each frame is one `mrr render`
per method, with the never-slower rule off so that every frame uses the method.

  scripts/flicker-anatomy.py [--mrr build/mrr] [--scene builtin:demo] [--size 320x180] [--frames 12]
      [--method NAME="mrr render options" ...]

Needs numpy and OpenImageIO's Python module (Debian: python3-numpy, python3-openimageio).
"""
import argparse
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

DEFAULT_METHODS = {
    "tiles": "--method tiles",
    "mrr": "--method mrr",
    "mrr-effect": "--method mrr-effect",
    "mrr-effect+c4+p0.15": "--method mrr-effect --effect-cap 4 --effect-posterior 0.15",
}
PARTS = ("level changed", "same L0, alpha<1", "same L0, alpha=1", "same coarser level")


def part(stages_path, name):
    """One channel of the part `name` of a `render --stages` EXR, cropped to the frame later."""
    image = oiio.ImageInput.open(stages_path)
    index = 0
    while image.seek_subimage(index, 0):
        if image.spec().get_string_attribute("name") == name:
            pixels = image.read_image(format="float")
            image.close()
            return pixels[..., 0]
        index += 1
    raise SystemExit("flicker-anatomy: %s has no part %s" % (stages_path, name))


def view_of(mrr, scene):
    """The scene's view as `mrr info` prints it: eye, target, fov."""
    info = subprocess.run([mrr, "info", scene], check=True, capture_output=True, text=True).stdout
    m = re.search(r"^view\s+--eye (\S+) --target (\S+) --fov (\S+)", info, re.M)
    if not m:
        raise SystemExit("flicker-anatomy: no view in mrr info " + scene)
    return (np.array([float(v) for v in m.group(1).split(",")]), np.array([float(v) for v in m.group(2).split(",")]),
            m.group(3))


def orbit_eye(eye, target, t):
    angle = math.radians(12.0) * math.sin(2.0 * math.pi * t / 59.0)
    d = eye - target
    c, s = math.cos(angle), math.sin(angle)
    return target + np.array([c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mrr", default=os.path.join(os.path.dirname(__file__), "..", "build", "mrr"))
    ap.add_argument("--scene", default="builtin:demo")
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--effect", default="ssao")
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--method", action="append", default=[], help='NAME="render options" (default: four methods)')
    a = ap.parse_args()
    methods = dict(m.split("=", 1) for m in a.method) if a.method else DEFAULT_METHODS
    eye, target, fov = view_of(a.mrr, a.scene)
    frames = {name: [] for name in list(methods) + ["full"]}
    with tempfile.TemporaryDirectory() as tmp:
        for t in range(a.frames):
            e = orbit_eye(eye, target, t)
            camera = ["--eye", ",".join("%.9g" % v for v in e), "--target", ",".join("%.9g" % v for v in target),
                      "--fov", fov]
            for name, options in list(methods.items()) + [("full", "--method full")]:
                stages = os.path.join(tmp, "stages.exr")
                subprocess.run([a.mrr, "render", "--scene", a.scene, "--effect", a.effect, "--size", a.size, "-q",
                                "--never-slower", "off", "--out", os.path.join(tmp, "out.exr"), "--stages", stages]
                               + camera + shlex.split(options), check=True, stderr=subprocess.DEVNULL)
                final = part(stages, "final")
                h, w = final.shape
                if name == "full":
                    frames[name].append((final, None, None))
                else:
                    frames[name].append((final, part(stages, "levelmap"), part(stages, "blendalpha.L0")[:h, :w]))
            print("flicker-anatomy: frame %d of %d" % (t + 1, a.frames), file=sys.stderr)
    print("%s %s %s, orbit frames 0..%d of 60" % (a.scene, a.size, a.effect, a.frames - 1))
    print("| method | flicker | mean RMS | " + " | ".join(PARTS) + " |")
    print("|---|---|---|" + "---|" * len(PARTS))
    for name in methods:
        sums = dict.fromkeys(PARTS, 0.0)
        total, count = 0.0, 0
        for t in range(1, a.frames):
            (x1, map1, alpha1), (x0, map0, _) = frames[name][t], frames[name][t - 1]
            d = np.abs((x1 - frames["full"][t][0]) - (x0 - frames["full"][t - 1][0]))
            changed = map1 != map0
            sums["level changed"] += d[changed].sum()
            sums["same L0, alpha<1"] += d[~changed & (map1 == 0) & (alpha1 < 1)].sum()
            sums["same L0, alpha=1"] += d[~changed & (map1 == 0) & (alpha1 == 1)].sum()
            sums["same coarser level"] += d[~changed & (map1 > 0)].sum()
            total += d.sum()
            count += d.size
        rms = np.mean([np.sqrt(((x - r[0]) ** 2).mean()) for (x, _, _), r in zip(frames[name], frames["full"])])
        shares = " | ".join("%.0f %%" % (100.0 * sums[p] / total if total else 0.0) for p in PARTS)
        print("| %s | %.3g | %.3g | %s |" % (name, total / count, rms, shares))


if __name__ == "__main__":
    main()
