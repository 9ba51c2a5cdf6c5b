"""SVG geometry in user space: path data, basic shapes, transforms and viewBox mapping.

Everything here is in the element's own user space; :mod:`aaeval.importers.svg` maps the
flattened outlines and stroke pieces through the current transformation matrix afterwards
(so a stroke is outlined in user space and then transformed, as SVG draws it).

Path data follows the SVG 2 grammar (``path-data`` in SVG 2, section 9.3.9): an error
stops the parse and the path is drawn up to the last complete segment (SVG 2's error
handling). ``S`` reflects only a cubic's second control point and ``T`` only a
quadratic's; anything else gives the current point. Arcs are converted to centre form by
the implementation notes (SVG 2, appendix B.2.4), radii scaled up when too small.
"""

from __future__ import annotations

import math
import re

import numpy as np

from aaeval.importers.stroke import Seg

__all__ = ["PathBuilder", "parse_path", "parse_transform", "parse_points", "viewbox_transform",
           "IDENTITY", "compose", "apply", "max_stretch", "rect_outline", "ellipse_outline"]

NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
WSP = re.compile(r"[ \t\r\n\f]*")
COMMA_WSP = re.compile(r"[ \t\r\n\f]*(?:,[ \t\r\n\f]*)?")
ARG_COUNTS = {"m": 2, "l": 2, "h": 1, "v": 1, "c": 6, "s": 4, "q": 4, "t": 2, "a": 7, "z": 0}

# an affine map as (a, b, c, d, e, f): x' = a x + c y + e, y' = b x + d y + f
IDENTITY = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)


def compose(m, n):
    """The map ``m`` after ``n`` (``n`` applied first)."""
    a, b, c, d, e, f = m
    a2, b2, c2, d2, e2, f2 = n
    return (a * a2 + c * b2, b * a2 + d * b2, a * c2 + c * d2, b * c2 + d * d2, a * e2 + c * f2 + e,
            b * e2 + d * f2 + f)


def apply(m, points: np.ndarray) -> np.ndarray:
    """Points (n, 2) through the map ``m``."""
    a, b, c, d, e, f = m
    x, y = points[:, 0], points[:, 1]
    return np.column_stack([a * x + c * y + e, b * x + d * y + f])


def max_stretch(m) -> float:
    """The largest factor by which ``m`` lengthens a vector (its largest singular value)."""
    return float(np.linalg.svd(np.array([[m[0], m[2]], [m[1], m[3]]]), compute_uv=False)[0])


def translate(x, y):
    return (1.0, 0.0, 0.0, 1.0, float(x), float(y))


def scale(sx, sy):
    return (float(sx), 0.0, 0.0, float(sy), 0.0, 0.0)


def rotate(degrees):
    r = math.radians(degrees)
    return (math.cos(r), math.sin(r), -math.sin(r), math.cos(r), 0.0, 0.0)


TRANSFORM = re.compile(r"\s*(matrix|translate|scale|rotate|skewX|skewY)\s*\(([^()]*)\)\s*,?", re.ASCII)


def parse_transform(text: str):
    """A transform list as one map, or None when it is not valid (SVG: no transform)."""
    text = text.strip()
    m = IDENTITY
    pos = 0
    while pos < len(text):
        match = TRANSFORM.match(text, pos)
        if not match:
            return None
        name, body = match.group(1), match.group(2)
        args = [float(v) for v in NUMBER.findall(body)]
        if re.sub(r"[\s,]+", " ", NUMBER.sub("0", body)).strip() != " ".join("0" * len(args)).strip():
            return None
        counts = {"matrix": (6,), "translate": (1, 2), "scale": (1, 2), "rotate": (1, 3), "skewX": (1,), "skewY": (1,)}
        if len(args) not in counts[name]:
            return None
        if name == "matrix":
            step = tuple(args)
        elif name == "translate":
            step = translate(args[0], args[1] if len(args) > 1 else 0.0)
        elif name == "scale":
            step = scale(args[0], args[1] if len(args) > 1 else args[0])
        elif name == "rotate":
            step = rotate(args[0])
            if len(args) == 3:
                step = compose(translate(args[1], args[2]), compose(step, translate(-args[1], -args[2])))
        elif name == "skewX":
            step = (1.0, 0.0, math.tan(math.radians(args[0])), 1.0, 0.0, 0.0)
        else:
            step = (1.0, math.tan(math.radians(args[0])), 0.0, 1.0, 0.0, 0.0)
        m = compose(m, step)
        pos = match.end()
    return m


