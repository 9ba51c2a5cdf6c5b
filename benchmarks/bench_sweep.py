"""Where a sweep's wall time goes: start-up, renders, each metric, masks, the store, the
results table, and the scheduling and bookkeeping around them, in total and per cell.

    PYTHONPATH=. python benchmarks/bench_sweep.py [CONFIG] [--group NAME] [--workers N]
        [--out benchmarks/results/bench_sweep.txt]

CONFIG defaults to configs/sweeps/default.toml; ``--group`` keeps one of its groups
(e.g. ``edge-aliasing``). The sweep runs from an empty folder and an empty reference cache
(both temporary), with the real ``fsync``.

With one worker (the default) the sweep runs in this process and every part is timed where
it runs: each timed function's own time, without the timed functions it calls (a render
inside a reference is the reference's render, not the cell's). ``start-up`` is importing
what a worker imports (aaeval, numpy, colour-science, scikit-image, flip-evaluator,
Mitsuba); ``scheduling and bookkeeping`` is what is left of the sweep's wall time: planning,
payloads, the executor, records. ``overhead`` is everything but the renders and the metric
kernels (masks and the z-test's noise twins count as metric work). With ``--workers N > 1``
the cells run in worker processes and only the wall time is measured.
"""

from __future__ import annotations

import time

_STARTED = time.perf_counter()

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import functools  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from collections import Counter, defaultdict  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


class Clock:
    """Exclusive time per bucket: a timed call's time less the timed calls inside it."""

    def __init__(self):
        self.seconds: dict[str, float] = defaultdict(float)
        self.calls: Counter = Counter()
        self._inner: list[float] = []
        self.owners: list[str] = ["sweep"]  # whose render a render is

    def add(self, bucket: str, seconds: float, calls: int = 1) -> None:
        self.seconds[bucket] += seconds
        self.calls[bucket] += calls

    def wrap(self, bucket, fn, owner: str | None = None):
        """``fn`` timed into ``bucket`` (a name, or a function of the current owner);
        ``owner``: what renders inside it are renders of."""

        @functools.wraps(fn)
        def timed(*args, **kwargs):
            name = bucket(self.owners[-1]) if callable(bucket) else bucket
            if owner:
                self.owners.append(owner)
            self._inner.append(0.0)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                spent = time.perf_counter() - start
                self.add(name, spent - self._inner.pop())
                if self._inner:
                    self._inner[-1] += spent
                if owner:
                    self.owners.pop()

        return timed


def patch(clock: Clock) -> None:
    """Time every part of a sweep that runs in this process."""
    import aaeval.renderers as renderers
    from aaeval.sweeps import measure, report_files, runner, store, tasks
    from aaeval.metrics import registry

    def on(owner, name, bucket, *, owns=None):
        if hasattr(owner, name):  # another version of aaeval may lack it (a comparison with older code)
            setattr(owner, name, clock.wrap(bucket, getattr(owner, name), owns))

    on(renderers, "render_timed", lambda owner: f"render ({owner})")
    on(tasks, "render_reference", "reference noise and strata", owns="references")
    for name in ("measure_frame", "measure_frames"):  # the first: older code, one cell per call
        on(tasks, name, "cell: intensity sum, checks", owns="cells")
    on(measure, "_test_noise", "z-test: noise strata", owns="z-test noise twins")
    on(measure, "agreement", "z-test: pass fractions")
    on(measure, "mask_source", "masks", owns="masks")
    from aaeval.metrics import colour_difference

    on(colour_difference, "ciede2000_maps", "metric: ciede2000 maps in bulk")
    for name in ("mask", "noise_weight", "exact_series"):
        on(measure.SceneCache, name, "masks")
    for views in (registry.IMAGE_METRICS, registry.TEMPORAL_METRICS):
        for name in list(views):
            views[name] = clock.wrap(f"metric: {name}", views[name])
    for name in ("write_cells", "write_cell"):  # the second: older code, one cell per call
        on(store.SweepStore, name, "store: cells")
    for name in ("write_reference", "load_reference"):
        on(store.SweepStore, name, "store: references")
    from aaeval.sweeps import reference_cache

    for name in ("get", "put"):
        on(reference_cache.ReferenceCache, name, "store: references")
    for name in ("write_manifest", "check"):
        on(store.SweepStore, name, "store: manifest, checks")
    on(runner, "write_provenance", "store: manifest, checks")
    on(report_files, "write_sweep_files", "results table")
    on(report_files, "write_summary_tables", "results table")


