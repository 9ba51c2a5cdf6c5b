"""aaeval as a library: load a scene, render it, compare methods, run and read sweeps.

These are the functions ``import aaeval`` exposes (lazily: importing :mod:`aaeval` loads
none of the renderers). They are thin: each one hands its work to the piece the command
line uses, so a number from :func:`compare` is the number ``aaeval compare`` prints for
the same scene, methods and frames. Each one that renders, measures or reads results
loads the registries first (:func:`aaeval.registries.load`, once per process). See
``docs/python.md``.
"""

from __future__ import annotations

import numbers
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from aaeval import registries
from aaeval.errors import ArgumentError
from aaeval.options import MAX_INT

if TYPE_CHECKING:
    import pandas as pd

    from aaeval.scenes import Scene

__all__ = ["load_scene", "render", "compare", "sweep", "open_sweep", "Sweep", "ArgumentError", "SweepIncomplete", "show",
           "show_scenes_in"]


class SweepIncomplete(RuntimeError):
    """:func:`sweep` finished with cells that did not run (a worker or the cluster was lost,
    or a worker could not start): ``summary`` says how many; the finished cells are kept and
    calling :func:`sweep` again runs the rest."""

    def __init__(self, message: str, summary: Any):
        super().__init__(message)
        self.summary = summary


def _refused(name: str, expected: str, value: Any) -> ArgumentError:
    if isinstance(value, numbers.Integral) and abs(value) > MAX_INT:  # its repr may be past int's digit limit
        shown = f"an integer of {int(value).bit_length()} bits"
    elif isinstance(value, (str, bytes, numbers.Number, type(None))):
        shown = repr(value)
    else:
        shown = type(value).__name__
    if len(shown) > 80:
        shown = shown[:77] + "..."
    return ArgumentError(f"{name}: expected {expected}, got {shown}")


def _path(name: str, value: Any) -> Path:
    """``value`` as a path: a str or an ``os.PathLike`` of str, not empty, no NUL byte."""
    text = os.fspath(value) if isinstance(value, os.PathLike) else value
    if not isinstance(text, str) or not text or "\0" in text:
        raise _refused(name, "a path (str or pathlib.Path, not empty)", value)
    return Path(text)


