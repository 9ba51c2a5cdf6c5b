"""The modules of the aaeval package by dotted name, for the tests that walk its imports."""

from __future__ import annotations

from pathlib import Path

import aaeval

ROOT = Path(aaeval.__file__).parent


def aaeval_modules() -> dict[str, Path]:
    """Every module and package of aaeval (a package named without ``__init__``) and its file."""
    out = {}
    for path in ROOT.rglob("*.py"):
        parts = ("aaeval",) + path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out