def startup(clock: Clock) -> None:
    """Import what a worker needs (timed as start-up), the registries loaded."""
    start = time.perf_counter()
    import colour  # noqa: F401
    import flip_evaluator  # noqa: F401
    import mitsuba  # noqa: F401
    import skimage.metrics  # noqa: F401

    import aaeval.sweeps  # noqa: F401
    from aaeval import registries

    registries.load()
    clock.add("start-up: imports", time.perf_counter() - start + (start - _STARTED))


def experiment_of(config: Path, group: str | None):
    from aaeval.sweeps import load_experiment

    experiment = load_experiment(config)
    if group is None:
        return experiment
    groups = tuple(g for g in experiment.groups if g.name == group)
    if not groups:
        sys.exit(f"bench_sweep: {config} has no group {group!r}; groups: {', '.join(g.name for g in experiment.groups)}")
    return dataclasses.replace(experiment, groups=groups, speed=())


RENDER, METRIC = ("render (cells)", "render (references)"), ("metric: ", "masks", "z-test", "render (z-test", "render (masks")


def table(clock: Clock, wall: float, cells: int, title: str) -> str:
    """The table: each bucket's seconds, milliseconds per cell and share of the wall time."""
    measured = sum(clock.seconds.values())
    rows = dict(sorted(clock.seconds.items(), key=lambda kv: -kv[1]))
    rows["scheduling and bookkeeping"] = max(0.0, wall - measured)
    lines = [title, f"{'part':42s} {'seconds':>9s} {'ms/cell':>9s} {'share':>7s}"]
    for name, seconds in rows.items():
        lines.append(f"{name:42s} {seconds:9.2f} {seconds / cells * 1e3:9.2f} {seconds / wall:7.1%}")
    lines.append(f"{'wall time':42s} {wall:9.2f} {wall / cells * 1e3:9.2f} {1:7.1%}")
    work = sum(s for n, s in rows.items() if n in RENDER or n.startswith(METRIC))
    start = rows.get("start-up: imports", 0.0)
    lines.append(f"overhead (all but renders and metric kernels): {wall - work:.2f} s, "
                 f"{(wall - work) / cells * 1e3:.2f} ms per cell; without start-up "
                 f"{(wall - work - start) / cells * 1e3:.2f} ms per cell ({cells} cells)")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("config", nargs="?", type=Path, default=ROOT / "configs/sweeps/default.toml")
    parser.add_argument("--group", help="keep only this group of the config")
    parser.add_argument("--workers", type=int, default=1, help="1: split the time; more: wall time only")
    parser.add_argument("--out", type=Path, help="also write the table to this file")
    args = parser.parse_args(argv)
    clock = Clock()
    startup(clock)
    from aaeval.sweeps import run_sweep

    experiment = experiment_of(args.config, args.group)
    if args.workers == 1:
        patch(clock)
    with tempfile.TemporaryDirectory(prefix="bench-sweep-") as tmp:
        os.environ["AAEVAL_CACHE_DIR"] = tmp  # ground truths for masks too: nothing from earlier runs
        start = time.perf_counter()
        summary = run_sweep(experiment, Path(tmp) / "out", workers=args.workers, quiet=True,
                            cache_dir=Path(tmp) / "cache", log=lambda *a: None)
        wall = time.perf_counter() - start + clock.seconds["start-up: imports"]
    what = f"{experiment.name}" + (f", group {args.group}" if args.group else "")
    title = (f"bench_sweep: {what}: {summary.total} cells, {summary.references_rendered} references, "
             f"{args.workers} worker(s), {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
             f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    if args.workers == 1:
        text = table(clock, wall, summary.total, title)
    else:
        text = f"{title}\nwall time {wall:.2f} s ({wall / summary.total * 1e3:.2f} ms per cell, start-up included)"
    print(text)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
