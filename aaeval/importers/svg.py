"""SVG files to scenes: ``aaeval import svg FILE.svg -o SCENE.toml``.

The file is read by :func:`aaeval.readlimits.read_bytes` and checked as XML first
(:mod:`aaeval.importers.svgdocument`: root ``<svg>``, a valid ``viewBox``, at most
:data:`~aaeval.importers.limits.MAX_ELEMENTS` elements once ``<use>`` is expanded, counted
without expanding). The root's size comes from :mod:`aaeval.importers.svgviewport`; the
tree is then walked as SVG 2 renders it (:mod:`aaeval.importers.svgwalk`), with

- the CSS cascade, colours and lengths of :mod:`aaeval.importers.svgstyle` (cssselect2,
  tinycss2) made into computed styles by :mod:`aaeval.importers.svgcomputed`;
- each shape's outline in user space from :mod:`aaeval.importers.svggeometry` (path
  data, shapes and transforms: :mod:`aaeval.importers.svgpath`), its fill rule resolved in
  float64 (:mod:`aaeval.importers.fill`);
- paints and ``paint-order`` from :mod:`aaeval.importers.svgpaint`, strokes (dashed,
  outlined in user space, then transformed) from :mod:`aaeval.importers.svgstroke`,
  markers from :mod:`aaeval.importers.svgmarkers`;
- nested viewports from :mod:`aaeval.importers.svgviewport` and ``clip-path`` from
  :mod:`aaeval.importers.svgclip`.

Each painted part is a layer in document order (later nearer). Colours are sRGB in the
file and linear in the scene.

What the scene format cannot hold is never dropped silently: text, images, gradient
and pattern paints, masks, filters, clip paths it cannot apply, CSS that cannot be
applied, and opacity (drawn opaque) are listed by element (:mod:`aaeval.importers.svgreport`)
in the result and in the scene's ``[svg].ignored``. So is every malformed element SVG does
not render (NaN or infinite numbers, negative sizes and radii), geometry beyond
:data:`~aaeval.importers.svggeometry.MAX_COORDINATE`, and ``<use>`` of anything outside the
file (nothing is fetched).
"""

from __future__ import annotations

import math
from pathlib import Path

from aaeval.importers.flatten import DEFAULT_TOLERANCE
from aaeval.importers.limits import MAX_ELEMENTS, ImportLimitError, VertexBudget, budget_scope, check_tolerance
from aaeval.importers.scene import ImportResult, Layer, scene_document
from aaeval.importers.svgdocument import SvgError, check_document
from aaeval.importers.svggeometry import MAX_COORDINATE
from aaeval.importers.svgpath import compose, viewbox_transform
from aaeval.importers.svgpath import scale as scaling
from aaeval.importers.svgviewport import root_viewport
from aaeval.importers.svgwalk import Walk

__all__ = ["import_svg"]


def import_svg(
    path: str | Path, *, tolerance: float = DEFAULT_TOLERANCE, scale: float = 1.0,
    background=(1.0, 1.0, 1.0), frames: int = 1, translate=(0.0, 0.0), file_ref: str | None = None,
) -> ImportResult:
    """Import an SVG file as a scene dictionary.

    Parameters
    ----------
    path : path of the SVG file.
    tolerance : float
        Flattening tolerance in scene pixels.
    scale : float
        Scene pixels per SVG pixel (the document's own size, viewBox applied).
    background : linear RGB of the scene's background (an SVG has none).
    frames, translate : the scene's animation.
    file_ref : str, optional
        How the scene's ``[svg].file`` names the SVG (default: ``path`` as given).
    """
    if not (math.isfinite(scale) and scale > 0):
        raise SvgError(f"scale must be a positive number, got {scale!r}")
    from aaeval.readlimits import read_bytes

    path = Path(path)
    data = read_bytes(path, what="SVG file")  # regular files of bounded size only
    ignored: list[str] = []
    root = check_document(data, path)  # root element, viewBox, element count after <use>
    try:
        walk = Walk(root, tolerance, ignored)
        width, height, box, aspect, root_style, lengths = root_viewport(root, walk.computed.tree_style(root))
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    if not (width > 0 and height > 0 and math.isfinite(width) and math.isfinite(height)):
        raise SvgError(f"{path}: the SVG has no positive width and height")
    if width * scale > MAX_COORDINATE or height * scale > MAX_COORDINATE:
        raise SvgError(f"{path}: the SVG is {width * scale:.3g}x{height * scale:.3g} px, beyond the limit of "
                       f"{MAX_COORDINATE:g} px")
    try:
        check_tolerance(tolerance, math.ceil(width * scale), math.ceil(height * scale))
    except ImportLimitError as exc:
        raise SvgError(f"{path}: {exc}") from None

    ctm = scaling(scale, scale)
    if box is not None:
        ctm = compose(ctm, viewbox_transform(box, aspect, width, height))
    layers: list[Layer] = []
    import sys

    depth = sys.getrecursionlimit()
    sys.setrecursionlimit(max(depth, 4 * MAX_ELEMENTS))  # a few frames per nesting level
    try:
        with budget_scope(VertexBudget()):
            if walk.root_drawn(root_style):
                walk.children(root, root_style, ctm, lengths, None, layers)
    except RecursionError:
        raise SvgError(f"{path}: elements are nested too deeply to import") from None
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    except ValueError as exc:  # limits, malformed values found on the way
        raise SvgError(f"{path}: {exc}") from None
    except Exception as exc:
        raise SvgError(f"{path}: could not import ({type(exc).__name__}: {exc})") from None
    finally:
        sys.setrecursionlimit(depth)

    source = {"file": file_ref if file_ref is not None else str(path), "scale": float(scale),
              "tolerance": float(tolerance), "ignored": ignored}
    document, cut = scene_document(
        math.ceil(width * scale - 1e-9), math.ceil(height * scale - 1e-9), background, layers,
        extension=("svg", source), frames=frames, translate=translate,
    )
    return ImportResult(document, ignored, cut)
