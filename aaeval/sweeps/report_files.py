"""The files of a sweep folder that the report reads beside the engine's tables
(:mod:`aaeval.sweeps.table`, which only tabulates): ``metrics.json`` (every registered metric's
:class:`~aaeval.metrics.info.MetricInfo`), ``specs.json`` (each spec's method and options, each
method's declared choices and speed baseline, for the figures' styles and the speed section),
``controls.json`` (every temporal metric on the controls whose answer is known,
:mod:`aaeval.metrics.controls`), ``specular_detection.npz`` (Amanatides' detector on the first
scene with shaded objects), the FLIP map of every finished cell stored without one, and in
``summaries/`` every table the page shows, aggregated once (:mod:`aaeval.sweeps.summaries`).

They are made here, by the sweep, and not by the report: some are measured (the detector, the
FLIP maps, the controls), and the report reaches nothing that renders or measures
(tests/report/test_report_imports.py). The sweep writes them when it ends
(:func:`write_sweep_files`) and the summaries again after its speed pass
(:func:`write_summary_tables`); the report only reads them (:mod:`aaeval.report.sweep_data`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.imageio import atomic_write
from aaeval.sweeps.measure import SCENES
from aaeval.sweeps.store import SweepStore, read_table
from aaeval.sweeps.summaries import SUMMARY_FOLDER, summarize
from aaeval.sweeps.table import results_frame, temporal_frame, write_parquet, write_results
from aaeval.sweeps.typed_json import dumps

__all__ = ["REPORT_FILES", "specs_of", "controls_of", "write_report_files", "write_summary_tables",
           "write_sweep_files", "rebuild_results"]

#: The sweep folder's files besides its tables and summaries, written with them (:func:`write_sweep_files`).
REPORT_FILES = ("metrics.json", "specs.json", "controls.json", "specular_detection.npz")


def write_sweep_files(store: SweepStore) -> pd.DataFrame:
    """Rebuild the tables from the cell files (:func:`aaeval.sweeps.table.write_results`) and write
    every file the report reads beside them, holding the folder's lock (a sweep calling this
    already holds it; another process's running sweep is :class:`~aaeval.sweeps.folder_lock.FolderInUse`).
    Returns ``results.parquet``'s frame."""
    with store.lock("report"):
        results = write_results(store)
        write_report_files(store, results)
        write_summary_tables(store)
    return results


def rebuild_results(store: SweepStore) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Both tables, rebuilt from the cell files on disk (``results.parquet`` and
    ``temporal.parquet`` rewritten with the files beside them, :func:`write_sweep_files`) and returned.

    While a sweep writes the folder (it holds the lock) nothing of it is rewritten or
    moved: both tables are built in memory from the cells finished so far, and the sweep
    rewrites ``results.parquet`` when it ends."""
    with store.try_lock("report") as held:
        if held:
            results = write_sweep_files(store)
            return results, read_table(store.root / "temporal.parquet")
    owner = store.owner()
    store.log(f"{store.root} is being written by a running {owner.get('command', 'sweep')} (pid "
              f"{owner.get('pid', '?')}): reading the cells finished so far, leaving results.parquet to it")
    results = results_frame(store, heal=False)
    return results, temporal_frame(store, results)


def write_report_files(store: SweepStore, results: pd.DataFrame) -> None:
    """The files of :data:`REPORT_FILES`: what the report shows beside the cells' tables."""
    from aaeval.metrics import METRICS

    _write_json(store.writable("metrics.json"), {name: m.info().to_dict() for name, m in METRICS.items()})
    _write_json(store.writable("specs.json"), specs_of(results))
    # the measures this sweep's temporal table holds: the page explains those (and a costly one
    # that was not asked for, a perceptual model, is not run for the page)
    measured = set(read_table(store.root / "temporal.parquet").columns)
    _write_json(store.writable("controls.json"), controls_of(measured))
    write_detection(store, results)
    write_missing_flips(store, results)


def _write_json(path: Path, data) -> None:
    text = dumps(data, sort_keys=True, indent=1)
    atomic_write(path, lambda tmp: Path(tmp).write_text(text + "\n"))


