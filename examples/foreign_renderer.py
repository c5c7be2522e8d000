#!/usr/bin/python3
"""Plays "a foreign renderer" for `mrr compare --against` (docs/validate-your-own.md).

Takes the oracle's stages EXR (`mrr render --stages FILE`), alters one stage the way a real
bug in another renderer would, and writes the result as a new stages EXR:

  edges   the depth-edge kind is never detected (a renderer that forgot the second
          difference of 1/z): edges.depth is 0 everywhere and E is the OR of the others.
  raw     SSAO normalised by N - 1 instead of N (AO = 1 - occluded / (N - 1)) at every
          level, where the level was shaded (S = 1).
  dark    SSAO 3% too dark: AO x 0.97 at every level where S = 1 (a constant folded in twice,
          a falloff slightly off). Within the exact rules' noise, and no single pixel shows it:
          `compare --noise-aware` names the bias at raw.L0.
  shift   every G-buffer half a pixel off (rays through pixel corners, not centres: the classic
          half-pixel offset), the effect computed from it: position, normal and depth of each
          level averaged with the right and lower neighbours (bilinear at +1/2, +1/2).

Every other part is copied as it is, so `mrr compare --against OUT` (with the options the
stages were rendered with) names the altered stage on its last line.

Needs OpenImageIO's Python bindings (Debian: python3-openimageio) and numpy.
"""
import argparse
import sys

import numpy as np
import OpenImageIO as oiio


def read_parts(path):
    """Every part of a multi-part EXR: (spec, pixels as float32 HxWxC)."""
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"foreign_renderer: cannot read {path}: {oiio.geterror()}")
    parts = []
    index = 0
    while inp.seek_subimage(index, 0):
        spec = inp.spec()
        parts.append((oiio.ImageSpec(spec), inp.read_image("float")))
        index += 1
    inp.close()
    return parts


def write_parts(path, parts):
    out = oiio.ImageOutput.create(path)
    if out is None or not out.open(path, [spec for spec, _ in parts]):
        sys.exit(f"foreign_renderer: cannot write {path}: {oiio.geterror()}")
    for index, (spec, pixels) in enumerate(parts):
        if index > 0 and not out.open(path, spec, "AppendSubimage"):
            sys.exit(f"foreign_renderer: cannot write part {index} of {path}: {out.geterror()}")
        out.write_image(pixels)
    out.close()


def channel(spec, name):
    return list(spec.channelnames).index(name)


def drop_depth_edges(parts):
    for spec, pixels in parts:
        if spec.getattribute("name") == "edges":
            pixels[:, :, channel(spec, "depth")] = 0.0
            kinds = [c for c in spec.channelnames if c not in ("E", "depth")]
            pixels[:, :, channel(spec, "E")] = np.max(pixels[:, :, [channel(spec, k) for k in kinds]], axis=2)
            return ["edges"]
    sys.exit("foreign_renderer: the file has no edges part (render with --method mrr)")


def ssao_over_n_minus_1(parts, samples):
    stencils = {spec.getattribute("name").split(".")[1]: pixels[:, :, 0] for spec, pixels in parts
                if spec.getattribute("name").startswith("stencil.")}
    altered = []
    for spec, pixels in parts:
        name = spec.getattribute("name")
        if name.startswith("raw."):
            shaded = stencils[name.split(".")[1]] > 0.5
            ao = pixels[:, :, 0]
            ao[shaded] = 1.0 - (1.0 - ao[shaded]) * samples / (samples - 1)
            altered.append(name)
    return altered


def stencil_of(parts):
    return {spec.getattribute("name").split(".")[1]: pixels[:, :, 0] for spec, pixels in parts
            if spec.getattribute("name").startswith("stencil.")}


def ssao_too_dark(parts, factor=0.97):
    stencils = stencil_of(parts)
    altered = []
    for spec, pixels in parts:
        name = spec.getattribute("name")
        if name.startswith("raw."):
            shaded = stencils[name.split(".")[1]] > 0.5
            pixels[:, :, 0][shaded] *= factor
            altered.append(name)
    return altered


def half_pixel_shift(parts):
    altered = []
    for spec, pixels in parts:
        name = spec.getattribute("name")
        if not name.startswith("gbuffer."):
            continue
        hit = pixels[:, :, channel(spec, "hit")] > 0.5
        # bilinear at (x + 1/2, y + 1/2): the mean of the 2x2 block, where all four hit
        right = np.concatenate([pixels[:, 1:], pixels[:, -1:]], axis=1)
        down = np.concatenate([pixels[1:], pixels[-1:]], axis=0)
        diag = np.concatenate([right[1:], right[-1:]], axis=0)
        mean = 0.25 * (pixels + right + down + diag)
        keep = hit & (right[:, :, channel(spec, "hit")] > 0.5) & (down[:, :, channel(spec, "hit")] > 0.5) & \
            (diag[:, :, channel(spec, "hit")] > 0.5)
        moved = [c for c in spec.channelnames if c not in ("hit",) and not c.startswith("albedo")]
        for c in moved:
            k = channel(spec, c)
            pixels[:, :, k][keep] = mean[:, :, k][keep]
        altered.append(name)
    return altered


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("stages", help="the oracle's stages EXR (mrr render --stages)")
    parser.add_argument("out", help="the altered stages EXR to write")
    parser.add_argument("--bug", choices=["edges", "raw", "dark", "shift"], default="edges",
                        help="which stage to break (default edges)")
    parser.add_argument("--samples", type=int, default=16, help="raw: the SSAO sample count N the stages were made with")
    args = parser.parse_args()
    parts = read_parts(args.stages)
    bugs = {"edges": lambda: drop_depth_edges(parts), "raw": lambda: ssao_over_n_minus_1(parts, args.samples),
            "dark": lambda: ssao_too_dark(parts), "shift": lambda: half_pixel_shift(parts)}
    altered = bugs[args.bug]()
    write_parts(args.out, parts)
    print(f"foreign_renderer: wrote {args.out} ({len(parts)} parts; altered: {', '.join(altered)})")


if __name__ == "__main__":
    main()