def viewbox_transform(box, aspect: str, width: float, height: float):
    """The map from a viewBox (x, y, w, h) onto a viewport of ``width`` x ``height`` under
    ``preserveAspectRatio`` (SVG 2, 8.2: align and meet or slice)."""
    vx, vy, vw, vh = box
    sx, sy = width / vw, height / vh
    words = (aspect or "").split()
    if words and words[0] == "defer":
        words = words[1:]
    align = words[0] if words else "xMidYMid"
    mode = words[1] if len(words) > 1 else "meet"
    if align != "none":
        s = min(sx, sy) if mode != "slice" else max(sx, sy)
        sx = sy = s
    tx, ty = -vx * sx, -vy * sy
    if align != "none":
        if "xMid" in align:
            tx += (width - vw * sx) / 2
        elif "xMax" in align:
            tx += width - vw * sx
        if "YMid" in align:
            ty += (height - vh * sy) / 2
        elif "YMax" in align:
            ty += height - vh * sy
    return (sx, 0.0, 0.0, sy, tx, ty)


class PathBuilder:
    """Subpaths of true segments (:class:`~aaeval.importers.stroke.Seg`) in user space."""

    def __init__(self):
        self.subpaths: list[tuple[list[Seg], bool]] = []
        self.segs: list[Seg] = []
        self.start = None
        self.at = None
        self.pending = False  # a moveto with nothing drawn after it yet

    def move(self, x, y):
        self._finish(False)
        self.start = self.at = (float(x), float(y))
        self.pending = True

    def _begin(self):
        if self.at is None:
            raise ValueError("a path must start with a moveto")
        self.pending = False

    def line(self, x, y):
        self._begin()
        end = (float(x), float(y))
        self.segs.append(Seg("line", np.array([self.at, end], dtype=np.float64)))
        self.at = end

    def bezier(self, *points):
        self._begin()
        ctrl = np.array([self.at, *points], dtype=np.float64)
        self.segs.append(Seg("bezier", ctrl))
        self.at = tuple(map(float, points[-1]))

    def arc(self, rx, ry, angle, large, sweep, x, y):
        self._begin()
        end = (float(x), float(y))
        if end == self.at:
            return  # an arc to its own start point is omitted
        if rx == 0 or ry == 0:
            self.line(*end)
            return
        self.segs.append(Seg("arc", np.array([self.at, end], dtype=np.float64),
                             arc_centre(self.at, end, abs(rx), abs(ry), angle, large, sweep)))
        self.at = end

    def close(self):
        if self.at is None:
            return
        if self.segs or self.pending:
            if self.at != self.start:
                self.segs.append(Seg("line", np.array([self.at, self.start], dtype=np.float64)))
            elif not self.segs:  # "M x y Z": a subpath of zero length
                self.segs.append(Seg("line", np.array([self.start, self.start], dtype=np.float64)))
        self._finish(True)
        self.at = self.start

    def _finish(self, closed: bool):
        if self.segs:
            self.subpaths.append((self.segs, closed))
        self.segs = []
        self.pending = False

    def result(self) -> list[tuple[list[Seg], bool]]:
        self._finish(False)
        return self.subpaths


def arc_centre(p1, p2, rx, ry, angle, large, sweep):
    """Centre form (cx, cy, rx, ry, rotation, start, sweep) of an endpoint-form arc."""
    phi = math.radians(angle % 360.0)
    cos, sin = math.cos(phi), math.sin(phi)
    dx, dy = (p1[0] - p2[0]) / 2, (p1[1] - p2[1]) / 2
    x1, y1 = cos * dx + sin * dy, -sin * dx + cos * dy
    lam = (x1 / rx) ** 2 + (y1 / ry) ** 2
    if lam > 1:
        rx, ry = rx * math.sqrt(lam), ry * math.sqrt(lam)
    num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1
    den = rx * rx * y1 * y1 + ry * ry * x1 * x1
    coef = math.sqrt(max(0.0, num / den)) if den > 0 else 0.0
    if bool(large) == bool(sweep):
        coef = -coef
    cxp, cyp = coef * rx * y1 / ry, -coef * ry * x1 / rx
    cx = cos * cxp - sin * cyp + (p1[0] + p2[0]) / 2
    cy = sin * cxp + cos * cyp + (p1[1] + p2[1]) / 2
    ux, uy = (x1 - cxp) / rx, (y1 - cyp) / ry
    vx, vy = (-x1 - cxp) / rx, (-y1 - cyp) / ry
    start = math.atan2(uy, ux)
    delta = math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)
    if not sweep and delta > 0:
        delta -= 2 * math.pi
    elif sweep and delta < 0:
        delta += 2 * math.pi
    return (cx, cy, rx, ry, phi, start, delta)


