"""Render SCENE with the method SPEC and write the image to OUT (.npy: float64 linear RGB
HxWx3; .exr: float32 linear; .png: 8-bit sRGB for viewing). OUT's folder must exist unless
--mkdir is given.
"""

from __future__ import annotations

from pathlib import Path

NAME = "render"
HELP = "render one frame of a scene with one method"


def add_arguments(p) -> None:
    p.add_argument("scene", help="scene file (TOML, see the scene format in the README)")
    p.add_argument("--method", "-m", default="catmull", metavar="SPEC",
                   help="method spec, e.g. catmull, supersample:k=4, mitsuba:spp=4096 (default: catmull)")
    p.add_argument("--frame", type=int, default=0, metavar="K", help="animation frame, 0-based (default 0)")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="output image: .npy, .exr or .png")
    p.add_argument("--mkdir", action="store_true", help="create OUT's folder if it does not exist (refused otherwise)")
    p.add_argument("--scale", type=int, default=1, metavar="N",
                   help="PNG only: enlarge every pixel to an N x N block (nearest neighbour), for viewing (default 1)")
    p.add_argument("--stats", metavar="STATS.json",
                   help="write timing as JSON; render_s is the render alone (no start-up, imports or JIT)")


def run(args) -> int:
    from aaeval.sweeps.typed_json import dumps
    from aaeval.imageio import SUFFIXES, atomic_write, check_outputs, save_image
    from aaeval.renderers import MethodSpec, render_timed
    from aaeval.scenes import load_scene

    out = Path(args.output)
    if out.suffix.lower() not in SUFFIXES:
        raise ValueError(f"{out}: unknown image suffix {out.suffix!r}; use one of {', '.join(SUFFIXES)}")
    if args.scale < 1:
        raise ValueError(f"--scale must be a whole number >= 1, got {args.scale}")
    if args.scale > 1 and out.suffix.lower() != ".png":
        raise ValueError(f"--scale enlarges PNG files only (for viewing); {out.name} keeps the rendered pixels")
    for path in filter(None, (out, Path(args.stats) if args.stats else None)):
        if not path.parent.is_dir() and not args.mkdir:
            raise ValueError(f"{path.parent}: no such folder; create it or pass --mkdir")
    check_outputs({"-o": out, "--stats": args.stats})  # before any work: a refusal costs nothing
    spec = MethodSpec.parse(args.method)  # the spec enters here: a bad one fails before any work
    scene = load_scene(args.scene)
    _check_enlargement(scene, args.scale)
    # with --stats, render_s is the render alone: the spec itself is warmed up first (its kernels compiled)
    image, (seconds,) = render_timed(scene, spec, frame=args.frame, rehearse=bool(args.stats))
    save_image(out, _enlarged(image, args.scale))
    if args.stats:
        stats = {
            "scene": str(args.scene),
            "method": spec.name,
            "options": dict(spec.options),
            "frame": args.frame,
            "width": scene.width,
            "height": scene.height,
            "render_s": seconds,
        }
        atomic_write(args.stats, lambda tmp: Path(tmp).write_text(dumps(stats, indent=2) + "\n"))
    size = f"{scene.width}x{scene.height}" + (f" shown {args.scale}x" if args.scale > 1 else "")
    print(f"wrote {out} ({size}, {spec.name}, frame {args.frame}, {seconds * 1e3:.1f} ms)")
    return 0


def _check_enlargement(scene, scale: int) -> None:
    from aaeval.limits import available_memory

    # the enlarged float64 image and its 8-bit copy, on top of the render itself
    need = scene.width * scene.height * scale * scale * 3 * (8 + 1)
    have = available_memory()
    if scale > 1 and need > have:
        raise ValueError(f"--scale {scale}: a {scene.width * scale}x{scene.height * scale} PNG needs about "
                         f"{need / 2**30:.3g} GiB of memory, {have / 2**30:.3g} GiB available")


def _enlarged(image, scale: int):
    """Each pixel repeated into a ``scale`` x ``scale`` block (nearest neighbour)."""
    return image if scale == 1 else image.repeat(scale, axis=0).repeat(scale, axis=1)
