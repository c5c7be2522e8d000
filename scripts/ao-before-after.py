#!/usr/bin/python3
"""SSAO's defaults before and after the view-framed radius and the 2% depth bias, side by side: a
sheet of scenes (the AO with R = 3% of the scene's diagonal and a depth bias of 5% of R, the AO
with the defaults: R = 15% of what the view frames and a bias of 2% of R, and the shaded image) and each one's darkest tenth (the 10th
percentile of the AO over the pixels that hit geometry). Run by scripts/make-doc-images.sh; by hand:

  /usr/bin/python3 scripts/ao-before-after.py OUT.png SCENE...   (after scripts/build.sh)

SCENE is anything --scene takes (a shared scene's name, a .gltf/.glb path). Prints the table as
Markdown on stdout. Needs python3-openimageio, python3-numpy and python3-matplotlib.
"""
import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
MRR = os.environ.get("MRR", os.path.join(HERE, "..", "build", "mrr"))
SIZE = os.environ.get("AO_SHEET_SIZE", "640x360")
OLD_FRACTION = 0.03  # SsaoSettings::kDiagonalFractionBefore
OLD_BIAS = 0.05  # SsaoSettings::kBiasFractionBefore: the depth bias, a fraction of R, before it became 2%


def info(scene):
    out = subprocess.run([MRR, "info", scene, "--size", SIZE, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def render(scene, work, tag, radius, bias=None):
    ao, stages, shaded = (os.path.join(work, tag + suffix) for suffix in (".exr", "-stages.exr", ".png"))
    extra = [] if bias is None else ["--ao-bias", repr(bias)]
    subprocess.run([MRR, "render", "--scene", scene, "--size", SIZE, "--quiet", "--ao-radius", repr(radius),
                    "--out", ao, "--stages", stages, "--shaded", shaded] + extra, check=True)
    buffer = oiio.ImageBuf(ao).get_pixels(oiio.FLOAT)[..., 0]
    gbuffer = oiio.ImageBuf(stages, 0, 0)  # the first part: gbuffer.L0 (depth, hit, ...)
    hit = gbuffer.get_pixels(oiio.FLOAT)[..., gbuffer.spec().channelindex("hit")] > 0.5
    darkest_tenth = float(np.percentile(buffer[hit], 10)) if hit.any() else float("nan")
    return buffer, oiio.ImageBuf(shaded).get_pixels(oiio.FLOAT)[..., :3], darkest_tenth


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, scenes = sys.argv[1], sys.argv[2:]
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for k, scene in enumerate(scenes):
            print("[ao-sheet] %s" % scene, file=sys.stderr)
            facts = info(scene)
            old_r = OLD_FRACTION * facts["bounds"]["diagonal"]
            new_r = facts["radii"]["ssao_radius"]
            before, _, before_p10 = render(scene, work, "%d-before" % k, old_r, OLD_BIAS)
            after, shaded, after_p10 = render(scene, work, "%d-after" % k, new_r)
            name = os.path.basename(scene) if os.path.sep in scene else scene
            rows.append((name, old_r, before_p10, new_r, after_p10, facts["radii"]["framed_size"], before, after, shaded))
    fig, axes = plt.subplots(len(rows), 3, figsize=(12, 2.35 * len(rows)), dpi=100, squeeze=False)
    for r, (name, old_r, before_p10, new_r, after_p10, framed, before, after, shaded) in enumerate(rows):
        for c, (image, title) in enumerate((
                (before, "%s: before, R %.3g (3%% of the diagonal), bias 5%% of R\ndarkest tenth of the AO %.3f" % (name, old_r, before_p10)),
                (after, "after, R %.3g (15%% of the framed %.3g), bias 2%% of R\ndarkest tenth of the AO %.3f" % (new_r, framed, after_p10)),
                (shaded, "shaded, after"))):
            ax = axes[r][c]
            ax.imshow(np.clip(image, 0, 1), cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1)
            ax.set_title(title, fontsize=8.5)
            ax.set_axis_off()
    fig.suptitle("SSAO's defaults: R from the scene's diagonal, bias 5%% (before); R from what the view frames, bias 2%% (after); "
                 "oracle, mrr, SSAO-64, %s" % SIZE, fontsize=10, fontweight="bold")
    fig.tight_layout()
    fig.savefig(out)
    print("| scene | R before (3% of the diagonal) | darkest tenth before (bias 5% of R) | R after (15% of the framed "
          "size) | darkest tenth after (bias 2% of R) |\n|---|---|---|---|---|")
    for name, old_r, before_p10, new_r, after_p10, *_ in rows:
        print("| %s | %.3g | %.3f | %.3g | %.3f |" % (name, old_r, before_p10, new_r, after_p10))


if __name__ == "__main__":
    main()
