"""The speed pass: the only render times the report charts.

Accuracy cells may run on several workers at once, so their times say how busy the machine
was. The speed pass runs after them, in the sweep's own process (one worker), with a stated
number of threads: for every ``[[speed]]`` table of the config and every scene of it, each
method spec is warmed up (:func:`aaeval.renderers.run.warm_up`: the spec itself,
untimed), then timed ``repeats`` times in interleaved rounds (the methods take turns inside
each round, the order rotating), as ``benchmarks/bench_methods.py`` does, so a machine
shared with other work disturbs them alike.

``DIR/speed.parquet``: one row per (table, scene, spec, round) with ``render_s`` and
``ms_per_mpix``, and the pass's identity in its metadata; a rerun with the same config,
code and machine keeps it. The report sums it up (one row per scene and spec: median,
fastest and slowest).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import time
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from aaeval.sweeps.config import Experiment, SpeedPass
from aaeval.imageio import atomic_write

if TYPE_CHECKING:
    from aaeval.renderers.spec import MethodSpec

__all__ = ["SPEED_FILE", "run_speed_pass", "read_speed", "speed_identity", "accuracy_spec"]

SPEED_FILE = "speed.parquet"
_META_KEY = b"aaeval_speed_identity"


def speed_identity(experiment: Experiment) -> str:
    """Digest of what the pass times (scenes, specs, repeats, threads), the code and the machine."""
    from aaeval.sweeps.cache_keys import code_version

    what = [{"scenes": [s.digest for s in p.scenes], "specs": list(p.specs), "repeats": p.repeats,
             "threads": p.threads} for p in experiment.speed]
    config = {"passes": what, "code": code_version(), "host": platform.node(), "cores": os.cpu_count()}
    return hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()[:16]


def accuracy_spec(spec: MethodSpec) -> MethodSpec:
    """``spec`` as the accuracy cells name it: the thread count (which changes no pixel) at
    its default, so a timing pairs with the same method's errors."""
    if "threads" in spec.method.options:
        return spec.with_options(threads=spec.method.options["threads"].default)
    return spec


def _time_table(index: int, speed: SpeedPass, log) -> list[dict]:
    from aaeval.renderers import render_timed, warm_up

    rows = []

    def row(src, scene, spec, r, seconds, error=None) -> dict:
        paired = accuracy_spec(spec)
        return {"pass": index, "scene": src.name, "difficulty": src.difficulty,
                "scene_digest": src.digest, "width": scene.width, "height": scene.height,
                "spec": str(paired), "timed_spec": str(spec), "label": paired.label(), "method": spec.name,
                "options": json.dumps(dict(paired.options), sort_keys=True), "round": r, "threads": speed.threads,
                "render_s": seconds, "ms_per_mpix": seconds * 1e3 / (scene.width * scene.height / 1e6),
                "accuracy_group": speed.accuracy, "error": error}

    for src in speed.scenes:
        scene = src.parsed
        specs, failed = [], {}
        for spec in speed.specs:
            try:
                warm_up(scene, spec, frame=0)
                specs.append(spec)
            except Exception as exc:  # noqa: BLE001 - a method that cannot render this scene is left out
                failed[spec] = f"{type(exc).__name__}: {exc}"
        log(f"speed pass {index}: {src.name} ({scene.width}x{scene.height}), {len(specs)} methods x "
            f"{speed.repeats} interleaved rounds, {speed.threads} thread(s)")
        for r in range(speed.repeats):
            order = specs[r % len(specs):] + specs[:r % len(specs)] if specs else []
            for spec in order:
                _, (seconds,) = render_timed(scene, spec, frame=0)
                rows.append(row(src, scene, spec, r, seconds))
        for spec, error in failed.items():
            rows.append(row(src, scene, spec, -1, math.nan, error))
    return rows


def run_speed_pass(experiment: Experiment, root: str | Path, *, log=print, force: bool = False) -> pd.DataFrame | None:
    """Time every ``[[speed]]`` table of ``experiment`` in this process; write ``root/speed.parquet``.

    Kept as it is when the file holds a pass of the same identity (:func:`speed_identity`)
    unless ``force``. Returns the table, or None when the config has no ``[[speed]]``.
    """
    if not experiment.speed:
        return None
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(root) / SPEED_FILE
    identity = speed_identity(experiment)
    if path.is_file() and not force:
        meta = pq.read_schema(path).metadata or {}
        if meta.get(_META_KEY, b"").decode() == identity:
            return read_speed(root)
    start = time.perf_counter()
    rows = []
    for i, speed in enumerate(experiment.speed):
        rows.extend(_time_table(i, speed, log))
    frame = pd.DataFrame(rows)
    table = pa.Table.from_pandas(frame, preserve_index=False)
    meta = dict(table.schema.metadata or {})
    meta[_META_KEY] = identity.encode()
    table = table.replace_schema_metadata(meta)
    atomic_write(path, lambda tmp: pq.write_table(table, tmp))
    log(f"speed pass: {len(frame)} timed renders in {time.perf_counter() - start:.0f} s -> {path}")
    return frame


def read_speed(root: str | Path) -> pd.DataFrame:
    """``root/speed.parquet``, or an empty table when the sweep had no speed pass."""
    path = Path(root) / SPEED_FILE
    if not path.is_file():
        return pd.DataFrame()
    return pd.read_parquet(path)


