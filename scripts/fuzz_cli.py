"""Fuzz the command line offline: N hypothesis cases, every one judged, counts printed.

Usage: ``PYTHONPATH=. python3 scripts/fuzz_cli.py [--cases 10000] [--bound 30] [--max-vertices 2000]``

The generators and the rule are those of the CI test (tests/fuzzing.py): each case must end
in an image or a one-line refusal with exit 2, never a traceback, another exit code or a
run over ``--bound`` seconds. Cases run in this process (``aaeval.cli.main``), after one
untimed warm-up of every method; a watchdog thread ends the run with exit 3 if a case
outlives its bound three times over (a kernel that never returns to Python cannot be
interrupted by the alarm). Failing cases are written to ``--failures`` (scene file and
arguments) so they can be replayed. No shrinking: every generated case counts once.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import sys
import tempfile
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from hypothesis import HealthCheck, Phase, given, settings  # noqa: E402

from fuzzing import cli_case, fuzz_environment, run_case, warm_up  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10000)
    parser.add_argument("--bound", type=float, default=30.0, help="seconds per case")
    parser.add_argument("--max-vertices", type=int, default=2000)
    parser.add_argument("--failures", default="fuzz-failures", help="folder for failing cases")
    args = parser.parse_args()
    os.environ.update(fuzz_environment())
    work = Path(tempfile.mkdtemp(prefix="aaeval-fuzz-"))
    warm_up(work)
    counts: collections.Counter = collections.Counter()
    slowest: list[tuple[float, str]] = []
    failures = Path(args.failures)
    state = {"started": None, "case": None}

    def watchdog() -> None:
        while True:
            time.sleep(1.0)
            started = state["started"]
            if started is not None and time.monotonic() - started > 3 * args.bound:
                print(f"HANG (not interruptible): {state['case'].args}", flush=True)
                os._exit(3)

    threading.Thread(target=watchdog, daemon=True).start()
    begin = time.monotonic()

    @settings(max_examples=args.cases, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(case=cli_case(max_vertices=args.max_vertices))
    def one(case):
        state["case"], state["started"] = case, time.monotonic()
        outcome = run_case(case, work / "case", args.bound)
        state["started"] = None
        counts[outcome.verdict] += 1
        counts[f"kind {case.kind}: {outcome.verdict}"] += 1
        slowest.append((outcome.seconds, " ".join(case.args[2:])))
        slowest.sort(reverse=True)
        del slowest[5:]
        if not outcome.ok:
            n = sum(counts[v] for v in ("traceback", "bad-exit", "not-one-line", "hang", "bad-output"))
            folder = failures / f"{n:04d}-{outcome.verdict}"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "scene.toml").write_bytes(case.scene)
            (folder / "case.json").write_text(json.dumps({"args": case.args, "kind": case.kind,
                                                          "code": outcome.code, "stderr": outcome.stderr}, indent=1))
        done = sum(counts[v] for v in ("image", "refused", "traceback", "bad-exit", "not-one-line", "hang",
                                        "bad-output"))
        if done % 500 == 0:
            print(f"{done} cases, {time.monotonic() - begin:.0f} s: "
                  + ", ".join(f"{v} {counts[v]}" for v in ("image", "refused", "traceback", "bad-exit",
                                                           "not-one-line", "hang", "bad-output")), flush=True)

    one()
    total = sum(counts[v] for v in ("image", "refused", "traceback", "bad-exit", "not-one-line", "hang", "bad-output"))
    print(f"\n{total} cases in {time.monotonic() - begin:.0f} s (bound {args.bound:g} s per case)")
    for key, value in sorted(counts.items()):
        print(f"  {key:40s} {value}")
    print("slowest cases:")
    for seconds, what in slowest:
        print(f"  {seconds:7.2f} s  {what}")
    bad = total - counts["image"] - counts["refused"]
    print(f"failures: {bad}" + (f" (cases in {failures}/)" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
