"""Installing a plugin the way an installer does, for the plugin tests."""

from __future__ import annotations

from pathlib import Path


def fake_install(site: Path, name: str, entry_points: dict[str, dict[str, str]]) -> None:
    """A dist-info folder for ``name`` with these entry points, as an installer writes it."""
    dist = site / f"{name.replace('-', '_')}-0.1.0.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.1.0\n")
    text = "".join(f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in points.items()) + "\n"
                   for group, points in entry_points.items())
    (dist / "entry_points.txt").write_text(text)
