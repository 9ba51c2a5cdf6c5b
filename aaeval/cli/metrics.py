"""List every registered metric (aaeval.metrics.METRICS) with its kind (image: one frame;
temporal: every frame of an animation), whether higher or lower is better, what it needs
(reference, scene, frames, a mask) and its table title. The names are what experiment
configs and 'compare --metric' take.
"""

from __future__ import annotations

NAME = "metrics"
HELP = "list metrics: kind, direction, what each needs"


def run(args) -> int:
    from aaeval.metrics import MASKS, METRICS

    for kind in ("image", "temporal"):
        print(f"{kind} metrics:")
        for name, m in METRICS.items():
            if m.kind != kind:
                continue
            needs = ", ".join(m.needs) + (f", mask {m.mask}" if m.mask else "")
            print(f"  {name}: {m.summary}")
            print(f"      title {m.title!r}, format {m.fmt}, {m.direction}; needs {needs}")
            if m.unavailable():
                print(f"      unavailable here: {m.unavailable()}")
    print("masks:")
    for name, mask in MASKS.items():
        print(f"  {name}: {mask.summary}")
    return 0
