"""Where and with what a sweep ran: ``DIR/provenance.json``, written once per sweep run that
renders cells, read by the report.

Fields: ``machine`` (host name), ``cpu_model``, ``cores`` (logical CPUs), ``platform``,
``executor`` and ``workers`` (how the cells shared the machine), ``versions`` (python,
aaeval, numpy, mitsuba, drjit,
skia-python, scikit-image; None where a package is missing), ``code_version`` and
``written_at``. Each record also names its own ``host``, ``executor`` and ``workers``.
"""

from __future__ import annotations

import json
import os
import platform
import socket
import time
from importlib import metadata
from pathlib import Path

__all__ = ["provenance", "write_provenance", "read_provenance", "PROVENANCE_FILE"]

PROVENANCE_FILE = "provenance.json"
_PACKAGES = {"numpy": "numpy", "mitsuba": "mitsuba", "drjit": "drjit", "skia": "skia-python",
             "scikit-image": "scikit-image", "pandas": "pandas", "pyarrow": "pyarrow"}


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def provenance(executor: str, workers: int) -> dict:
    """This machine, the executor, and the library versions, as a JSON-ready dict."""
    import aaeval
    from aaeval.sweeps.cache_keys import code_version

    versions = {"python": platform.python_version(), "aaeval": aaeval.__version__}
    versions.update({name: _version(dist) for name, dist in _PACKAGES.items()})
    return {"machine": socket.gethostname(), "cpu_model": _cpu_model(), "cores": os.cpu_count(),
            "platform": platform.platform(), "executor": executor, "workers": int(workers),
            "versions": versions, "code_version": code_version(),
            "written_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def write_provenance(root: str | Path, executor: str, workers: int) -> dict:
    from aaeval.sweeps.typed_json import dumps
    from aaeval.imageio import atomic_write

    info = provenance(executor, workers)
    text = dumps(info, indent=1) + "\n"
    atomic_write(Path(root) / PROVENANCE_FILE, lambda tmp: Path(tmp).write_text(text))
    return info


def read_provenance(root: str | Path) -> dict | None:
    """The sweep folder's provenance, or None for a folder written before it existed."""
    from aaeval.sweeps.folder_files import read_own_file

    path = Path(root) / PROVENANCE_FILE
    if not os.path.lexists(path):
        return None
    try:  # never through a link or from a FIFO planted in the folder
        return json.loads(read_own_file(path).decode("utf-8"))
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: not a readable provenance file ({exc}); run the sweep again to rewrite it") from None
