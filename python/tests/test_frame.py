"""mrr.Frame against `mrr render`: the same bits on every method and effect, every stage of the
stage list readable as an array of its part's shape and dtype, the report, and the parameters
taken by the command line's names (docs/python.md)."""
import math
import subprocess

import numpy as np
import pytest

import mrr
from conftest import EFFECTS, SAMPLES, SIZE, render_cli, same_bits

METHODS = [row["name"] for row in mrr.methods()]


def test_the_method_table_is_the_command_lines():
    assert METHODS[:2] == ["mrr", "full"]
    assert {"uniform-2", "tiles", "mrr-effect"} <= set(METHODS)


@pytest.mark.parametrize("rule", ["on", "off"])
@pytest.mark.parametrize("effect", EFFECTS)
@pytest.mark.parametrize("method", METHODS)
def test_final_has_the_bits_of_mrr_render(demo, mrr_binary, tmp_path, effect, method, rule):
    """On every method and effect, with the never-slower rule (SPEC §11: small frames often fall
    back to full) and without it (the method's own stencils)."""
    params = dict(effect=effect, method=method, size=SIZE, samples=SAMPLES, never_slower=rule)
    frame = mrr.Frame(demo, **params).render()
    cli = render_cli(mrr_binary, tmp_path, **params)
    assert same_bits(frame["final"], cli["final"]), (effect, method)


def test_the_documented_example(mrr_binary, tmp_path):
    f = mrr.Frame(mrr.load_scene("builtin:demo"), effect="ssao", size=(160, 96), samples=16)
    f.render()
    ao = f["final"]
    assert ao.shape == (96, 160) and ao.dtype == np.float32
    assert same_bits(ao, render_cli(mrr_binary, tmp_path, effect="ssao", size=(160, 96), samples=16)["final"])