def specs_of(results: pd.DataFrame) -> dict:
    """Each spec's method and options (keyed by the ``options`` column's text, which names
    them in every table), each shown method's declared choices per option, and the speed baseline
    each shown method declares (:attr:`aaeval.renderers.Method.speed_baseline`)."""
    from aaeval.renderers import METHODS

    specs = {}
    for method, options in dict.fromkeys(zip(results.get("method", []), results.get("options", []))):
        specs.setdefault(method, {})[options] = json.loads(options)
    choices, baselines = {}, {}
    for method in specs:
        declared = METHODS.get(method)
        choices[method] = {name: list(option.choices) for name, option in (declared.options.items() if declared else ())
                           if option.choices}
        if declared is not None and declared.speed_baseline is not None:
            baselines[method] = declared.speed_baseline
    return {"specs": specs, "choices": choices, "speed_baselines": baselines}


def controls_of(measured=None) -> dict:
    """The temporal metrics ``measured`` (every registered one when None) on the controls
    whose answer is known."""
    from aaeval.metrics.controls import CONTROL_NOTES, CONTROLS, control_scores

    return {"controls": list(CONTROLS), "notes": dict(CONTROL_NOTES), "scores": control_scores(measured)}


def write_summary_tables(store: SweepStore) -> None:
    """``DIR/summaries/``: every table the report shows, from the tables just written
    (:mod:`aaeval.sweeps.summaries`); again after the speed pass, whose summary it holds."""
    from aaeval.sweeps.speed import read_speed
    from aaeval.metrics.info import MetricInfo

    root = store.root
    infos = {name: MetricInfo.from_dict(entry) for name, entry in json.loads((root / "metrics.json").read_text()).items()}
    # from the stored tables, not the frames in memory: a summary is of exactly what a reader of
    # the folder finds (parquet's types), and after the speed pass only the files are at hand
    found = summarize(read_table(root / "results.parquet"), read_table(root / "temporal.parquet"), read_speed(root),
                      store.read_manifest(), infos, store)
    folder = store.own_folder(SUMMARY_FOLDER)
    for name, frame in found.items():
        write_parquet(frame, folder / f"{name}.parquet")


def write_detection(store: SweepStore, results: pd.DataFrame) -> None:
    """Amanatides' detector (:func:`aaeval.specular.render.specular_aliasing_map`) on frame 0 of
    the first scene with shaded objects, conservative (power 1) and at P = 0.999; no file
    when the sweep has no such scene."""
    path = store.writable("specular_detection.npz")
    shaded = results[results["shaded"]] if "shaded" in results else results.iloc[:0]
    if shaded.empty:
        path.unlink(missing_ok=True)
        return
    from aaeval.specular.render import specular_aliasing_map

    first = shaded.iloc[0]
    entry = store.read_manifest()["scenes"][first["scene_digest"]]
    scene = SCENES.scene(first["scene_digest"], entry["document"], entry["source"]).at_frame(0)
    maps = {power: specular_aliasing_map(scene, power=power) for power in (1.0, 0.999)}
    arrays = {"scene": np.array(first["scene"]), "dot": maps[1.0].dot,
              **{f"{name}_{power:g}": getattr(found, name) for power, found in maps.items() for name in ("rate", "flag")}}
    atomic_write(path, lambda tmp: np.savez(tmp, **arrays))  # tmp ends in .npz: savez adds nothing


def write_missing_flips(store: SweepStore, results: pd.DataFrame) -> None:
    """The FLIP map of every finished cell that has none: the worker stores it with the
    image; cells a sweep finished before it did get theirs here, once."""
    from aaeval.metrics.perceptual import flip_map

    if results.empty:
        return
    ok = results[results["error"].isna()].drop_duplicates("key")
    references: dict[str, np.ndarray] = {}
    for key, ref_key in zip(ok["key"], ok["reference_key"]):
        if store.flip_path(key).is_file():
            continue
        image = store.load_image(key)
        if ref_key not in references:
            references = {ref_key: store.load_reference(ref_key)}  # cells of one reference are neighbours
        if image is not None and references[ref_key] is not None:
            store.write_flip(key, flip_map(references[ref_key], image))
