"""``aaeval compare``: methods against a reference on the frames of a scene, as a table and JSON."""

from __future__ import annotations

import json
import math
from pathlib import Path

# column title and format of each metric in the table (names as in IMAGE_METRICS)
_COLUMNS = {
    "rmse": ("RMSE", "{:.3e}"),
    "psnr": ("PSNR dB", "{:.2f}"),
    "ssim": ("SSIM", "{:.4f}"),
    "ciede2000_mean": ("ΔE00 mean", "{:.3f}"),
    "ciede2000_p95": ("ΔE00 p95", "{:.3f}"),
    "flip": ("FLIP", "{:.4f}"),
    "edge_rmse": ("edge RMSE", "{:.3e}"),
}


def add_parser(sub) -> None:
    p = sub.add_parser(
        "compare",
        help="compare methods against a reference: image metrics, render times, temporal stability",
        description="Render SCENE with every --method and with the --reference on the frames asked, "
        "and print for each method and frame the image metrics against the reference (RMSE, PSNR, "
        "SSIM, CIEDE2000 mean and 95th percentile, FLIP, RMSE over edge pixels), its intensity sum "
        "and its render time (JIT warm-up excluded); then per method the relative variation "
        "(max - min) / mean of its intensity sum over the frames, beside the reference's, and its "
        "flicker (RMS over pixels of the standard deviation across frames of its error).",
    )
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--method", "-m", action="append", required=True, metavar="SPEC", dest="methods",
                   help="method spec to compare; repeat for more methods")
    p.add_argument("--reference", "-r", required=True, metavar="SPEC",
                   help="method spec of the reference, e.g. catmull")
    p.add_argument("--frames", default="1", metavar="N|all",
                   help="the first N frames of the animation, or 'all' (default 1)")
    p.add_argument("--json", metavar="OUT.json", help="write the rows and the temporal summary as JSON")
    p.add_argument("--quiet", "-q", action="store_true",
                   help="no progress bar and no per-frame table: only the per-method summary")
    p.set_defaults(run=run)


def run(args) -> int:
    from rich.console import Console

    from aaeval.experiments.compare import plan_comparison, run_comparison
    from aaeval.imageio import atomic_write

    if args.json and Path(args.json).is_dir():
        raise ValueError(f"--json {args.json} is a directory; give a file name")
    plan = plan_comparison(args.scene, args.methods, args.reference, args.frames)
    console = Console()
    if not console.is_terminal:  # piped or logged: tables at their natural width, never elided
        console = Console(width=10_000)
    if args.quiet:
        document = run_comparison(plan)
    else:
        document = _run_with_progress(plan, run_comparison)
        console.print(_rows_table(document))
    console.print(_summary_table(document))
    if args.json:
        text = json.dumps(document, indent=2) + "\n"
        atomic_write(args.json, lambda tmp: Path(tmp).write_text(text))
        if not args.quiet:
            console.print(f"wrote {args.json}")
    return 0


def _run_with_progress(plan, run_comparison) -> dict:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, transient=True) as progress:
        task = progress.add_task("rendering", total=plan.renders)

        def advance(spec: str, frame: int) -> None:
            progress.update(task, advance=1, description=f"rendered {spec} frame {frame}")

        return run_comparison(plan, on_render=advance)


def _number(value: float, fmt: str) -> str:
    if math.isnan(value):
        return "n/a"
    if math.isinf(value):
        return "∞" if value > 0 else "-∞"
    return fmt.format(value)


def _rows_table(document: dict):
    from rich.table import Table

    table = Table(title=f"{document['scene']} against {document['reference']}")
    for title in ("method", "frame", *(_COLUMNS[m][0] for m in document["metrics"]), "intensity sum", "render ms"):
        table.add_column(title, justify="left" if title == "method" else "right", overflow="fold")
    for row in document["rows"]:
        cells = [_number(row[m], _COLUMNS[m][1]) for m in document["metrics"]]
        table.add_row(row["method"], str(row["frame"]), *cells,
                      f"{row['intensity_sum']:.10g}", f"{row['render_s'] * 1e3:.2f}")
    return table


def _summary_table(document: dict):
    from rich.table import Table

    frames = len(document["frames"])
    metrics = document["metrics"]
    table = Table(title=f"over {frames} frame{'s' if frames != 1 else ''}: mean metrics, "
                  "intensity sum variation (max - min) / mean, flicker")
    titles = ("method", *(_COLUMNS[m][0] for m in metrics), "sum variation", "flicker", "median render ms")
    for title in titles:
        table.add_column(title, justify="left" if title == "method" else "right", overflow="fold")
    reference = document["reference_summary"]
    table.add_row(f"{reference['method']} (reference)", *("" for _ in metrics), f"{reference['sum_variation']:.3e}",
                  "", f"{reference['render_s_median'] * 1e3:.2f}")
    for entry in document["summary"]:
        cells = [_number(entry["mean"][m], _COLUMNS[m][1]) for m in metrics]
        table.add_row(entry["method"], *cells, f"{entry['sum_variation']:.3e}", f"{entry['flicker']:.3e}",
                      f"{entry['render_s_median'] * 1e3:.2f}")
    return table
