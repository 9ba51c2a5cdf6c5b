"""Run (or resume) the sweep of the study folder DIR (its config.toml) into DIR/results, then
rewrite only the part of DIR/README.md between the study markers with the numbers that bear
on the paper's claim, read from the stored results (which numbers: DIR/study.toml). The
hand-written text around the markers is kept.
"""

from __future__ import annotations

NAME = "study"
HELP = "run a study (experiments/NAME) and regenerate the measured part of its README"


def add_arguments(p) -> None:
    p.add_argument("dir", metavar="DIR", help="study folder, e.g. experiments/catmull1978")
    p.add_argument("--no-run", action="store_true",
                   help="run nothing: regenerate the README from the results already in the folder")
    p.add_argument("--results", metavar="RESULTS", help="sweep folder (default DIR/results)")
    p.add_argument("--workers", "-j", type=int, metavar="N",
                   help="local worker processes (default: every core; 1 runs in this process)")
    p.add_argument("--cache", metavar="CACHE", help="reference cache folder (default $AAEVAL_CACHE_DIR or ~/.cache/aaeval)")
    p.add_argument("--print", action="store_true", dest="show", help="also print the generated section")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bars")


def run(args) -> int:
    import sys

    from aaeval.studies.run import IncompleteSweep, run_study
    from aaeval.studies.study import load_study
    from aaeval.imageio import check_outputs

    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    study = load_study(args.dir, results=args.results)
    check_outputs({"README": study.readme})
    if not args.no_run:
        check_outputs({"--results": study.results, "--cache": args.cache}, folders=True)
    try:
        section = run_study(study, run=not args.no_run, workers=args.workers, quiet=args.quiet, cache_dir=args.cache)
    except IncompleteSweep as exc:  # exit 1 as for 'aaeval sweep': a rerun finishes the cells
        print(f"aaeval study: {exc}", file=sys.stderr)
        return 1
    if args.show:
        print(section)
    print(f"study: {study.readme} (measured part regenerated from {study.results})")
    return 0
