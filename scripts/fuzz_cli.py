"""Fuzz the command line offline: N hypothesis cases, every one judged, counts printed.

Usage: ``PYTHONPATH=. python3 scripts/fuzz_cli.py [--cases 10000] [--bound 30] [--max-vertices 2000]``

The generators and the rule are those of the CI test (tests/helpers/fuzzing.py): each case must end
in an image or a one-line refusal with exit 2, never a traceback, another exit code or a
run over ``--bound`` seconds, and change no file outside its folder (the targets of the
links it plants: ``outside-changed``). The watchdog also samples this process's resident
memory: a case during which it passed ``--max-rss`` (default 2 GiB) counts as ``memory``.
Cases run with a fresh empty folder as the working directory and ``AAEVAL_CACHE_DIR`` inside
the fuzz folder; at the end any file that appeared or changed in that working directory
is listed (with the per-case check of link targets, the "files changed outside the temp
folder" count). Cases run in this process (``aaeval.cli.main``), after one
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

from tests.helpers.fuzzing import cli_case, fuzz_environment, run_case, warm_up  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10000)
    parser.add_argument("--bound", type=float, default=30.0, help="seconds per case")
    parser.add_argument("--max-vertices", type=int, default=2000)
    parser.add_argument("--failures", default="fuzz-failures", help="folder for failing cases")
    parser.add_argument("--max-rss", type=float, default=2.0, help="GiB of resident memory a case may reach")
    args = parser.parse_args()
    os.environ.update(fuzz_environment())
    work = Path(tempfile.mkdtemp(prefix="aaeval-fuzz-"))
    sandbox = Path(tempfile.mkdtemp(prefix="aaeval-fuzz-cwd-"))
    os.environ["AAEVAL_CACHE_DIR"] = str(work / "cache-dir")
    failures = Path(args.failures).resolve()
    os.chdir(sandbox)
    before = _tree_state(sandbox, work)
    warm_up(work)
    counts: collections.Counter = collections.Counter()
    slowest: list[tuple[float, str]] = []
    state = {"started": None, "case": None, "peak": 0}

    def watchdog() -> None:
        while True:
            time.sleep(0.05)
            state["peak"] = max(state["peak"], _rss())
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
        state["case"], state["started"], state["peak"] = case, time.monotonic(), _rss()
        outcome = run_case(case, work / "case", args.bound)
        state["started"] = None
        peak = max(state["peak"], _rss())
        counts["max rss MiB"] = max(counts["max rss MiB"], peak >> 20)
        if outcome.ok and peak > args.max_rss * 2**30:
            outcome.verdict = "memory"
            outcome.stderr += f" (resident memory reached {peak / 2**30:.2f} GiB)"
        counts[outcome.verdict] += 1
        counts[f"kind {case.kind}: {outcome.verdict}"] += 1
        slowest.append((outcome.seconds, " ".join(case.args[2:])))
        slowest.sort(reverse=True)
        del slowest[5:]
        if not outcome.ok:
            n = sum(counts[v] for v in VERDICTS[2:])
            folder = failures / f"{n:04d}-{outcome.verdict}"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "scene.toml").write_bytes(case.scene)
            (folder / "case.json").write_text(json.dumps({"args": case.args, "kind": case.kind,
                                                          "code": outcome.code, "stderr": outcome.stderr}, indent=1))
        done = sum(counts[v] for v in VERDICTS)
        if done % 500 == 0:
            print(f"{done} cases, {time.monotonic() - begin:.0f} s: "
                  + ", ".join(f"{v} {counts[v]}" for v in VERDICTS) + f", max rss {counts['max rss MiB']} MiB",
                  flush=True)

    one()
    total = sum(counts[v] for v in VERDICTS)
    print(f"\n{total} cases in {time.monotonic() - begin:.0f} s (bound {args.bound:g} s per case)")
    for key, value in sorted(counts.items()):
        print(f"  {key:40s} {value}")
    print("slowest cases:")
    for seconds, what in slowest:
        print(f"  {seconds:7.2f} s  {what}")
    after = _tree_state(sandbox, work)
    changed = sorted(p for p in set(before) | set(after) if before.get(p) != after.get(p)
                     and not p.startswith(str(failures)))
    print(f"files changed outside the fuzz folder: {len(changed)}")
    for p in changed[:20]:
        print(f"  {p}")
    bad = total - counts["image"] - counts["refused"]
    print(f"failures: {bad}" + (f" (cases in {failures}/)" if bad else ""))
    return 1 if bad or changed else 0


VERDICTS = ("image", "refused", "traceback", "bad-exit", "not-one-line", "hang", "bad-output", "outside-changed",
            "memory")


def _rss() -> int:
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return 0


def _tree_state(root: Path, skip: Path, depth: int | None = None) -> dict[str, tuple]:
    """``path -> (size, mtime)`` of the files under ``root`` (``depth`` levels), ``skip`` and
    caches left out."""
    state: dict[str, tuple] = {}
    root_depth = len(root.parts)
    for folder, dirs, files in os.walk(root):
        here = Path(folder)
        dirs[:] = [d for d in dirs if not d.startswith((".git", "__pycache__", ".pytest_cache", ".hypothesis"))
                   and here / d != skip and (depth is None or len(here.parts) - root_depth < depth)]
        for name in files:
            p = here / name
            try:
                st = p.lstat()
            except OSError:
                continue
            state[str(p)] = (st.st_size, st.st_mtime_ns)
    return state


if __name__ == "__main__":
    sys.exit(main())
