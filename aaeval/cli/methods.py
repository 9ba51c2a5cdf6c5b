"""List every registered rendering method with its options and defaults.
"""

from __future__ import annotations

NAME = "methods"
HELP = "list rendering methods and their options"


def run(args) -> int:
    from aaeval.renderers import METHODS  # filled by main's aaeval.registries.load()

    for name in sorted(METHODS):
        m = METHODS[name]
        print(f"{name}{'  [exact]' if m.exact else ''}: {m.summary}")
        for key, opt in sorted(m.options.items()):
            choices = f" one of {list(opt.choices)}" if opt.choices else ""
            print(f"    {key}={opt.default!r} ({opt.type.__name__}{choices}) {opt.doc}")
    return 0
