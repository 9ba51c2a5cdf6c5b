"""``AAEVAL_BENCH_SMOKE=1``: every benchmark at its smallest (one repeat, tiny scenes); and
the chart axes the benchmarks share.

The README's test runs each of its commands, benchmarks included, and a benchmark's real
sizes take minutes on a 2-core machine; with this set they take seconds. The numbers a
benchmark prints then mean nothing, and it says so on its first line.
"""

from __future__ import annotations

import argparse
import os

SMOKE = os.environ.get("AAEVAL_BENCH_SMOKE") == "1"


def smallest(args: argparse.Namespace, **values) -> argparse.Namespace:
    """``args`` with ``values`` put in when smoke-testing, unchanged otherwise."""
    if SMOKE:
        for name, value in values.items():
            setattr(args, name, value)
        print("AAEVAL_BENCH_SMOKE=1: smallest sizes, one repeat; these numbers mean nothing")
    return args


def time_against_size_axes(ax, *, xlabel: str, ylabel: str, title: str, legend_size: int) -> None:
    """The log-log axes of a benchmark's time-against-size chart, labelled, with a legend and
    both grids (every such chart reads alike)."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=legend_size)
    ax.grid(True, which="both", alpha=0.3)
