"""The report of an SVG import: what was not imported, listed once, by element.

An element is named ``#id``, or ``tag[n]`` (the n-th drawn element of that tag, 0-based;
definitions such as clip-path contents are not counted). Each line is listed once, in
the order it was found; the list is the result's ``ignored`` and the scene's
``[svg].ignored``.
"""

from __future__ import annotations

__all__ = ["Report"]


class Report:
    """The lines of what an import did not import (appended to ``ignored``)."""

    def __init__(self, ignored: list[str]):
        self.ignored = ignored
        self.reported: set[str] = set()
        self.counts: dict[str, int] = {}

    def note(self, text: str) -> None:
        """List ``text`` unless it is listed already."""
        if text not in self.reported:
            self.reported.add(text)
            self.ignored.append(text)

    def name(self, el, tag: str) -> str:
        """The element's name in the report (each call counts one drawn element of ``tag``)."""
        n = self.counts.get(tag, 0)
        self.counts[tag] = n + 1
        return f"#{el.get('id')}" if el.get("id") else f"{tag}[{n}]"

