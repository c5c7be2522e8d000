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
