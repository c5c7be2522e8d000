"""Masks from Python (docs/python.md, SPEC §3): mrr's own masks handed back reproduce mrr's bits,
a numpy rule's stencils are what the frame shades and counts, and a malformed mask is one
ValueError naming the stage and the shape it expects."""
import threading

import numpy as np
import pytest

import mrr
from conftest import EFFECTS, SAMPLES, SIZE, same_bits

LEVELS = range(mrr.level_count())


def frame(demo, **params):
    return mrr.Frame(demo, **dict(dict(size=SIZE, samples=SAMPLES, never_slower="off"), **params))


@pytest.mark.parametrize("effect", EFFECTS)
def test_mrrs_own_pyramid_through_python_gives_mrrs_bits(demo, effect):
    own = frame(demo, effect=effect).render()
    seen = []

    def rule(ctx):
        seen.append(sorted(ctx))
        return {name: ctx[name] for name in ctx if name.startswith("mask.")}

    mine = frame(demo, effect=effect, masks=rule).render()
    assert len(seen) == 1 and "edges" in seen[0] and "gbuffer.L0" in seen[0]
    assert mine.report["masks_from_python"], "the rule's masks were used"
    for name in own.stages():
        assert same_bits(mine[name], own[name]), name
    assert mine.report["ideal_speedup"] == own.report["ideal_speedup"]


@pytest.mark.parametrize("effect", EFFECTS)
def test_mrrs_own_stencils_as_a_dict_give_mrrs_bits(demo, effect):
    own = frame(demo, effect=effect).render()
    given = {}
    for name in own.stages():
        if name.startswith(("stencil.", "alpha.")):
            given[name] = own[name] if name.startswith("alpha.") else own[name].astype(np.uint8)
    mine = frame(demo, effect=effect, masks=given).render()
    assert same_bits(mine["final"], own["final"])
    assert mine.report["shaded_pixels_total"] == own.report["shaded_pixels_total"]


def test_a_numpy_rule_is_shaded_and_counted_as_given(demo):
    """Every other row of level 1 stencilled: the frame shades those pixels, and its ideal speedup is
    W·H / Σ|S_ℓ| over what it shaded (SPEC §4)."""
    def rule(ctx):
        s1 = ctx["mask.L1"].copy()
        s1[::2] = 1
        return {"mask.L1": s1}

    f = frame(demo, effect="ssao", masks=rule).render(reference=True)
    mine = f["mask.L1"]
    assert (mine[::2] == 1).all()
    shaded = sum(int(f["stencil.L%d" % l].sum()) for l in LEVELS if "stencil.L%d" % l in f)
    assert f.report["shaded_pixels_total"] == shaded
    assert f.report["ideal_speedup"] == pytest.approx(SIZE[0] * SIZE[1] / shaded, rel=1e-12)
    assert (f["raw.L1"][f["stencil.L1"] == 0] == 0).all(), "unstencilled pixels are never shaded"
    own = frame(demo, effect="ssao").render(reference=True)
    assert f.report["ideal_speedup"] < own.report["ideal_speedup"]
    assert np.isfinite(f.report["error_vs_full"]["rms"]) and f.report["error_vs_full"]["flip"]["mean"] >= 0


def test_everything_at_full_resolution_is_full(demo):
    """S_0 = 1 everywhere, with α_0 = 1: the blend takes level 0 alone, the frame `full` renders."""
    full = frame(demo, effect="ssm", method="full").render()
    probe = frame(demo, effect="ssm").render()
    h, w = probe.level_shape(0)
    ones = np.ones((h, w), np.float32)
    f = frame(demo, effect="ssm", masks={"stencil.L0": ones, "alpha.L0": ones}).render()
    assert np.array_equal(f["final"], full["final"])


MALFORMED = [
    lambda h, w: ({"mask.L1": np.zeros((h, w + 1), np.uint8)},
                  r"mask\.L1: shape \(%d, %d\), expected a numpy array of shape \(%d, %d\)" % (h, w + 1, h, w)),
    lambda h, w: ({"stencil.L1": np.zeros((h, w), np.complex64)}, r"stencil\.L1: dtype complex64"),
    lambda h, w: ({"stencil.L1": np.full((h, w), 2, np.uint8)}, r"stencil\.L1: value 2"),
    lambda h, w: ({"mask.L1": [[0] * w] * h}, r"mask\.L1: list, expected a numpy array of shape \(%d, %d\)" % (h, w)),
    lambda h, w: ({"mask.L9": np.zeros((h, w))}, r"unknown stage mask\.L9"),
    lambda h, w: ({"final": np.zeros((h, w))}, r"unknown stage final"),
]


@pytest.mark.parametrize("case", range(len(MALFORMED)))
def test_a_malformed_mask_is_one_value_error(demo, case):
    h, w = frame(demo).level_shape(1)
    given, words = MALFORMED[case](h, w)
    with pytest.raises(ValueError, match=words):
        frame(demo, masks=lambda ctx: given).render()
    with pytest.raises(ValueError, match=words):
        frame(demo, masks=given).render()


def test_a_rule_that_returns_no_dict_or_fails(demo):
    with pytest.raises(ValueError, match="the rule returned list"):
        frame(demo, masks=lambda ctx: []).render()
    with pytest.raises(ZeroDivisionError):
        frame(demo, masks=lambda ctx: 1 / 0).render()
    with pytest.raises(ValueError, match="masks: expected a callable"):
        frame(demo, masks=3)
    none = frame(demo, masks=lambda ctx: None).render()
    assert same_bits(none["final"], frame(demo).render()["final"])


def test_a_disabled_level_and_a_method_without_a_pyramid(demo):
    h, w = frame(demo).level_shape(1)
    with pytest.raises(ValueError, match="level 1 is disabled"):
        frame(demo, disable_level=[1], masks={"mask.L1": np.zeros((h, w))}).render()
    with pytest.raises(ValueError, match=r"mask\.L0: method uniform-2 has no M_l there; give it too \(shape"):
        frame(demo, method="uniform-2", masks={"mask.L2": np.zeros(frame(demo).level_shape(2))}).render()
    with pytest.raises(ValueError, match="oracle"):
        frame(demo, path="gpu", masks={"mask.L1": np.zeros((h, w))}).render()


def test_the_oracle_runs_without_the_gil(demo):
    """Another Python thread runs while a frame renders (the GIL is released), and the rule, called
    from the renderer, takes it back."""
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        frame(demo, effect="ssgi", size=(192, 108), masks=lambda ctx: None).render()
    finally:
        stop.set()
        t.join()
    assert len(ticks) > 5


def test_a_rule_may_not_render_and_threads_take_turns(demo):
    """A frame rendered from inside a mask rule is a ValueError, not a re-entered renderer; frames of
    one scene rendered from several Python threads at once take turns and give the same bits."""
    with pytest.raises(ValueError, match="a mask rule may not render"):
        frame(demo, masks=lambda ctx: frame(demo).render() and None).render()
    alone = frame(demo, effect="ssgi").render()["final"]
    results, errors = [], []

    def work():
        try:
            results.append(frame(demo, effect="ssgi").render()["final"])
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(results) == 3
    assert all(same_bits(r, alone) for r in results)
