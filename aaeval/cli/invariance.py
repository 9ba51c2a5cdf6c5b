"""Render every frame of SCENE's animation with SPEC and print each frame's intensity sum and
the relative variation (max - min) / mean. Area sampling keeps the sum constant under
translation inside the frame; point sampling does not.
"""

from __future__ import annotations

NAME = "invariance"
HELP = "intensity sum of every frame of an animation, and its relative variation"


def add_arguments(p) -> None:
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--method", "-m", default="catmull", metavar="SPEC", help="method spec (default: catmull)")
    p.add_argument("--quiet", "-q", action="store_true", help="print only the variation")


def run(args) -> int:
    from aaeval.metrics import intensity_sum, relative_variation
    from aaeval.renderers import MethodSpec, render
    from aaeval.scenes import load_scene

    from aaeval.renderers.budget import check_frames

    spec = MethodSpec.parse(args.method)  # the spec enters here
    scene = load_scene(args.scene)
    # budgeted as a generator's frames, and the time of rendering every one of them
    check_frames(scene, scene.frames, "invariance renders every frame", specs=(spec,))
    sums = []
    for k in range(scene.frames):
        sums.append(intensity_sum(render(scene, spec, frame=k)))
        if not args.quiet:
            print(f"frame {k:4d}  sum {sums[-1]:.15g}")
    variation = relative_variation(sums)
    print(f"{args.scene}  {args.method}  frames {scene.frames}  relative variation {variation:.3e}")
    return 0
