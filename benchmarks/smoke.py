"""``AAEVAL_BENCH_SMOKE=1``: every benchmark at its smallest (one repeat, tiny scenes).

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
