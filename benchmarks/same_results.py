"""Do two sweep folders hold the same numbers? A check for changes that claim to change no
result (speed work): run one config with the old code and the new, then

    python benchmarks/same_results.py OLD_DIR NEW_DIR [--rtol 1e-6]

Rows are matched by what a cell is (group, scene, difficulty, spec, frame), not by key (the
key holds the code version). Every number of ``results.parquet`` and ``temporal.parquet``
except times, hosts and processes is compared; a seeded Monte Carlo render (Mitsuba, jitter)
with the same seed gives the same image, so its rows are held to the same tolerance. Prints
the largest relative difference per column and exits 1 when one is above ``--rtol`` or a row
is missing on either side.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

IDENTITY = ["group", "scene", "difficulty", "spec", "frame"]
# what differs between two runs of the same cell without being a result
NOT_RESULTS = {"key", "reference_key", "code_version", "finished_at", "host", "pid", "executor", "workers",
               "render_s", "render_s_min", "render_s_max", "ms_per_mpix", "traceback"}


def compare(old: pd.DataFrame, new: pd.DataFrame, identity: list[str], rtol: float) -> list[str]:
    """Lines naming each column's largest relative difference; a line starting with 'FAIL'
    for a column above ``rtol`` or rows present on one side only."""
    lines = []
    old, new = old.set_index(identity).sort_index(), new.set_index(identity).sort_index()
    only = old.index.symmetric_difference(new.index)
    if len(only):
        lines.append(f"FAIL {len(only)} rows on one side only, e.g. {list(only[:3])}")
    both = old.index.intersection(new.index)
    old, new = old.loc[both], new.loc[both]
    for column in old.columns:
        if column in NOT_RESULTS or column not in new.columns:
            continue
        a, b = old[column], new[column]
        if pd.api.types.is_numeric_dtype(a) and pd.api.types.is_numeric_dtype(b):
            x, y = a.to_numpy(float), b.to_numpy(float)
            same_nan = np.isnan(x) == np.isnan(y)
            scale = np.maximum(np.abs(x), np.abs(y))
            diff = np.where(np.isnan(x) | np.isnan(y) | (x == y), 0.0, np.abs(x - y) / np.where(scale > 0, scale, 1))
            worst = float(diff.max()) if len(diff) else 0.0
            bad = worst > rtol or not same_nan.all()
            lines.append(f"{'FAIL' if bad else 'ok  '} {column}: largest relative difference {worst:.2e}"
                         + ("" if same_nan.all() else f", NaN on one side in {int((~same_nan).sum())} rows"))
        else:
            differs = sum(_text(x) != _text(y) for x, y in zip(a, b))
            if differs:
                lines.append(f"FAIL {column}: {differs} rows differ")
    return lines


def _text(value) -> str | None:
    """A value as text to compare, None for a missing one (None, NaN)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return None
    return repr(value.tolist() if isinstance(value, np.ndarray) else value)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-6, help="largest relative difference taken as rounding")
    args = parser.parse_args(argv)
    failed = False
    for table, identity in (("results.parquet", IDENTITY), ("temporal.parquet", IDENTITY[:-1])):
        old, new = args.old / table, args.new / table
        if not old.exists() and not new.exists():
            continue
        print(f"{table}: {len(pd.read_parquet(old))} rows old, {len(pd.read_parquet(new))} new")
        for line in compare(pd.read_parquet(old), pd.read_parquet(new), identity, args.rtol):
            print("  " + line)
            failed |= line.startswith("FAIL")
    print("FAIL: the results differ" if failed else "same results (to the tolerance)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
