"""Run every cell of the experiment CONFIG (TOML, see configs/sweeps/) and write one result
file per cell into DIR, then DIR/results.parquet. Finished cells are kept: a rerun (after a
crash, or with more cells in the config) runs only what is missing.
"""

from __future__ import annotations

import sys

NAME = "sweep"
HELP = "run an experiment sweep (scenes x methods x options x frames) into a folder"


def add_arguments(p) -> None:
    p.add_argument("config", help="experiment config (TOML)")
    p.add_argument("--out", "-o", required=True, metavar="DIR", help="results folder (created if missing)")
    p.add_argument("--dry-run", action="store_true", help="list the cells and which are already done; run nothing")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the cells on a Dask distributed cluster, e.g. tcp://HOST:8786")
    p.add_argument("--workers", "-j", type=int, metavar="N",
                   help="local worker processes (default: every core; 1 runs in this process)")
    p.add_argument("--retry-failed", action="store_true", help="run cells that finished with an error again")
    p.add_argument("--cache", metavar="DIR", help="reference cache folder (default $AAEVAL_CACHE_DIR or ~/.cache/aaeval)")
    p.add_argument("--force", action="store_true",
                   help="run into a folder that holds another experiment (its config moves to DIR/history/, "
                   "its cell files stay)")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bars; print only the summary line")


def run(args) -> int:
    from aaeval.sweeps import load_experiment, run_sweep

    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    if args.scheduler is not None and not args.scheduler.strip():  # not "run locally": a blank variable, likely
        raise ValueError("--scheduler: empty address; give one such as tcp://HOST:8786, or leave the option out "
                         "to run on local workers")
    from aaeval.imageio import check_outputs

    experiment = load_experiment(args.config)
    if args.dry_run:
        return dry_run(experiment, args.out)
    check_outputs({"--out": args.out, "--cache": args.cache}, folders=True)
    scheduler = None
    try:
        if args.scheduler:  # reached, with a worker, before the folder is touched (no empty sweep.lock)
            from aaeval.sweeps.dask_executor import connect

            scheduler = connect(args.scheduler)
        summary = run_sweep(experiment, args.out, workers=args.workers, scheduler=scheduler, quiet=args.quiet,
                            retry_failed=args.retry_failed, cache_dir=args.cache, force=args.force)
    except ConnectionError as exc:
        raise ValueError(str(exc)) from None
    finally:
        if scheduler is not None:
            from aaeval.sweeps.dask_executor import close_quietly

            close_quietly(scheduler)
    if summary.cluster_lost:  # the cluster's own reason (lost, not answering, no worker left), once
        print(f"aaeval sweep: {' '.join(summary.cluster_lost.split())} ({len(summary.lost)} cell(s) not run)",
              file=sys.stderr)
    print(f"{experiment.name}: {summary.total} cells, {summary.skipped} already done, {summary.ran} run "
          f"({summary.failed} failed), references {summary.references_rendered} rendered / "
          f"{summary.references_cached} from cache{', on ' + summary.executor if summary.executor else ''}; "
          f"results in {args.out}/results.parquet")
    for line in summary.lost:
        print(f"  not run (will be retried): {line}")
    print_errors(summary, args.out)
    if summary.lost:
        return NOT_RUN
    return CELLS_FAILED if summary.errors else 0


#: Exit codes of ``aaeval sweep`` beside 0 (done) and 2 (input error): cells left not run
#: (rerun to finish them), and every cell ran but some failed (their errors are recorded).
NOT_RUN, CELLS_FAILED = 1, 3


def print_errors(summary, out) -> None:
    """Each distinct error of the failed cells once, with its count and one cell that had it."""
    if not summary.errors:
        return
    cells = sum(len(v) for v in summary.errors.values())
    earlier = f", {summary.failed_before} kept from earlier runs (--retry-failed runs them again)" \
        if summary.failed_before else ""
    print(f"aaeval sweep: {cells} cell(s) failed{earlier}; the errors (full tracebacks in {out}/cells/):",
          file=sys.stderr)
    for error, where in sorted(summary.errors.items(), key=lambda item: -len(item[1])):
        print(f"  {len(where)} x {error}\n      e.g. {where[0]}", file=sys.stderr)


def dry_run(experiment, out) -> int:
    from aaeval.sweeps import SweepStore, plan
    planned = plan(experiment)
    done = set(SweepStore(out).check(heal=False))  # sound cells only; a dry run moves nothing
    rows: dict[tuple, list] = {}
    for p in planned:
        rows.setdefault((p.cell.group, p.cell.scene_source.name, p.cell.spec.label()), []).append(p.key in done)
    print(f"{experiment.name}: {len(planned)} cells in {len(experiment.groups)} groups, "
          f"{len({p.key for p in planned})} distinct, {len({p.key for p in planned} & done)} done "
          f"(reference: {', '.join(sorted({g.reference.label() for g in experiment.groups}))})")
    for line in plugin_lines(planned, SweepStore(out), done):
        print(line)
    width = max(len(f"{g}  {s}") for g, s, _ in rows) if rows else 0
    for (group, scene, spec), flags in rows.items():
        print(f"  {f'{group}  {scene}':<{width}}  {spec:<40} frames {sum(flags):3d}/{len(flags):<3d} done")
    return 0


def plugin_lines(planned, store, done: set[str]) -> list[str]:
    """What the dry run says of plugins: each plugin in the cells' keys, and the finished
    cells that rerun because the plugin behind them changed (another version or code)."""
    users: dict[tuple, int] = {}
    for p in planned:
        for plugin in p.manifest_row()["plugins"]:
            ident = (plugin["distribution"], plugin["version"], plugin["files"])
            users[ident] = users.get(ident, 0) + 1
    lines = [f"  plugin {name} {version} (code {files}): in the key of {n} cell(s)"
             for (name, version, files), n in users.items()]
    try:
        previous = store.read_manifest()["cells"]
    except (OSError, ValueError):  # no folder yet, or a damaged manifest: nothing to compare
        return lines
    where = lambda row: (row["group"], row["scene"], row["difficulty"], str(row["spec"]), row["frame"])  # noqa: E731
    before = {where(row): row for row in previous if isinstance(row, dict) and row.get("key") in done}
    changed: dict[str, int] = {}
    for p in planned:
        row = p.manifest_row()
        old = before.get(where(row))
        if p.key not in done and old is not None and old.get("plugins", []) != row["plugins"]:
            for was, now in _plugin_changes(old.get("plugins", []), row["plugins"]):
                changed[f"{was} -> {now}"] = changed.get(f"{was} -> {now}", 0) + 1
    lines += [f"  {n} finished cell(s) rerun: plugin changed, {change}" for change, n in changed.items()]
    return lines


def _plugin_changes(old: list[dict], new: list[dict]) -> list[tuple[str, str]]:
    def text(p):
        return f"{p['distribution']} {p['version']} (code {p['files']})"

    old_by, new_by = {p["distribution"]: p for p in old}, {p["distribution"]: p for p in new}
    return [(text(old_by[n]) if n in old_by else "none", text(new_by[n]) if n in new_by else "none")
            for n in sorted(set(old_by) | set(new_by)) if old_by.get(n) != new_by.get(n)]
