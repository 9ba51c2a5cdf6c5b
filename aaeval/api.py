"""aaeval as a library: load a scene, render it, compare methods, run and read sweeps.

These are the functions ``import aaeval`` exposes (lazily: importing :mod:`aaeval` loads
none of the renderers). They are thin: each one hands its work to the piece the command
line uses, so a number from :func:`compare` is the number ``aaeval compare`` prints for
the same scene, methods and frames. Each one that renders, measures or reads results
loads the registries first (:func:`aaeval.registries.load`, once per process). See
``docs/python.md``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from aaeval import registries

if TYPE_CHECKING:
    import pandas as pd

    from aaeval.scenes import Scene

__all__ = ["load_scene", "render", "compare", "sweep", "open_sweep", "Sweep", "show", "show_scenes_in"]


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
    return load_file(scene)


def render(scene, spec: str = "catmull", frame: int = 0) -> np.ndarray:
    """Render frame ``frame`` of ``scene`` with the method ``spec``.

    Parameters
    ----------
    scene : Scene, path or mapping
        Anything :func:`load_scene` takes.
    spec : str or MethodSpec
        A method spec as on the command line: ``"catmull"``, ``"supersample:k=4"``.

    Returns
    -------
    image : ndarray
        (height, width, 3) linear RGB, float64.
    """
    from aaeval.renderers import render as render_spec

    registries.load()
    return render_spec(load_scene(scene), spec, frame=frame)


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

    from aaeval.experiments.compare import plan_comparison, run_comparison

    registries.load()
    specs = [specs] if isinstance(specs, str) else list(specs)  # texts are parsed once, by the plan
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
        An experiment config file (``configs/experiments/*.toml``), the same as a
        dictionary, or a loaded :class:`~aaeval.experiments.Experiment`.
    out : path
        The results folder; finished cells in it are kept.
    **options
        Passed to :func:`aaeval.experiments.run_sweep` (``workers``, ``quiet``,
        ``retry_failed``, ``cache_dir``, ``force``).

    Returns
    -------
    folder : Path
        ``out``, holding ``results.parquet`` (read it with :func:`open_sweep`).
    """
    from aaeval.experiments import Experiment, load_experiment, parse_experiment, run_sweep

    registries.load()
    if isinstance(config, Mapping):
        config = parse_experiment(config)
    elif not isinstance(config, Experiment):
        config = load_experiment(config)
    options.setdefault("quiet", True)
    run_sweep(config, out, **options)
    return Path(out)


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
    from aaeval.experiments.table import read_table

    registries.load()
    folder = Path(folder)
    if not (folder / "results.parquet").is_file():
        raise FileNotFoundError(f"{folder}: no results.parquet; run a sweep into it first")
    temporal = folder / "temporal.parquet"
    import pandas as pd

    return Sweep(folder, read_table(folder / "results.parquet"),
                 read_table(temporal) if temporal.is_file() else pd.DataFrame())


# --- display in notebooks ----------------------------------------------------------

from aaeval.preview import show, show_scenes_in, show_scenes_in_a_running_notebook  # noqa: E402

show_scenes_in_a_running_notebook()
