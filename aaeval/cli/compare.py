"""Render SCENE with every --method and with the --reference on the frames asked, and print for
each method and frame every image metric against the reference (see 'aaeval metrics'), its
intensity sum and its render time (median of --repeats timed renders after an untimed warm-
up); then per method the mean of each metric and, over two or more frames, the temporal
metrics (intensity-sum variation beside the reference's, flicker, ...).

Output formats (--format): table (default; rich tables at most 100 columns wide,
metric columns split over several tables when they do not fit), csv (one row per
method and frame, every field), markdown (the per-frame and summary tables as pipe
tables) and json (the whole document). JSON is strict: a value that is not a finite
number (NaN, infinity: PSNR of identical images, a metric on an empty mask) is written as
the string "NaN", "Infinity" or "-Infinity" (aaeval.sweeps.typed_json).
Column titles and number formats come from the metric registry (aaeval metrics).
"""

from __future__ import annotations

import csv
import io
import sys
from pathlib import Path

FORMATS = ("table", "csv", "markdown", "json")
TABLE_WIDTH = 100

NAME = "compare"
HELP = "compare methods against a reference: image metrics, render times, temporal stability"
EPILOG = ('JSON output is strict: a value that is not a finite number is written as "NaN", "Infinity" '
          'or "-Infinity".')


def add_arguments(p) -> None:
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--method", "-m", action="append", required=True, metavar="SPEC", dest="methods",
                   help="method spec to compare; repeat for more methods")
    p.add_argument("--reference", "-r", required=True, metavar="SPEC",
                   help="method spec of the reference, e.g. catmull")
    p.add_argument("--frames", default="1", metavar="N|all",
                   help="the first N frames of the animation, or 'all' (default 1)")
    p.add_argument("--metric", action="append", metavar="NAME", dest="metrics",
                   help="image metric to compute; repeat for more (default: every one that applies to the scene)")
    p.add_argument("--temporal", action="append", metavar="NAME",
                   help="temporal metric to compute over the frames; repeat for more (default: every one)")
    p.add_argument("--repeats", type=int, default=1, metavar="N",
                   help="timed renders per method and frame; the median is reported (default 1)")
    p.add_argument("--format", "-f", choices=FORMATS, default="table",
                   help="output on stdout: table (default, fits 100 columns), csv, markdown or json")
    p.add_argument("--json", metavar="OUT.json", help="also write the whole document as JSON to this file")
    p.add_argument("--quiet", "-q", action="store_true",
                   help="no progress bar; with --format table, no per-frame table: only the per-method summary")


def run(args) -> int:
    from aaeval.sweeps.compare import plan_comparison, run_comparison
    from aaeval.sweeps.typed_json import dumps
    from aaeval.imageio import atomic_write

    from aaeval.imageio import check_outputs

    if args.json and Path(args.json).is_dir():
        raise ValueError(f"--json {args.json} is a directory; give a file name")
    check_outputs({"--json": args.json})  # a folder that cannot be written is refused before rendering
    plan = plan_comparison(args.scene, args.methods, args.reference, args.frames, metrics=args.metrics,
                           temporal=args.temporal, repeats=args.repeats)
    quiet = args.quiet or not sys.stderr.isatty()
    document = run_comparison(plan) if quiet else _run_with_progress(plan, run_comparison)
    if args.format == "json":
        sys.stdout.write(dumps(document, indent=2) + "\n")
    elif args.format == "csv":
        sys.stdout.write(to_csv(document))
    elif args.format == "markdown":
        sys.stdout.write(to_markdown(document))
    else:
        print_tables(document, per_frame=not args.quiet)
    if args.json:
        text = dumps(document, indent=2) + "\n"
        atomic_write(args.json, lambda tmp: Path(tmp).write_text(text))
        if not args.quiet:
            print(f"wrote {args.json}", file=sys.stderr)
    return _report_failures(document)


def _report_failures(document: dict) -> int:
    """One line on stderr per method that failed on some frame; 1 when any did (the table
    still shows every row, the failed ones with their reason)."""
    failed = [row for row in document["rows"] if row.get("error")]
    for row in failed:
        print(f"aaeval compare: {row['method']} failed on frame {row['frame']}: {row['error']}", file=sys.stderr)
    return 1 if failed else 0


def _run_with_progress(plan, run_comparison) -> dict:
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, transient=True, console=Console(stderr=True)) as progress:
        task = progress.add_task("rendering", total=plan.renders)

        def advance(spec: str, frame: int) -> None:
            progress.update(task, advance=1, description=f"rendered {spec} frame {frame}")

        return run_comparison(plan, on_render=advance)


# --- the tables, as rows of strings ---------------------------------------------------

def _ms(seconds) -> str:
    from aaeval.metrics import format_value

    return format_value(None if seconds is None else seconds * 1e3, ".3g")


