"""ColorVideoVDP as a temporal metric: registered like the others, optional, and passing the
answers a perceptual measure of video should give."""

from __future__ import annotations

import os

import numpy as np
import pytest

from aaeval.metrics import registry

CVVDP = registry.METRICS["cvvdp"]

# One worker: importing PyTorch and loading ColorVideoVDP's model take about 3 s, once a
# process (the metric is kept per display), so tests on two workers paid them twice.
pytestmark = pytest.mark.xdist_group("cvvdp")


@pytest.fixture
def cvvdp_installed():
    """The optional extra is there: a plain ``pip install -e .`` may leave it out (a skip
    says how to add it), but the README's install and CI install it, so under CI a missing
    ColorVideoVDP is a broken install and fails."""
    reason = CVVDP.unavailable()
    if reason is None:
        return
    if os.environ.get("CI", "").lower() == "true":
        pytest.fail(f"CI=true: scripts/install.sh installs the cvvdp extra, yet ColorVideoVDP is unavailable: {reason}")
    pytest.skip(f"the optional cvvdp extra is not installed (pip install -e '.[cvvdp]'): {reason}")


needs_cvvdp = pytest.mark.usefixtures("cvvdp_installed")
FRAMES, SIZE = 16, 24  # a default-sweep-sized animation


def _animation():
    """A soft bright bar on a grey ground drifting 0.15 px a frame (linear sRGB)."""
    x = np.arange(SIZE) + 0.5
    frames = [0.1 + 0.4 * np.clip(1.0 - np.abs(x - 10.0 - 0.15 * t) / 3.0, 0.0, 1.0) for t in range(FRAMES)]
    return np.repeat(np.array(frames)[:, None, :, None], SIZE, axis=1).repeat(3, axis=3)


def _jod(truth, test):
    return registry.compute_temporal_metric("cvvdp", truth, test)


def test_registered_as_a_temporal_metric_where_higher_is_better():
    assert CVVDP.kind == "temporal" and CVVDP.higher_is_better
    assert CVVDP.requires == "pycvvdp" and CVVDP.extra == "cvvdp"


@needs_cvvdp
def test_the_truth_against_itself_scores_the_maximum():
    truth = _animation()
    assert _jod(truth, truth) == pytest.approx(10.0, abs=1e-4)


@needs_cvvdp
def test_popping_scores_below_a_steady_error_of_the_same_rms():
    truth = _animation()
    alternate = np.where(np.arange(FRAMES) % 2 == 0, 1.0, -1.0)[:, None, None, None]
    popping, steady = truth * (1.0 + 0.2 * alternate), truth * 1.2
    assert np.sqrt(np.mean((popping - truth) ** 2)) == pytest.approx(np.sqrt(np.mean((steady - truth) ** 2)))
    jod_popping, jod_steady = _jod(truth, popping), _jod(truth, steady)
    assert jod_popping < jod_steady - 1.0, (jod_popping, jod_steady)  # measured 6.4 and 9.7
    # and less popping is less visible
    assert jod_popping < _jod(truth, truth * (1.0 + 0.05 * alternate)) < 10.0


def test_bad_input_is_refused_before_any_work():
    from aaeval.metrics.video import cvvdp

    truth = _animation()
    with pytest.raises(ValueError, match="shape"):
        cvvdp(truth, truth[:, :-1])
    with pytest.raises(ValueError, match="2 frames"):
        cvvdp(truth[:1], truth[:1])
    with pytest.raises(ValueError, match="fps"):
        cvvdp(truth, truth, fps=0.0)


@needs_cvvdp
def test_an_unknown_display_is_named():
    truth = _animation()
    with pytest.raises(ValueError, match="no-such-display"):
        registry.compute_temporal_metric("cvvdp", truth, truth, display="no-such-display")


def test_a_metric_whose_module_is_missing_is_listed_unavailable_and_refused():
    def metric(frames_true, frames_test):
        return 0.0

    registry.register_metric("optional_probe", metric, kind="temporal", title="probe", fmt=".1f",
                             requires="aaeval_no_such_module", extra="probe")
    try:
        why = registry.METRICS["optional_probe"].unavailable()
        assert "aaeval_no_such_module" in why and "aaeval[probe]" in why
        with pytest.raises(registry.MetricError, match="unavailable here: optional_probe needs"):
            registry.check_metric_names(["flicker", "optional_probe"], "temporal")
        assert "optional_probe" not in registry.default_metrics("temporal")
    finally:
        registry.METRICS.unregister("optional_probe")
    with pytest.raises(registry.MetricError, match="go together"):
        registry.register_metric("optional_probe", metric, kind="temporal", title="probe", fmt=".1f",
                                 requires="aaeval_no_such_module")
