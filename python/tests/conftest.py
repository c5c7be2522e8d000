"""Shared pieces of the Python module's tests (ctest python_*; docs/python.md): the `mrr`
binary whose bits the module must reproduce, small frames, and running `mrr render`."""
import json
import os
import subprocess

import numpy as np
import pytest

import mrr

# Small frames: every test takes seconds on 2 cores.
SIZE = (96, 54)
SAMPLES = 16
EFFECTS = ("ssao", "ssm", "ssgi")


@pytest.fixture(scope="module")
def mrr_binary():
    """The command line the module is checked against (MRR, set by ctest)."""
    path = os.environ.get("MRR")
    if not path or not os.path.exists(path):
        pytest.fail("MRR must name the mrr binary (ctest sets it)")
    return path


@pytest.fixture(scope="module")
def demo():
    return mrr.load_scene("builtin:demo")


def words(params):
    """Keyword arguments as the command line's words: the same rows the module maps them by."""
    out = []
    for key, value in params.items():
        option = "--" + key.replace("_", "-")
        if key == "size":
            value = "%dx%d" % tuple(value)
        if value is True:
            out.append(option)
        elif isinstance(value, (list, tuple)):
            out += [option, ",".join(str(v) for v in value)]
        else:
            out += [option, str(value)]
    return out


def render_cli(binary, tmp_path, scene="builtin:demo", stages=False, report=False, **params):
    """`mrr render` on the same frame: its --out (and --stages, --report) read back."""
    out = tmp_path / "final.exr"
    cmd = [binary, "render", "--quiet", "--scene", scene, "--out", str(out)] + words(params)
    if stages:
        cmd += ["--stages", str(tmp_path / "stages.exr")]
    if report:
        cmd += ["--report", str(tmp_path / "report.json")]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    result = {"final": mrr.read_image(str(out))}
    if stages:
        result["stages"] = mrr.read_parts(str(tmp_path / "stages.exr"))
    if report:
        result["report"] = json.loads((tmp_path / "report.json").read_text())
    return result


def same_bits(a, b):
    """The same float32 bits (NaN included), not merely close."""
    a, b = np.ascontiguousarray(a, dtype=np.float32), np.ascontiguousarray(b, dtype=np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))
