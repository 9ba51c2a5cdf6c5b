"""Perceptual video difference: ColorVideoVDP (Mantiuk et al., SIGGRAPH 2024) through ``cvvdp``.

An optional dependency (the ``cvvdp`` extra: the package and a CPU build of PyTorch): where
it is not installed the metric is registered but unavailable, and says why.
"""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_frames_pair, check_positive

__all__ = ["cvvdp", "CVVDP_MODULE", "DISPLAY"]

#: The module the metric imports (the ``cvvdp`` distribution installs it).
CVVDP_MODULE = "pycvvdp"
#: ColorVideoVDP's own default display: a 30-inch 4K monitor, 200 cd/m^2, office light,
#: seen from 0.75 m (about 75 pixels per degree, close to FLIP's 67).
DISPLAY = "standard_4k"

_METRICS: dict = {}  # one loaded model per display (its set-up reads the display and CSF tables)
_TORCHVISION_OPS = []  # keeps the operator declarations below alive while the process runs


def cvvdp(frames_true, frames_test, *, fps: float = 30.0, display: str = DISPLAY) -> float:
    """ColorVideoVDP quality of a test animation against the reference, in JOD.

    The frames are linear sRGB; they are clipped to [0, 1], encoded with the sRGB transfer
    function (colour-science) and shown on ``display`` (a display model of ColorVideoVDP's own tables, shipped
    with the package: nothing is fetched) at ``fps`` frames per second. JOD (just-objectionable
    differences) is 10 for a test no one can tell from the reference and falls as the
    difference becomes visible; temporal artefacts such as popping count for more than a
    steady error of the same size.

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (F, H, W, 3)
        Reference and test frames (linear sRGB).
    fps : float, optional
        Frames per second the animation is shown at.
    display : str, optional
        Name of a display in ColorVideoVDP's ``display_models.json``.

    Returns
    -------
    jod : float
        At most 10; higher is better.

    Raises
    ------
    ImportError
        When ``cvvdp`` (or PyTorch) is not installed.
    """
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    check_positive("fps", fps)
    if frames_true.shape[0] < 2:
        raise ValueError(f"need at least 2 frames for a video, got {frames_true.shape[0]}")
    import colour
    import torch

    metric = _metric(display)

    def video(frames):
        encoded = colour.models.eotf_inverse_sRGB(np.clip(frames, 0.0, 1.0))
        return torch.as_tensor(encoded, dtype=torch.float32)

    # One thread: a sweep already runs a cell per core, and PyTorch's threads waiting on a
    # busy machine cost 30 times the work (24 x 24 x 16 frames: 8 s on two threads, 0.2 s on one).
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        with torch.no_grad():
            jod, _ = metric.predict(video(frames_test), video(frames_true), dim_order="FHWC",
                                    frames_per_second=float(fps))
    finally:
        torch.set_num_threads(threads)
    return float(jod)


def _metric(display: str):
    if display not in _METRICS:
        import torch

        pycvvdp = _import_cvvdp()
        try:
            _METRICS[display] = pycvvdp.cvvdp(display_name=display, quiet=True, device=torch.device("cpu"))
        except Exception as exc:  # cvvdp names an unknown display with a bare exception
            raise ValueError(f"display {display!r}: {exc}") from None
    return _METRICS[display]


def _import_cvvdp():
    """``pycvvdp``, imported where PyTorch is a CPU build.

    cvvdp imports torchvision (for a Gaussian blur written in PyTorch). torchvision's wheels
    on the package index link a CUDA build of PyTorch: beside a CPU build its compiled
    operators do not load, which it allows, but its import then fails declaring fake
    kernels for two of them (``nms``, ``qnms``) that no longer exist. Declaring their
    schemas first lets it import; cvvdp calls neither.
    """
    import sys

    import torch

    try:
        import pycvvdp
    except RuntimeError as exc:
        if "torchvision::" not in str(exc):
            raise
        for name in [m for m in sys.modules if m.split(".")[0] in ("torchvision", "pycvvdp")]:
            del sys.modules[name]
        ops = torch.library.Library("torchvision", "DEF")
        for op in ("nms", "qnms"):
            ops.define(f"{op}(Tensor dets, Tensor scores, float iou_threshold) -> Tensor")
        _TORCHVISION_OPS.append(ops)
        import pycvvdp
    return pycvvdp
