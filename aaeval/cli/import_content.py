"""Import real content as a scene: vector art from an SVG file, or text set in a
TrueType/OpenType font. Curves are flattened to --tolerance pixels; anything the scene
format cannot hold is listed by element, never dropped silently.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from aaeval.importers.flatten import DEFAULT_TOLERANCE

NAME = "import"
HELP = "turn an SVG file or a string of text into a scene file"


def add_arguments(p) -> None:
    kinds = p.add_subparsers(dest="kind", metavar="KIND", required=True)

    svg = kinds.add_parser("svg", help="an SVG file (paths, shapes, groups, transforms, fills, strokes)")
    svg.add_argument("svg", metavar="FILE.svg")
    svg.add_argument("--scale", type=float, default=1.0, help="scene pixels per SVG pixel (default 1)")
    svg.add_argument("--background", type=float, nargs=3, default=[1.0, 1.0, 1.0], metavar=("R", "G", "B"),
                     help="linear RGB background (default white)")
    svg.add_argument("--strict", action="store_true", help="refuse the file if anything would be ignored")
    _common(svg)
    svg.set_defaults(run=run_svg)

    text = kinds.add_parser("text", help="a line of text set in a font")
    text.add_argument("string", metavar="STRING")
    text.add_argument("--font", default=None, metavar="FONT.ttf",
                      help="TrueType/OpenType font file (default: DejaVu Sans, shipped with matplotlib)")
    text.add_argument("--size", type=float, nargs="+", default=[12.0], metavar="PX",
                      help="pixels per em; several sizes set one line each (default 12)")
    text.add_argument("--color", type=float, nargs=3, default=[0.0, 0.0, 0.0], metavar=("R", "G", "B"),
                      help="linear RGB of the text (default black)")
    text.add_argument("--background", type=float, nargs=3, default=[1.0, 1.0, 1.0], metavar=("R", "G", "B"),
                      help="linear RGB background (default white)")
    text.add_argument("--origin", type=float, nargs=2, default=None, metavar=("X", "Y"),
                      help="pen start of the first line (default: a small margin, one line down)")
    text.add_argument("--margin", type=float, default=2.0, help="pixels around the text (default 2)")
    _common(text)
    text.set_defaults(run=run_text)


def _common(p) -> None:
    p.add_argument("-o", "--output", required=True, metavar="SCENE.toml", help="scene file to write")
    p.add_argument("--mkdir", action="store_true",
                   help="create the output's folder if it does not exist (refused otherwise)")
    p.add_argument("--tolerance", type=float, default=DEFAULT_TOLERANCE, metavar="PX",
                   help=f"flattening tolerance in pixels (default {DEFAULT_TOLERANCE:g})")
    p.add_argument("--frames", type=int, default=1, help="animation frames (default 1)")
    p.add_argument("--translate", type=float, nargs=2, default=[0.0, 0.0], metavar=("DX", "DY"),
                   help="pixels per frame, e.g. 0.125 0 for text scrolling by 1/8 px (default 0 0)")


def _relative(target: Path, output: Path) -> str:
    """How the scene file names a source file: relative to its own folder."""
    return os.path.relpath(target.resolve(), output.resolve().parent)


def _report(output: Path, document: dict, ignored: list[str], cut: int) -> None:
    polygons = document["polygons"]
    holed = sum("holes" in p for p in polygons)
    image = document["image"]
    print(f"wrote {output} ({image['width']}x{image['height']}, {len(polygons)} polygons, {holed} with holes"
          + (f", {cut} shapes cut into triangles where their rings touch" if cut else "")
          + (f", {len(ignored)} ignored" if ignored else "") + ")")
    for item in ignored:
        print(f"  ignored {item}")


def _check_common(args) -> None:
    if not (math.isfinite(args.tolerance) and args.tolerance > 0):
        raise ValueError(f"--tolerance must be a positive number of pixels, got {args.tolerance}")
    folder = Path(args.output).parent
    if not folder.is_dir() and not args.mkdir:
        raise ValueError(f"{folder}: no such folder for -o {args.output}; create it or pass --mkdir")
    if args.frames < 1:
        raise ValueError(f"--frames must be >= 1, got {args.frames}")


def _check_options(args) -> None:
    """Every number option finite and in range, refused naming the option, and the output
    file writable, before anything is read or imported."""
    from aaeval.imageio import check_outputs

    def finite(name: str, values, low=None, high=None, rule: str = "") -> None:
        for v in values if isinstance(values, (list, tuple)) else [values]:
            if not math.isfinite(v) or (low is not None and v < low) or (high is not None and v > high):
                shown = " ".join(f"{x:g}" for x in values) if isinstance(values, (list, tuple)) else f"{values:g}"
                raise ValueError(f"{name} must be {rule or 'a finite number'}, got {shown}")

    finite("--translate", args.translate, -1e6, 1e6, "finite pixels per frame within +-1e6")
    finite("--background", args.background, 0.0, 1.0, "three linear RGB values in [0, 1]")
    if getattr(args, "scale", None) is not None:
        finite("--scale", args.scale, 1e-9, 1e6, "a positive finite number (scene pixels per SVG pixel, at most 1e6)")
        if args.scale <= 0:
            raise ValueError(f"--scale must be a positive finite number, got {args.scale:g}")
    if getattr(args, "color", None) is not None:
        finite("--color", args.color, 0.0, 1.0, "three linear RGB values in [0, 1]")
    if getattr(args, "size", None) is not None:
        finite("--size", args.size, 1e-3, 1e5, "pixels per em, finite, in [0.001, 1e5]")
    if getattr(args, "margin", None) is not None:
        # 2 x 8192 px of margin alone reaches the scene format's 2^28-pixel image limit
        finite("--margin", args.margin, 0.0, 8192.0, "a finite number of pixels in [0, 8192]")
    if getattr(args, "origin", None) is not None:
        finite("--origin", args.origin, -1e6, 1e6, "finite pixel coordinates within +-1e6")
    check_outputs({"-o": args.output})  # a folder that cannot be written is refused now, by the user's path


def run_svg(args) -> int:
    from aaeval.scenes.write import write_scene_document
    from aaeval.importers.svg import import_svg

    _check_common(args)
    _check_options(args)
    output = Path(args.output)
    result = import_svg(args.svg, tolerance=args.tolerance, scale=args.scale, background=args.background,
                        frames=args.frames, translate=args.translate,
                        file_ref=_relative(Path(args.svg), output))
    if args.strict and result.ignored:
        raise ValueError(f"{args.svg}: {len(result.ignored)} element(s) cannot be imported, first: {result.ignored[0]}")
    write_scene_document(result.document, output, comment=f"Imported from {args.svg} by 'aaeval import svg'.")
    _report(output, result.document, result.ignored, result.cut)
    return 0


def run_text(args) -> int:
    from aaeval.scenes.write import write_scene_document
    from aaeval.importers.text import import_text

    _check_common(args)
    _check_options(args)
    output = Path(args.output)
    font_ref = None if args.font is None or args.font.startswith("matplotlib:") else _relative(Path(args.font), output)
    result = import_text(args.string, font=args.font, sizes=args.size, color=args.color,
                         background=args.background, origin=args.origin, margin=args.margin,
                         tolerance=args.tolerance, frames=args.frames, translate=args.translate,
                         font_ref=font_ref)
    write_scene_document(result.document, output,
                         comment=f"Imported by 'aaeval import text' at {', '.join(f'{s:g}' for s in args.size)} px.")
    _report(output, result.document, result.ignored, result.cut)
    return 0
