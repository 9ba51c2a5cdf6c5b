"""The tidy results tables, rebuilt from the cell files at any time.

``results.parquet``: one row per cell of the manifest that has finished, read through
:class:`~aaeval.experiments.record.CellRecord` (one column per record field, ``options``
and ``metric_errors`` as JSON text, one column per metric of the experiment, and
``label``). A cell file that is not a readable record of this schema is an error naming
the file. The parquet file's metadata carries ``aaeval_schema_version``.

``temporal.parquet``: one row per (group, scene, spec) animation whose frames have all
finished: every temporal metric of the experiment over all its frames, recomputed from the
stored images by the measuring engine (:func:`aaeval.experiments.measure.series_metrics`),
and ``reference_sum_variation`` (the reference's own intensity-sum variation).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd

from aaeval.experiments.measure import SceneCache, series_metrics
from aaeval.metrics import relative_variation
from aaeval.experiments.record import (SCHEMA_VERSION, TABLE_FIELDS, CellRecord, RecordError, agreement_column,
                                       noise_column)
from aaeval.experiments.store import SweepStore
from aaeval.imageio import atomic_write

__all__ = ["results_frame", "temporal_frame", "write_results", "rebuild_results", "read_table", "short_label",
           "varying_options", "RESULTS_COLUMNS", "TEMPORAL_COLUMNS"]

#: Columns of ``results.parquet`` besides one per metric.
RESULTS_COLUMNS = (*TABLE_FIELDS, "label")
#: Columns of ``temporal.parquet`` besides one per temporal metric.
TEMPORAL_COLUMNS = ("group", "scene", "difficulty", "difficulty_label", "spec", "label", "method", "frames",
                    "reference", "reference_noise_rmse", "failed_frames", "reference_sum_variation", "metric_errors")
_SCHEMA_KEY = b"aaeval_schema_version"


def read_record(store: SweepStore, key: str) -> CellRecord:
    """The cell file ``key`` as a record (:class:`RecordError` naming the file if it is not one)."""
    return CellRecord.from_json(store.read_cell(key), where=str(store.cell_path(key)))


def results_frame(store: SweepStore, *, heal: bool = True) -> pd.DataFrame:
    """One row per finished cell of the manifest, in manifest order (``heal=False``: damaged
    cells are left where they are, for a reader that does not hold the folder's lock)."""
    manifest = store.read_manifest()
    metrics = list(manifest.get("metrics", []))
    done = set(store.check(heal=heal))
    out = []
    for row in manifest["cells"]:
        if row["key"] not in done:
            continue
        record = read_record(store, row["key"])
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
    frame["label"] = _labels(frame) if out else pd.Series(dtype=object)
    for col in ("render_s", "render_s_min", "render_s_max", "megapixels", "ms_per_mpix", "intensity_sum",
                "reference_noise_rmse", "reference_intensity_sum", "difficulty", "spp", "seed", "reference_spp",
                "reference_seed", *metrics, *tests):
        frame[col] = pd.to_numeric(frame[col], errors="coerce").astype(float)
    return frame


def short_label(spec: str, keep: set[str] = frozenset()) -> str:
    """The label of a spec (:meth:`aaeval.renderers.MethodSpec.label`): the options in
    ``keep`` and those that differ from the defaults. A stored spec enters here (parsed)."""
    from aaeval.renderers import MethodError, MethodSpec

    try:
        return MethodSpec.parse(spec).label(keep)
    except MethodError:  # a method this checkout lacks: show the spec as stored
        return spec


def varying_options(options_json) -> list[str]:
    """The option names whose values differ between these JSON option tables."""
    opts = [json.loads(o) for o in options_json]
    return sorted(k for k in set().union(*opts) if len({json.dumps(o.get(k)) for o in opts}) > 1)


def _labels(frame: pd.DataFrame) -> pd.Series:
    """The label of every row: the options that are not the default, and those that vary
    among the method's rows anywhere in the sweep. One label per spec, whichever table,
    figure, section or viewer shows it."""
    labels = pd.Series(index=frame.index, dtype=object)
    for _, rows in frame.groupby("method", sort=False):
        varying = set(varying_options(rows["options"]))
        for spec, idx in rows.groupby("spec", sort=False).groups.items():  # a stored spec, parsed once
            labels[idx] = short_label(spec, varying)
    return labels


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
               "method": first["method"], "frames": len(series), "reference": first["reference"],
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


def _write_parquet(frame: pd.DataFrame, path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_pandas(frame, preserve_index=False)
    meta = dict(table.schema.metadata or {})
    meta[_SCHEMA_KEY] = str(SCHEMA_VERSION).encode()
    table = table.replace_schema_metadata(meta)
    atomic_write(path, lambda tmp: pq.write_table(table, tmp))  # replaces a planted link, never follows it


def read_table(path: str | Path) -> pd.DataFrame:
    """Read ``results.parquet`` or ``temporal.parquet``, refusing another schema version."""
    import pyarrow.parquet as pq

    path = Path(path)
    meta = pq.read_schema(path).metadata or {}
    version = meta.get(_SCHEMA_KEY, b"").decode() or None
    if version != str(SCHEMA_VERSION):
        raise RecordError(f"{path}: results schema version {version}, this aaeval reads {SCHEMA_VERSION}; "
                          "rebuild it with 'aaeval report' or run the sweep again")
    return pd.read_parquet(path)


def write_results(store: SweepStore) -> pd.DataFrame:
    """Rebuild ``results.parquet`` and ``temporal.parquet`` from the cell files, holding the
    folder's lock (a sweep calling this already holds it; another process's running sweep
    is :class:`~aaeval.experiments.store.FolderInUse`)."""
    with store.lock("report"):
        results = results_frame(store)
        temporal = temporal_frame(store, results)
        _write_parquet(results, store.writable("results.parquet"))
        _write_parquet(temporal, store.writable("temporal.parquet"))
    return results


def rebuild_results(store: SweepStore) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Both tables, rebuilt from the cell files on disk (``results.parquet`` and
    ``temporal.parquet`` rewritten, :func:`write_results`) and returned.

    While a sweep writes the folder (it holds the lock) nothing of it is rewritten or
    moved: both tables are built in memory from the cells finished so far, and the sweep
    rewrites ``results.parquet`` when it ends."""
    with store.try_lock("report") as held:
        if held:
            results = write_results(store)
            return results, read_table(store.root / "temporal.parquet")
    owner = store.owner()
    store.log(f"{store.root} is being written by a running {owner.get('command', 'sweep')} (pid "
              f"{owner.get('pid', '?')}): reading the cells finished so far, leaving results.parquet to it")
    results = results_frame(store, heal=False)
    return results, temporal_frame(store, results)
