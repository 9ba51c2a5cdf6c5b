"""The specular study's section of the default report (written by the specular study;
this placeholder keeps the report's call in place until it lands)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["specular_section"]


def specular_section(out_dir: Path, figures_dir: Path) -> str:
    """HTML fragment of the specular study for the report of the sweep in ``out_dir``."""
    return ""
