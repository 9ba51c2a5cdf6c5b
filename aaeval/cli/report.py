"""Rebuild DIR/results.parquet from the cell files and write DIR/index.html with its figures
(PNG files beside it, each with its SVG and PDF for papers): speed against accuracy,
intensity sum per frame, flicker, stability as difficulty grows, an image grid with crops
and error maps, and the tables.
"""

from __future__ import annotations

NAME = "report"
HELP = "write DIR/index.html: charts and tables of a sweep's results"


def add_arguments(p) -> None:
    p.add_argument("dir", metavar="DIR", help="sweep folder written by 'aaeval sweep'")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bar")
    p.add_argument("--png-only", action="store_true",
                   help="a quicker draft: figures as PNG only, without their SVG and PDF twins")


def run(args) -> int:
    from pathlib import Path

    from aaeval.fileio import check_outputs
    from aaeval.report import write_report

    if Path(args.dir).is_dir():  # a folder the report cannot write into is refused before any work
        check_outputs({"DIR": args.dir}, folders=True)
        for name in ("figures", "tables", "viewer"):  # written into: must be the folder's own
            if (Path(args.dir) / name).is_symlink():
                raise ValueError(f"{Path(args.dir) / name} is a symbolic link; the report writes only inside "
                                 f"{args.dir} (remove the link)")
    index = write_report(args.dir, quiet=args.quiet, formats=("png",) if args.png_only else ("png", "svg", "pdf"))
    print(f"report: {index}")
    return 0