def _whole(name: str, value: Any, low: int, rule: str) -> int:
    """``value`` as an int in [``low``, 2**63 - 1] (a Python or numpy integer; not a bool, a
    float, a str)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not low <= value <= MAX_INT:
        raise _refused(name, rule, value)
    return int(value)


def _text(name: str, value: Any, what: str) -> str:
    if not isinstance(value, str):
        raise _refused(name, what, value)
    return value


def _texts(name: str, value: Any, what: str) -> list[str]:
    """A str (one) or a sequence of str (a list, a tuple), each checked."""
    if isinstance(value, str):
        return [value]
    if not isinstance(value, Sequence) or isinstance(value, (bytes, bytearray)):
        raise _refused(name, f"{what} or a list of them", value)
    return [_text(f"{name}[{i}]", item, what) for i, item in enumerate(value)]


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise _refused(name, "True or False", value)
    return bool(value)


def load_scene(scene: str | Path | Mapping[str, Any] | "Scene") -> "Scene":
    """A validated scene from a TOML file, a parsed document (a dict) or a Scene.

    Parameters
    ----------
    scene : str, Path, mapping or Scene
        A scene file (``configs/scenes/fan.toml``), the same content as a dictionary
        (``{"image": {...}, "polygons": [...]}``), or a Scene, returned as it is.

    Raises
    ------
    SceneError
        The file is missing or breaks a rule of the scene format (``docs/scene_format.md``).
    """
    from aaeval.scenes import Scene, parse_scene
    from aaeval.scenes import load_scene as load_file

    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return parse_scene(scene, source="<document>")
    if not isinstance(scene, (str, os.PathLike)):
        raise _refused("scene", "a Scene, a scene file's path or a scene document (dict)", scene)
    return load_file(_path("scene", scene))


def render(scene, spec: str = "catmull", frame: int = 0) -> np.ndarray:
    """Render frame ``frame`` of ``scene`` with the method ``spec``.

    Parameters
    ----------
    scene : Scene, path or mapping
        Anything :func:`load_scene` takes.
    spec : str or MethodSpec
        A method spec as on the command line: ``"catmull"``, ``"supersample:k=4"``.
    frame : int
        The animation's frame, from 0.

    Returns
    -------
    image : ndarray
        (height, width, 3) linear RGB, float64.

    Raises
    ------
    ArgumentError
        An argument of the wrong type, or a frame outside the animation.
    """
    from aaeval.renderers import render as render_spec

    spec = _text("spec", spec, "a method spec (str), such as 'catmull'")
    frame = _whole("frame", frame, 0, "a frame number (an int >= 0)")
    registries.load()
    scene = load_scene(scene)
    if frame >= scene.frames:
        raise ArgumentError(f"frame: {frame} is outside the scene's frames 0..{scene.frames - 1}")
    return render_spec(scene, spec, frame=frame)


def compare(scene, specs: Sequence[str] | str, reference: str = "catmull", frames: int | str = 1,
            metrics: Sequence[str] | None = None, temporal: Sequence[str] | None = None,
            repeats: int = 1) -> "pd.DataFrame":
    """Every method in ``specs`` against ``reference``, frame by frame, as ``aaeval compare``.

    Parameters
    ----------
    scene : Scene, path or mapping
        Anything :func:`load_scene` takes.
    specs : sequence of str, or one str
        Method specs to compare.
    reference : str
        The reference method spec (default the exact ``catmull``).
    frames : int or "all"
        The first N frames of the animation, or every frame.
    metrics, temporal : sequence of str, optional
        Image and temporal metrics (``aaeval metrics``); default every one that applies.
        Metrics that need a mask (``edge_rmse``) get it built from the scene.
    repeats : int
        Timed renders per method and frame (the median is reported).

    Returns
    -------
    table : DataFrame
        One row per method and frame: ``method``, ``frame``, one column per metric,
        ``intensity_sum``, the timings (``render_s`` ...) and ``error`` (None when the
        render succeeded). ``table.attrs["document"]`` holds the whole comparison
        (per-method summary and temporal metrics), as ``aaeval compare --format json``.
    """
    import pandas as pd

    from aaeval.sweeps.compare import plan_comparison, run_comparison

    specs = _texts("specs", specs, "a method spec (str)")  # texts are parsed once, by the plan
    reference = _text("reference", reference, "a method spec (str), such as 'catmull'")
    if frames != "all":
        frames = _whole("frames", frames, 1, "a number of frames (an int >= 1) or 'all'")
    metrics = None if metrics is None else _texts("metrics", metrics, "a metric name (str)")
    temporal = None if temporal is None else _texts("temporal", temporal, "a temporal metric name (str)")
    repeats = _whole("repeats", repeats, 1, "a number of timed renders (an int >= 1)")
    registries.load()
    plan = plan_comparison(load_scene(scene), specs, reference, frames, metrics=metrics, temporal=temporal,
                           repeats=repeats)
    document = run_comparison(plan)
    rows = [{**row, "method": str(row["method"])} for row in document["rows"]]
    table = pd.DataFrame(rows)
    table.attrs["document"] = document
    return table


def sweep(config, out: str | Path, **options: Any) -> Path:
    """Run an experiment config into the folder ``out`` (resumable) and return the folder.

    Parameters
    ----------
    config : path, mapping or Experiment
        An experiment config file (``configs/sweeps/*.toml``), the same as a
        dictionary, or a loaded :class:`~aaeval.sweeps.Experiment`.
    out : path
        The results folder; finished cells in it are kept.
    **options
        Passed to :func:`aaeval.sweeps.run_sweep`: ``workers`` (local worker
        processes, a positive int; default every core), ``scheduler`` (a Dask scheduler's
        address or Client), ``quiet``, ``retry_failed``, ``force`` (bools), ``cache_dir``
        (a path).

    Returns
    -------
    folder : Path
        ``out``, holding ``results.parquet`` (read it with :func:`open_sweep`).

    Raises
    ------
    ArgumentError
        An argument of the wrong type or value, before anything runs.
    SweepIncomplete
        Some cells did not run (a worker or the cluster was lost); the others are kept, and
        calling :func:`sweep` again runs the rest. With local workers, a script must call
        :func:`sweep` under ``if __name__ == "__main__":`` (each worker starts by importing
        the script).
    """
    from aaeval.sweeps import Experiment, load_experiment, parse_experiment, run_sweep
    from aaeval.sweeps.task_failures import NO_MAIN_GUARD

    if _importing_a_worker():  # the script's top level, run again by a worker that imports it
        raise SystemExit(f"aaeval.sweep() called while a worker process imports the script: {NO_MAIN_GUARD}")
    options = _sweep_options(options)
    out = _path("out", out)
    registries.load()
    if isinstance(config, Mapping):
        config = parse_experiment(config)
    elif isinstance(config, (str, os.PathLike)):
        config = load_experiment(_path("config", config))
    elif not isinstance(config, Experiment):
        raise _refused("config", "an experiment config's path, its content (dict) or an Experiment", config)
    summary = run_sweep(config, out, **options)
    if summary.lost:
        raise SweepIncomplete(f"{out}: {len(summary.lost)} of {summary.total} cell(s) did not run ({summary.lost[0]}); "
                              "finished cells are kept, call sweep() again to run the rest", summary)
    return out


def _importing_a_worker() -> bool:
    """Whether this is a process that multiprocessing is still starting ("spawn": it imports
    the parent's main script before it runs anything it was started for)."""
    import multiprocessing

    return bool(getattr(multiprocessing.current_process(), "_inheriting", False))


# sweep()'s keyword options: the check of each (run_sweep's own keywords)
_SWEEP_OPTIONS = {
    "workers": lambda v: None if v is None else _whole("workers", v, 1, "a number of worker processes (an int >= 1)"),
    "quiet": lambda v: _flag("quiet", v),
    "retry_failed": lambda v: _flag("retry_failed", v),
    "force": lambda v: _flag("force", v),
    "cache_dir": lambda v: None if v is None else _path("cache_dir", v),
    "scheduler": lambda v: _scheduler(v),
}


def _sweep_options(options: Mapping[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(options) - set(_SWEEP_OPTIONS))
    if unknown:
        raise ArgumentError(f"sweep(): unknown option(s) {unknown}; options: {', '.join(_SWEEP_OPTIONS)}")
    checked = {name: _SWEEP_OPTIONS[name](value) for name, value in options.items()}
    checked.setdefault("quiet", True)
    return checked


def _scheduler(value: Any) -> Any:
    """A Dask scheduler: None (run locally), a non-empty address or a ``distributed.Client``."""
    if value is None or (isinstance(value, str) and value.strip()):
        return value
    client = sys.modules.get("distributed")
    if client is not None and isinstance(value, client.Client):
        return value
    raise _refused("scheduler", "a Dask scheduler address such as 'tcp://HOST:8786', a distributed.Client or None",
                   value)


@dataclass(frozen=True)
class Sweep:
    """A finished sweep folder: its ``results`` (one row per cell) and ``temporal`` (one row
    per animation) tables."""

    folder: Path
    results: "pd.DataFrame"
    temporal: "pd.DataFrame"

    def __repr__(self) -> str:
        return f"Sweep({str(self.folder)!r}, {len(self.results)} cells, {len(self.temporal)} animations)"

    def _repr_html_(self) -> str:
        return f"<p>{self.__repr__()}</p>" + self.results.head(20)._repr_html_()


def open_sweep(folder: str | Path) -> Sweep:
    """The results tables of a sweep folder written by :func:`sweep` or ``aaeval sweep``.

    Raises
    ------
    FileNotFoundError
        ``folder`` holds no ``results.parquet``.
    """
    from aaeval.sweeps.table import read_table

    folder = _path("folder", folder)
    registries.load()
    if not (folder / "results.parquet").is_file():
        raise FileNotFoundError(f"{folder}: no results.parquet; run a sweep into it first")
    temporal = folder / "temporal.parquet"
    import pandas as pd

    return Sweep(folder, read_table(folder / "results.parquet"),
                 read_table(temporal) if temporal.is_file() else pd.DataFrame())


# --- display in notebooks ----------------------------------------------------------

from aaeval.preview import show, show_scenes_in, show_scenes_in_a_running_notebook  # noqa: E402

show_scenes_in_a_running_notebook()