def frame_table(document: dict) -> tuple[list[str], list[list[str]], int]:
    """Titles and cells of the per-frame table; the first ``n`` columns identify the row."""
    from aaeval.metrics import METRICS, format_value

    metrics = document["metrics"]
    titles = ["method", "frame", *(METRICS[m].title for m in metrics), "intensity sum", "ms", "error"]
    rows = []
    for row in document["rows"]:
        rows.append([row["method"], str(row["frame"]), *(METRICS[m].format(row[m]) for m in metrics),
                     format_value(row["intensity_sum"], ".6g"), _ms(row["render_s"]), row["error"] or ""])
    return titles, rows, 2


def summary_table(document: dict) -> tuple[list[str], list[list[str]], int]:
    """Titles and cells of the per-method summary (means, temporal metrics, median time)."""
    from aaeval.metrics import METRICS, format_value

    metrics, temporal = document["metrics"], document["temporal"]
    titles = ["method", *(METRICS[m].title for m in metrics), *(METRICS[m].title for m in temporal), "median ms"]
    ref = document["reference_summary"]
    rows = [[f"{ref['method']} (reference)", *("" for _ in metrics),
             *(format_value(ref["sum_variation"], METRICS["sum_variation"].fmt) if m == "sum_variation" else ""
               for m in temporal), _ms(ref["render_s_median"])]]
    for entry in document["summary"]:
        rows.append([entry["method"], *(METRICS[m].format(entry["mean"][m]) for m in metrics),
                     *(METRICS[m].format(entry["temporal"][m]) for m in temporal), _ms(entry["render_s_median"])])
    return titles, rows, 1


def _chunks(titles: list[str], rows: list[list[str]], keys: int, width: int) -> list[list[int]]:
    """Column indices of tables at most ``width`` wide: the key columns, then what fits."""

    def col_width(j):
        return max([len(titles[j]), *(len(r[j]) for r in rows)])

    overhead = 2  # a space either side of each column (rich, box=None, padding (0, 1))
    base = sum(col_width(j) + overhead for j in range(keys))
    chunks, current, used = [], [], base
    for j in range(keys, len(titles)):
        if not any(r[j] for r in rows):  # a column with nothing in it (no errors): left out
            continue
        w = col_width(j) + overhead
        if current and used + w > width:
            chunks.append(current)
            current, used = [], base
        current.append(j)
        used += w
    if current or not chunks:
        chunks.append(current)
    return [list(range(keys)) + c for c in chunks]


def print_tables(document: dict, *, per_frame: bool = True, file=None) -> None:
    """The per-frame table (unless not ``per_frame``) and the summary, at most 100 columns wide."""
    from rich.console import Console
    from rich.table import Table

    console = Console(file=file or sys.stdout, width=TABLE_WIDTH, soft_wrap=False, highlight=False)
    frames = len(document["frames"])
    parts = []
    if per_frame:
        parts.append((f"{document['scene']} against {document['reference']}", *frame_table(document)))
    parts.append((f"over {frames} frame{'s' if frames != 1 else ''}: mean metrics, temporal metrics, median time",
                  *summary_table(document)))
    for title, titles, rows, keys in parts:
        for cols in _chunks(titles, rows, keys, TABLE_WIDTH - 2):
            table = Table(title=title, box=None, padding=(0, 1), title_justify="left")
            for j in cols:
                table.add_column(titles[j], justify="left" if j < keys else "right", no_wrap=True,
                                 overflow="fold" if j == 0 else "ellipsis")
            for row in rows:
                table.add_row(*(row[j] for j in cols))
            console.print(table)


def to_csv(document: dict) -> str:
    """One row per method and frame: every metric, the intensity sum, timings and errors."""
    fields = ["method", "frame", *document["metrics"], "intensity_sum", "render_s", "render_s_min",
              "render_s_max", "repeats", "megapixels", "ms_per_mpix", "error"]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(fields)
    for row in document["rows"]:
        writer.writerow(["" if row[f] is None else row[f] for f in fields])
    return out.getvalue()


def to_markdown(document: dict) -> str:
    """The per-frame table and the summary as Markdown pipe tables."""

    def pipe(titles, rows):
        esc = [[c.replace("|", "\\|") for c in r] for r in [titles, *rows]]
        lines = ["| " + " | ".join(esc[0]) + " |", "|" + "|".join("---" for _ in titles) + "|"]
        lines += ["| " + " | ".join(r) + " |" for r in esc[1:]]
        return "\n".join(lines)

    frames = len(document["frames"])
    parts = [f"**{document['scene']}** against **{document['reference']}**", "",
             pipe(*frame_table(document)[:2]), "",
             f"Over {frames} frame{'s' if frames != 1 else ''}:", "", pipe(*summary_table(document)[:2]), ""]
    return "\n".join(parts)
