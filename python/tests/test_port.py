"""The GL port from Python (path="gpu"): where EGL gives a context, its frame has the oracle's
stages and comes close to the oracle's final; where it does not, one clear exception, not a
crash (skipped then, unless MRR_REQUIRE_GL=1, as the GL tests)."""
import os

import numpy as np
import pytest

import mrr
from conftest import SAMPLES, SIZE


def test_the_port_or_a_clear_exception(demo):
    params = dict(effect="ssao", size=SIZE, samples=SAMPLES, never_slower="off")
    try:
        port = mrr.Frame(demo, path="gpu", **params).render()
    except mrr.PortUnavailable as e:
        assert "path gpu" in str(e) and isinstance(e, RuntimeError)
        if os.environ.get("MRR_REQUIRE_GL") == "1":
            pytest.fail(str(e))
        pytest.skip(str(e))
    oracle = mrr.Frame(demo, **params).render()
    assert port.stages() == oracle.stages()
    assert port.report["path"] == "gpu" and port.report["renderer"]
    assert np.isfinite(port["final"]).all()
    assert mrr.rms(port["final"], oracle["final"]) < 0.02


def test_an_unknown_path(demo):
    with pytest.raises(ValueError, match="path"):
        mrr.Frame(demo, path="tpu", size=SIZE).render()


def test_a_device_that_is_not_there_is_a_clear_exception(demo):
    """An EGL failure (here: a device index past the last) is mrr.PortUnavailable naming why."""
    with pytest.raises(mrr.PortUnavailable, match="path gpu: the GL port cannot start here"):
        mrr.Frame(demo, path="gpu", gl_device=99, size=SIZE).render()


def test_the_port_stays_on_the_thread_of_its_context(demo):
    """The port's GL context is current on one thread: a frame of the same scene rendered on another
    thread is mrr.PortUnavailable saying so, not a crash."""
    import threading
    scene = mrr.load_scene("builtin:steps")
    try:
        mrr.Frame(scene, path="gpu", size=SIZE, samples=SAMPLES).render()
    except mrr.PortUnavailable as e:
        pytest.skip(str(e))
    caught = []
    t = threading.Thread(target=lambda: caught.append(pytest.raises(
        mrr.PortUnavailable, mrr.Frame(scene, path="gpu", size=SIZE, samples=SAMPLES).render)))
    t.start()
    t.join()
    assert len(caught) == 1 and "on that thread" in str(caught[0].value)
