"""The tidy results tables, rebuilt from the cell files at any time.

``results.parquet``: one row per cell of the manifest that has finished, read through
:class:`~aaeval.sweeps.record.CellRecord` (one column per record field, ``options``
and ``metric_errors`` as JSON text, one column per metric of the experiment, and
``label``). A cell file that is not a readable record of this schema is an error naming
the file. The parquet file's metadata carries ``aaeval_schema_version``.

Each row also carries what the report would otherwise have to work out from spec text or
scene documents: ``exact`` (the method is exact), ``filter`` (its pixel filter),
``label_plain`` (its options that differ from the defaults, whatever varies),
``label_unfiltered`` (its label with the box filter), ``ladder`` (:func:`ladder_of`), the reference's ``reference_method``,
``reference_label`` and ``reference_filter``, ``shaded`` (the scene has shaded objects) and
``phase`` (the frame's sub-pixel offset along x, :meth:`aaeval.scenes.Scene.offset`).

``temporal.parquet``: one row per (group, scene, spec) animation whose frames have all
finished: every temporal metric of the experiment over all its frames, computed from the
stored images by the measuring engine (:func:`aaeval.sweeps.measure.series_metrics`),
and ``reference_sum_variation`` (the reference's own intensity-sum variation).

This module only tabulates. What the report reads beside these tables (the metrics' and
specs' descriptions, the controls, the detector's map, the summaries) is written from them by
:mod:`aaeval.sweeps.report_files`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd

from aaeval.sweeps.measure import SCENES, SceneCache, series_metrics
from aaeval.metrics import relative_variation
from aaeval.sweeps.record import (SCHEMA_VERSION, TABLE_FIELDS, RecordError, agreement_column,
                                       noise_column)
from aaeval.sweeps.store import SCHEMA_KEY, SweepStore, read_table
from aaeval.imageio import atomic_write

__all__ = ["results_frame", "temporal_frame", "write_results", "read_table", "short_label",
           "varying_options", "RESULTS_COLUMNS", "TEMPORAL_COLUMNS", "write_parquet"]

#: Typed columns of ``results.parquet`` the sweep adds to the record's fields.
SPEC_COLUMNS = ("label", "label_plain", "exact", "filter", "label_unfiltered", "ladder", "reference_method", "reference_label",
                "reference_filter")
#: Columns of ``results.parquet`` besides one per metric.
RESULTS_COLUMNS = (*TABLE_FIELDS, *SPEC_COLUMNS, "shaded", "phase")
#: Columns of ``temporal.parquet`` besides one per temporal metric.
TEMPORAL_COLUMNS = ("group", "scene", "difficulty", "difficulty_label", "spec", "label", "method", "options", "ladder",
                    "frames",
                    "reference", "reference_noise_rmse", "failed_frames", "reference_sum_variation", "metric_errors")


def results_frame(store: SweepStore, *, heal: bool = True) -> pd.DataFrame:
    """One row per finished cell of the manifest, in manifest order (``heal=False``: damaged
    cells are left where they are, for a reader that does not hold the folder's lock)."""
    manifest = store.read_manifest()
    metrics = list(manifest.get("metrics", []))
    done = store.sound_records(heal=heal)  # every sound record, read and checked once
    out = []
    for row in manifest["cells"]:
        if row["key"] not in done:
            continue
        record = done[row["key"]]
        wrong = next((name for name in ("group", "scene", "spec", "frame") if getattr(record, name) != row[name]),
                     None)
        if wrong:  # a record edited after it was written: set aside (healing) or left out, never blocking
            store.set_aside(row["key"], f"{wrong} {getattr(record, wrong)!r} differs from the manifest's "
                                        f"{row[wrong]!r}", heal)
            continue
        flat = record.table_row()
        for name in metrics:
            flat.setdefault(name, math.nan)  # a metric another group measured
        out.append(flat)
    from aaeval.metrics import METRICS

    rms = [m for m in metrics if m in METRICS and METRICS[m].rms]
    tests = [f(m) for m in rms for f in (noise_column, agreement_column)]
    columns = [*TABLE_FIELDS, *metrics, *tests]
    frame = pd.DataFrame(out, columns=columns)
    for name, values in _spec_columns(frame).items():
        frame[name] = values
    frame["shaded"], frame["phase"] = _scene_columns(frame, manifest.get("scenes", {}))
    for col in ("render_s", "render_s_min", "render_s_max", "megapixels", "ms_per_mpix", "intensity_sum",
                "reference_noise_rmse", "reference_intensity_sum", "difficulty", "spp", "seed", "reference_spp",
                "reference_seed", *metrics, *tests):
        frame[col] = pd.to_numeric(frame[col], errors="coerce").astype(float)
    return frame


def short_label(spec: str, keep: set[str] = frozenset()) -> str:
    """The label of a spec (:meth:`aaeval.renderers.MethodSpec.label`): the options in
    ``keep`` and those that differ from the defaults; a method this checkout lacks shows
    the spec as stored."""
    parsed = _parsed(spec)
    return parsed.label(keep) if parsed is not None else spec


def varying_options(options_json) -> list[str]:
    """The option names whose values differ between these JSON option tables."""
    opts = [json.loads(o) for o in options_json]
    return sorted(k for k in set().union(*opts) if len({json.dumps(o.get(k)) for o in opts}) > 1)


def _parsed(spec: str):
    """The stored spec parsed, or None for a method this checkout lacks."""
    from aaeval.renderers import MethodError, MethodSpec

    try:
        return MethodSpec.parse(spec)
    except MethodError:
        return None


def ladder_of(method: str, options_json: str) -> str:
    """The method and its options without their numeric values: every spec of one option
    ladder (k, spp) shares it."""
    opts = json.loads(options_json or "{}")
    return f"{method}|" + json.dumps({k: v for k, v in opts.items()
                                      if not (isinstance(v, (int, float)) and not isinstance(v, bool))}, sort_keys=True)


def _spec_columns(frame: pd.DataFrame) -> dict[str, pd.Series]:
    """The typed columns of every row (:data:`SPEC_COLUMNS`), each stored spec parsed once.

    ``label``: the options that are not the default, and those that vary among the
    method's rows anywhere in the sweep; one label per spec, whichever table, figure,
    section or viewer shows it."""
    columns = {name: pd.Series(index=frame.index, dtype=object) for name in SPEC_COLUMNS}
    for _, rows in frame.groupby("method", sort=False):
        varying = set(varying_options(rows["options"]))
        for spec, idx in rows.groupby("spec", sort=False).groups.items():
            parsed = _parsed(spec)
            columns["label"][idx] = parsed.label(varying) if parsed is not None else spec
            columns["label_plain"][idx] = parsed.label() if parsed is not None else spec
            columns["exact"][idx] = bool(parsed is not None and parsed.method.exact)
            columns["ladder"][idx] = ladder_of(rows.loc[idx[0], "method"], rows.loc[idx[0], "options"])
            columns["filter"][idx] = str(parsed.options.get("filter", "box")) if parsed is not None else "box"
            columns["label_unfiltered"][idx] = (parsed.with_options(filter="box").label() if parsed is not None
                                                and "filter" in parsed.method.options else columns["label"][idx])
    for reference, idx in frame.groupby("reference", sort=False).groups.items():
        parsed = _parsed(reference)
        columns["reference_method"][idx] = parsed.method.name if parsed is not None else reference.split(":", 1)[0]
        columns["reference_label"][idx] = parsed.label() if parsed is not None else reference
        columns["reference_filter"][idx] = str(parsed.options.get("filter", "box")) if parsed is not None else "box"
    columns["exact"] = columns["exact"].astype(bool)
    return columns


def _scene_columns(frame: pd.DataFrame, documents: dict) -> tuple[pd.Series, pd.Series]:
    """``shaded`` and ``phase`` of every row, from the scene documents of the manifest
    (NaN phase and not shaded where the manifest lacks the scene)."""
    from aaeval.scenes.phases import subpixel_phase
    from aaeval.scenes.shaded import has_shaded

    shaded = pd.Series(False, index=frame.index, dtype=bool)
    phase = pd.Series(math.nan, index=frame.index, dtype=float)
    for digest, rows in frame.groupby("scene_digest", sort=False):
        entry = documents.get(digest)
        if entry is None:
            continue
        scene = SCENES.scene(digest, entry["document"], entry["source"])
        shaded[rows.index] = has_shaded(scene)
        for k, idx in rows.groupby("frame", sort=False).groups.items():
            phase[idx] = float(subpixel_phase(scene.offset(int(k)))[0])
    return shaded, phase


def temporal_frame(store: SweepStore, results: pd.DataFrame) -> pd.DataFrame:
    """One row per finished animation: every temporal metric over all of its frames."""
    manifest = store.read_manifest()
    names = list(manifest.get("temporal", []))
    out = []
    if results.empty or not names:
        return pd.DataFrame(out, columns=[*TEMPORAL_COLUMNS, *names])
    expected: dict[tuple, set] = {}
    for row in manifest["cells"]:
        expected.setdefault((row["group"], row["scene"], row["spec"]), set()).add(row["frame"])
    scenes = SceneCache()
    documents = manifest.get("scenes", {})
    own = manifest.get("group_temporal", {})
    for (group, scene, spec), series in results.groupby(["group", "scene", "spec"], sort=False):
        frames = expected.get((group, scene, spec), set())
        wanted = own.get(group, names)
        if len(frames) < 2 or set(series["frame"]) != frames:
            continue  # not an animation, or not finished
        series = series.sort_values("frame")
        first = series.iloc[0]
        row = {"group": group, "scene": scene, "difficulty": first["difficulty"],
               "difficulty_label": first["difficulty_label"], "spec": spec, "label": first["label"],
               "method": first["method"], "options": first["options"], "ladder": first["ladder"],
               "frames": len(series),
               "reference": first["reference"],
               "reference_noise_rmse": first["reference_noise_rmse"],
               "failed_frames": int(series["error"].notna().sum()),
               "reference_sum_variation": relative_variation(series["reference_intensity_sum"].to_numpy(float)),
               "metric_errors": None}
        row.update({name: math.nan for name in names})  # a metric another group asked for
        if not row["failed_frames"]:
            digest = first["scene_digest"]
            entry = documents.get(digest)
            tests = [store.load_image(k) for k in series["key"]]
            refs = [store.load_reference(k) for k in series["reference_key"]]
            frame_list = [int(k) for k in series["frame"]]

            def scene_of(entry=entry, digest=digest):
                if entry is None:
                    raise RecordError(f"{store.root}/manifest.json has no scene {digest[:12]}… to build masks")
                return scenes.scene(digest, entry["document"], entry["source"])

            def mask_of(name, digest=digest, frame_list=frame_list, scene_of=scene_of):
                return scenes.series_mask(digest, scene_of(), frame_list, name)

            def exact_of(digest=digest, frame_list=frame_list, scene_of=scene_of):
                return scenes.exact_series(digest, scene_of(), frame_list)

            values, errors = series_metrics(wanted, refs, tests, mask_of, exact_of)
            row.update(values)
            row["metric_errors"] = json.dumps(errors, sort_keys=True) if errors else None
        out.append(row)
    return pd.DataFrame(out, columns=[*TEMPORAL_COLUMNS, *names])


def write_parquet(frame: pd.DataFrame, path: Path) -> None:
    """``frame`` as a parquet file carrying the schema version, written atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_pandas(frame, preserve_index=False)
    meta = dict(table.schema.metadata or {})
    meta[SCHEMA_KEY] = str(SCHEMA_VERSION).encode()
    table = table.replace_schema_metadata(meta)
    atomic_write(path, lambda tmp: pq.write_table(table, tmp))  # replaces a planted link, never follows it


def write_results(store: SweepStore) -> pd.DataFrame:
    """Rebuild ``results.parquet`` and ``temporal.parquet`` from the cell files, holding the
    folder's lock (a sweep calling this already holds it; another process's running sweep
    is :class:`~aaeval.sweeps.folder_lock.FolderInUse`)."""
    with store.lock("report"):
        results = results_frame(store)
        temporal = temporal_frame(store, results)
        write_parquet(results, store.writable("results.parquet"))
        write_parquet(temporal, store.writable("temporal.parquet"))
    return results
