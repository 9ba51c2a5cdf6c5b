"""Solve the hidden surfaces of SCENE with Weiler & Atherton's polygon clipper and write the
visible parts of the polygon edges, and the lines where interpenetrating polygons cross, to
an SVG file.
"""

from __future__ import annotations

from pathlib import Path

NAME = "hidden-lines"
HELP = "draw the visible edges of a scene (Weiler-Atherton hidden-line removal) as SVG"


def add_arguments(p) -> None:
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--frame", type=int, default=0, metavar="K", help="animation frame, 0-based (default 0)")
    p.add_argument("--window", type=int, default=0, metavar="N",
                   help="screen subdivision: most polygons per window (default 0: none)")
    p.add_argument("--stroke", type=float, default=0.05, metavar="W", help="line width in pixels (default 0.05)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.svg", help="output SVG file")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")


def run(args) -> int:
    import math

    from aaeval.imageio import atomic_write, check_outputs
    from aaeval.scenes import load_scene
    from aaeval.weiler_atherton.lines import hidden_line_svg

    out = Path(args.output)
    if out.suffix.lower() != ".svg":
        raise ValueError(f"{out}: hidden-line drawings are written as .svg")
    if args.window < 0:
        raise ValueError(f"--window must be >= 0, got {args.window}")
    if not (math.isfinite(args.stroke) and args.stroke > 0):
        raise ValueError(f"--stroke must be a positive line width in pixels, got {args.stroke}")
    check_outputs({"-o": out})
    scene = load_scene(args.scene).at_frame(args.frame)
    # the same memory and time budget as the weiler-atherton method, before any work
    from aaeval.renderers.budget import check_budget
    from aaeval.renderers.spec import MethodSpec

    spec = MethodSpec.parse(f"weiler-atherton:window={args.window}")
    check_budget(scene, spec.method, spec.options)
    svg = hidden_line_svg(scene, window=args.window, stroke=args.stroke)
    atomic_write(out, lambda tmp: Path(tmp).write_text(svg))
    if not args.quiet:
        print(f"wrote {out} ({svg.count('<line ')} visible edge segments, frame {args.frame})")
    return 0