def expected_shape(frame, name, report):
    """The part's array shape from its row: its grid's size and its channel count."""
    rows = {row["name"]: row for row in mrr.stages()}
    base, _, level = name.partition(".L")
    row = rows[base]
    w, h, pw, ph = report["width"], report["height"], report["padded_width"], report["padded_height"]
    if row["grid"] == "level":
        s = 2 ** int(level)
        rows_cols = (ph // s, pw // s)
    elif row["grid"] == "screen":
        rows_cols = (h, w)
    elif row["grid"] == "tiles":
        rows_cols = (math.ceil(ph / 16), math.ceil(pw / 16))
    else:
        n = report["frame"]["shadow_map_size"]
        rows_cols = (n, n)
    channels = len(row["channels"])
    if base == "edges" and report["effect"] != "ssm":
        channels -= 1  # the shadow kind is SSM's
    if row["channels"][0].startswith(("c", "Y")) and report["effect"] == "ssgi":
        channels = 3  # an effect part: RGB for SSGI
    return rows_cols if channels == 1 else rows_cols + (channels,)


# Frames that together hold every part of the stage list: the method's masks, the tiles' rates,
# mrr-effect's marks, the level limit of a gaze and a pan, SSM's shadow map and test.
COVERING = [
    dict(effect="ssao", method="mrr"),
    dict(effect="ssm", method="tiles"),
    dict(effect="ssgi", method="mrr-effect", effect_posterior=0.01),
    dict(effect="ssm", method="mrr", gaze=(40, 20), pan=0.05),
    dict(effect="ssao", method="mrr-effect", effect_temporal=0.5, pan=0.05),
]


@pytest.mark.parametrize("params", COVERING, ids=lambda p: "-".join(str(v) for v in p.values()))
def test_every_stage_is_the_stages_exr_part(demo, mrr_binary, tmp_path, params):
    params = dict(params, size=SIZE, samples=SAMPLES, never_slower="off")
    frame = mrr.Frame(demo, **params).render()
    cli = render_cli(mrr_binary, tmp_path, stages=True, **params)
    assert frame.stages() == list(cli["stages"]), "the frame holds the stages EXR's parts, in its order"
    for name in frame.stages():
        array = frame[name]
        assert array.dtype == np.float32, name
        assert array.shape == expected_shape(frame, name, frame.report), name
        assert same_bits(array.reshape(cli["stages"][name].shape), cli["stages"][name]), name
        assert name in frame


def test_the_covering_frames_hold_every_part(demo):
    held = set()
    for params in COVERING:
        frame = mrr.Frame(demo, size=SIZE, samples=SAMPLES, never_slower="off", **params).render()
        held |= {name.partition(".L")[0] for name in frame.stages()}
    assert held == {row["name"] for row in mrr.stages()}


def test_arrays_read_the_frame_in_place_and_keep_it_alive(demo):
    frame = mrr.Frame(demo, size=SIZE, samples=SAMPLES).render()
    a, b = frame["final"], frame["final"]
    assert np.shares_memory(a, b), "float parts are the frame's own pixels, not copies"
    assert not a.flags.writeable
    del frame
    assert np.isfinite(a).all()  # the array keeps the frame's pixels


def test_report_is_the_command_lines(demo, mrr_binary, tmp_path):
    params = dict(effect="ssao", method="mrr", size=SIZE, samples=SAMPLES, never_slower="off")
    report = mrr.Frame(demo, **params).render(reference=True).report
    cli = render_cli(mrr_binary, tmp_path, report=True, **params)["report"]
    for key in ("method", "effect", "levels", "shaded_pixels_total", "ideal_speedup", "ideal_speedup_hit", "frame"):
        assert report[key] == cli[key], key
    assert 0 < report["error_vs_full"]["rms"] < 0.2


def test_parameters_by_their_command_line_names(demo, mrr_binary, tmp_path):
    params = dict(effect="ssao", method="mrr-effect", size=SIZE, samples=SAMPLES, effect_cap=4, tau_n=0.2,
                  sigma2=(0.5, 1, 2, 0), disable_level=[1], eye=(0, 2, 6), target=(0, 0, 0))
    frame = mrr.Frame(demo, **params).render()
    assert frame.report["frame"]["effect_cap"] == 4
    assert frame.report["frame"]["disable_level"] == [1]
    cli = render_cli(mrr_binary, tmp_path, **{k: v for k, v in params.items() if k != "disable_level"},
                     disable_level=1)
    assert same_bits(frame["final"], cli["final"])


def test_a_frame_file_and_a_scene_by_name(mrr_binary, tmp_path):
    """frame="F.json" reads a frame file as `--frame` does; keywords given win over its values."""
    frame_file = tmp_path / "frame.json"
    subprocess.run([mrr_binary, "render", "--quiet", "--scene", "builtin:steps", "--effect", "ssm", "--size", "96x54",
                    "--samples", "16", "--camera", "0", "--frame-out", str(frame_file)], check=True)
    f = mrr.Frame("builtin:steps", frame=str(frame_file), never_slower="off").render()
    assert f.report["frame"]["effect"] == "ssm" and f.report["frame"]["never_slower"] == "off"
    cli = render_cli(mrr_binary, tmp_path, scene="builtin:steps", frame=str(frame_file), never_slower="off")
    assert same_bits(f["final"], cli["final"])


def test_every_row_of_the_parameter_table_is_a_keyword():
    keys = {row["key"] for row in mrr.params()}
    assert {"effect_cap", "tau_n", "samples", "size", "method", "path"} <= keys
    assert all(row["option"] == "--" + row["key"].replace("_", "-") for row in mrr.params())


@pytest.mark.parametrize("params, words", [
    (dict(tau_n=-1), "--tau-n"),
    (dict(effect="fog"), "fog"),
    (dict(size=(0, 10)), "size"),
    (dict(no_such_thing=1), "no_such_thing"),
    (dict(samples=True), "samples"),
    (dict(method="nope"), "nope"),
])
def test_bad_parameters_are_one_value_error(demo, params, words):
    with pytest.raises(ValueError, match=words):
        mrr.Frame(demo, **params)


def test_stage_names_that_do_not_fit(demo):
    frame = mrr.Frame(demo, size=SIZE, samples=SAMPLES)
    with pytest.raises(ValueError, match="render"):
        frame["final"]
    frame.render()
    for name, words in [("mask", "per level"), ("final.L1", "not per level"), ("mask.L7", "level 7"),
                        ("nothing", "no such stage"), ("tilerates", "not in this frame")]:
        with pytest.raises(KeyError, match=words):
            frame[name]
        assert name not in frame


def test_a_bad_scene_is_one_exception():
    with pytest.raises(ValueError, match="nowhere.glb"):
        mrr.load_scene("/nowhere.glb")
