"""A sweep whose cells pause before they render, so that a test can stop it mid-way.

Run as a script: ``python tests/helpers/slow_sweep.py CONFIG OUT CACHE WORKERS`` with
``SLOW_SWEEP_PAUSE`` seconds a cell in the environment (default 0.4). A script file, not
``python -c``: spawned workers import it again and so know the method "test-slow".
The config is :func:`tests.helpers.sweep_util.slow_config`.
"""

import os
import sys
import time

from aaeval.renderers import register_method, render


@register_method("test-slow", summary="catmull after a pause, so a sweep can be stopped mid-way")
def slow(scene):
    time.sleep(float(os.environ.get("SLOW_SWEEP_PAUSE", "0.4")))
    return render(scene, "catmull")


if __name__ == "__main__":
    from aaeval.cli import main

    config, out, cache, workers = sys.argv[1:5]
    sys.exit(main(["sweep", config, "--out", out, "--workers", workers, "--quiet", "--cache", cache]))