class _Scanner:
    def __init__(self, text: str):
        self.text, self.pos = text, 0

    def skip(self, pattern=WSP):
        self.pos = pattern.match(self.text, self.pos).end()

    def done(self) -> bool:
        self.skip()
        return self.pos >= len(self.text)

    def number(self, first: bool) -> float:
        self.skip(WSP if first else COMMA_WSP)
        match = NUMBER.match(self.text, self.pos)
        if not match:
            raise ValueError(f"a number expected at character {self.pos}")
        self.pos = match.end()
        return float(match.group(0))

    def flag(self) -> bool:
        self.skip(COMMA_WSP)
        ch = self.text[self.pos:self.pos + 1]
        if ch not in ("0", "1"):
            raise ValueError(f"a flag (0 or 1) expected at character {self.pos}")
        self.pos += 1
        return ch == "1"


def parse_path(d: str):
    """Path data as subpaths of true segments; returns (subpaths, error or None). On an
    error the subpaths hold everything up to the last complete segment."""
    out = PathBuilder()
    scan = _Scanner(d)
    command = None
    last_cubic = last_quad = None  # the control points S and T may reflect
    try:
        while not scan.done():
            ch = scan.text[scan.pos]
            if ch.lower() in ARG_COUNTS:
                command = ch
                scan.pos += 1
                first = True
            elif command is None or command in "zZ":
                raise ValueError(f"a command expected at character {scan.pos}")
            else:
                first = False  # the previous command repeated
            if command is None or (out.at is None and command not in "mM"):
                raise ValueError("path data must start with a moveto")
            kind = command.lower()
            if kind == "z":
                out.close()
                last_cubic = last_quad = None
                continue
            args = []
            for k in range(ARG_COUNTS[kind]):
                args.append(scan.flag() if kind == "a" and k in (3, 4) else scan.number(first and k == 0))
            x0, y0 = out.at if out.at is not None else (0.0, 0.0)
            rel = command.islower()
            dx, dy = (x0, y0) if rel else (0.0, 0.0)

            def pt(i):
                return (args[i] + dx, args[i + 1] + dy)

            cubic = quad = None
            if kind == "m":
                out.move(*pt(0))
                command = "l" if rel else "L"  # further pairs are lines
            elif kind == "l":
                out.line(*pt(0))
            elif kind == "h":
                out.line(args[0] + dx, y0)
            elif kind == "v":
                out.line(x0, args[0] + dy)
            elif kind == "c":
                cubic = pt(2)
                out.bezier(pt(0), cubic, pt(4))
            elif kind == "s":
                c1 = (2 * x0 - last_cubic[0], 2 * y0 - last_cubic[1]) if last_cubic else (x0, y0)
                cubic = pt(0)
                out.bezier(c1, cubic, pt(2))
            elif kind == "q":
                quad = pt(0)
                out.bezier(quad, pt(2))
            elif kind == "t":
                quad = (2 * x0 - last_quad[0], 2 * y0 - last_quad[1]) if last_quad else (x0, y0)
                out.bezier(quad, pt(0))
            else:
                out.arc(args[0], args[1], args[2], args[3], args[4], *pt(5))
            last_cubic, last_quad = cubic, quad
    except ValueError as exc:
        return out.result(), str(exc)
    return out.result(), None


def parse_points(text: str):
    """A points list as (n, 2); an odd number drops the last coordinate (SVG: rendered up
    to the error), as does anything that is not a number. Returns (points, error or None)."""
    scan = _Scanner(text)
    values: list[float] = []
    error = None
    while not scan.done():
        try:
            values.append(scan.number(not values))
        except ValueError as exc:
            error = str(exc)
            break
    if len(values) % 2:
        error = error or "an odd number of coordinates"
        values.pop()
    return np.array(values, dtype=np.float64).reshape(-1, 2), error


def rect_outline(x, y, w, h, rx, ry):
    """The outline of a rectangle with corner radii (already clamped), from (x + rx, y)."""
    out = PathBuilder()
    out.move(x + rx, y)
    corners = rx > 0 and ry > 0
    for (lx, ly), (ex, ey) in [((x + w - rx, y), (x + w, y + ry)), ((x + w, y + h - ry), (x + w - rx, y + h)),
                               ((x + rx, y + h), (x, y + h - ry)), ((x, y + ry), (x + rx, y))]:
        if (lx, ly) != out.at:
            out.line(lx, ly)
        if corners:
            out.arc(rx, ry, 0, False, True, ex, ey)
    out.close()
    return out.result()


def ellipse_outline(cx, cy, rx, ry):
    """An ellipse as four arcs, from (cx + rx, cy) through (cx, cy + ry) (SVG 2, 10.4)."""
    out = PathBuilder()
    out.move(cx + rx, cy)
    for ex, ey in [(cx, cy + ry), (cx - rx, cy), (cx, cy - ry), (cx + rx, cy)]:
        out.arc(rx, ry, 0, False, True, ex, ey)
    out.close()
    return out.result()
