"""``aaeval render``: one frame of a scene with one method, to .npy, .exr or .png."""

from __future__ import annotations

import json
from pathlib import Path


def add_parser(sub) -> None:
    p = sub.add_parser(
        "render",
        help="render one frame of a scene with one method",
        description="Render SCENE with the method SPEC and write the image to OUT "
        "(.npy: float64 linear RGB HxWx3; .exr: float32 linear; .png: 8-bit sRGB for viewing).",
    )
    p.add_argument("scene", help="scene file (TOML, see the scene format in the README)")
    p.add_argument("--method", "-m", default="catmull", metavar="SPEC",
                   help="method spec, e.g. catmull, supersample:k=4, mitsuba:spp=4096 (default: catmull)")
    p.add_argument("--frame", type=int, default=0, metavar="K", help="animation frame, 0-based (default 0)")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="output image: .npy, .exr or .png")
    p.add_argument("--stats", metavar="STATS.json",
                   help="write timing as JSON; render_s is the render alone (no start-up, imports or JIT)")
    p.set_defaults(run=run)


def run(args) -> int:
    from aaeval.imageio import SUFFIXES, atomic_write, check_outputs, save_image
    from aaeval.renderers import render_timed, resolve
    from aaeval.scenes import load_scene

    out = Path(args.output)
    if out.suffix.lower() not in SUFFIXES:
        raise ValueError(f"{out}: unknown image suffix {out.suffix!r}; use one of {', '.join(SUFFIXES)}")
    check_outputs({"-o": out, "--stats": args.stats})  # before any work: a refusal costs nothing
    method, options = resolve(args.method)  # fail on a bad spec before any work
    scene = load_scene(args.scene)
    image, seconds = render_timed(scene, args.method, frame=args.frame)
    save_image(out, image)
    if args.stats:
        stats = {
            "scene": str(args.scene),
            "method": method.name,
            "options": options,
            "frame": args.frame,
            "width": scene.width,
            "height": scene.height,
            "render_s": seconds,
        }
        atomic_write(args.stats, lambda tmp: Path(tmp).write_text(json.dumps(stats, indent=2) + "\n"))
    print(f"wrote {out} ({scene.width}x{scene.height}, {method.name}, frame {args.frame}, {seconds * 1e3:.1f} ms)")
    return 0
