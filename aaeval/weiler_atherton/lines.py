"""Hidden-line drawings from the visible polygons (Weiler & Atherton 1977, figure 11).

A visible piece's edge is drawn when it is part of its own polygon's outline or lies on
the line where its plane crosses another polygon's; the cuts made by clipping (between
visible pieces of one polygon, or along window borders) are not drawn.
"""

from __future__ import annotations

from xml.sax.saxutils import escape

from aaeval.scenes import Scene
from aaeval.weiler_atherton.hidden_surface import EDGE_CROSSING, EDGE_OWN, visible_pieces

__all__ = ["visible_edges", "hidden_line_svg"]


def visible_edges(
    scene: Scene, *, window: int = 0, convex: bool = True
) -> list[tuple[tuple[float, float], tuple[float, float], int]]:
    """Visible edge segments ``(p, q, source)``, each drawn once (``window`` and ``convex``
    as in :func:`~.hidden_surface.visible_pieces`)."""
    seen = set()
    out = []
    for piece in visible_pieces(scene, window=window, convex=convex):
        for ring, labels in zip(piece.shape.rings, piece.shape.labels):
            n = len(ring)
            for k in range(n):
                if labels[k] not in (EDGE_OWN, EDGE_CROSSING):
                    continue
                p, q = ring[k], ring[(k + 1) % n]
                key = (min(p, q), max(p, q))
                if key in seen:  # a crossing line bounds pieces on both sides
                    continue
                seen.add(key)
                out.append((p, q, piece.source))
    return out


def hidden_line_svg(scene: Scene, *, window: int = 0, stroke: float = 0.05) -> str:
    """An SVG drawing (image coordinates, one unit per pixel) of the visible edges."""
    w, h = scene.width, scene.height
    lines = [
        f'<line x1="{p[0]:.12g}" y1="{p[1]:.12g}" x2="{q[0]:.12g}" y2="{q[1]:.12g}"/>'
        for p, q, _ in visible_edges(scene, window=window)
    ]
    return "\n".join(
        [
            '<svg xmlns="http://www.w3.org/2000/svg" '
            f'width="{w * 8}" height="{h * 8}" viewBox="0 0 {w} {h}">',
            f"<title>{escape(scene.source)} frame {scene.frame}: visible edges (Weiler-Atherton)</title>",
            '<rect width="100%" height="100%" fill="white"/>',
            f'<g stroke="black" stroke-width="{stroke:g}" stroke-linecap="round">',
            *lines,
            "</g>",
            "</svg>",
            "",
        ]
    )
