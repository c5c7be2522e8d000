"""mrr: multi-resolution rendering of expensive screen-space lighting, from Python.

The oracle (and the GL port, ``path="gpu"``) as `mrr render` runs them, with every stage of a
frame as a numpy array by its stage-list name (docs/python.md)::

    import mrr
    scene = mrr.load_scene("builtin:demo")
    f = mrr.Frame(scene, effect="ssao", size=(160, 96), samples=16)
    f.render()
    ao = f["final"]          # float32 (96, 160): the bits `mrr render --out F.exr` writes
    m1 = f["mask.L1"]        # M_1 on level 1's padded grid (SPEC §3)
    f.report["ideal_speedup"]

Keyword arguments are the command line's options with '_' for '-' (``effect_cap=4`` is
``--effect-cap 4``; ``mrr.params()`` lists them). ``masks=`` takes a mask rule written in numpy
(docs/python.md, "Bring your own masks").
"""

from ._mrr import (  # noqa: F401  (the module's API)
    BadValue,
    Error,
    Frame,
    PortUnavailable,
    Scene,
    flip,
    level_count,
    load_scene,
    methods,
    params,
    psnr,
    read_image,
    read_parts,
    rms,
    ssim,
    stages,
)

__all__ = [
    "BadValue", "Error", "Frame", "PortUnavailable", "Scene", "flip", "level_count", "load_scene", "methods",
    "params", "psnr", "read_image", "read_parts", "rms", "ssim", "stages", "chart_point",
]


def chart_point(frame):
    """The frame's point on the speed-against-accuracy chart (SPEC §4, §10): a dict of its method,
    its ideal speedup W·H / Σ|S_ℓ| and, when it was rendered with reference=True, its RMS and mean
    FLIP against full resolution."""
    report = frame.report
    point = {"method": report["method"], "ideal_speedup": report["ideal_speedup"]}
    error = report.get("error_vs_full")
    if error is not None:
        point["rms"] = error["rms"]
        point["flip"] = error["flip"]["mean"]
    return point
