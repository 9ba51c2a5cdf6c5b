"""Hostile-but-fair inputs for the command line, and the one rule every case must meet.

A case is a scene file (valid, mutated, or hostile: huge, tiny, NaN, duplicate, degenerate,
self-crossing, deep overlaps, binary, a billion frames) put in place as a file, a symbolic
link (to it, to ``/dev/zero``, dangling), a FIFO or a device, possibly with an SVG source
(valid, NaN coordinates, a ``<use>`` bomb, an entity bomb, a huge path, not XML, naming a
local image, or itself a FIFO or a link to ``/dev/zero``), and the arguments of ``aaeval
render``, ``hidden-lines``, ``invariance``, ``compare``, ``import svg``, or ``sweep`` into a
folder holding a damaged record (an unknown field) or planted links. It must end in an
image or output (exit 0, the file written and finite) or in a refusal (exit 2, the last
stderr line ``aaeval CMD: error: ...``, nothing written), never in a traceback, another exit
code, or a case over its time bound; and nothing outside the case's folder may change
(:func:`outside_digest` of the files links point at).

Used by tests/native/test_fuzz.py (a few hundred cases in CI) and scripts/fuzz_cli.py (offline).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from hypothesis import strategies as st

# Methods a case may ask for (mitsuba: its JIT start-up alone is seconds; covered elsewhere).
METHODS = ["catmull", "catmull-jagged", "point", "supersample", "jitter", "abuffer", "skia", "weiler-atherton",
           "freetype", "resvg"]
BAD_VALUES = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-320, 0, -1, 2**63, "x", True, [], {}, None]


# --- TOML, written here so that hostile values (nan, inf, odd types) can be written at all ---


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v == math.inf else "-inf" if v == -math.inf else repr(v))
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(x)}" for k, x in v.items() if x is not None) + "}"
    return '""'  # None and anything else: an empty string, a wrong type for every key


def toml_document(doc: dict) -> str:
    return "".join(f"{json.dumps(str(k))} = {toml_value(v)}\n" for k, v in doc.items() if v is not None)


# --- scenes -----------------------------------------------------------------------------

coord = st.floats(-20, 90, allow_nan=False, width=32).map(float)
unit = st.floats(0, 1, allow_nan=False)


@st.composite
def polygon(draw, sane=False):
    n = draw(st.integers(3, 8))
    kinds = ["convex", "tiny", "huge"] if sane else ["random", "convex", "tiny", "huge", "collinear", "duplicate",
                                                      "bowtie"]
    kind = draw(st.sampled_from(kinds))
    cx, cy, z = draw(coord), draw(coord), draw(st.floats(-5, 5))
    radius = {"tiny": 1e-9, "huge": 1e7}.get(kind, draw(st.floats(0.5, 40)))
    if kind == "random":
        xy = [[draw(coord), draw(coord)] for _ in range(n)]
    else:
        angles = sorted(draw(st.lists(st.floats(0, 2 * math.pi), min_size=n, max_size=n, unique=True)))
        xy = [[cx + radius * math.cos(a), cy + radius * math.sin(a)] for a in angles]
    if kind == "collinear":
        xy = [[cx + i, cy + 2 * i] for i in range(n)]
    if kind == "duplicate" and n > 3:
        xy[1] = list(xy[0])
    if kind == "bowtie":
        xy = [[cx, cy], [cx + radius, cy + radius], [cx + radius, cy], [cx, cy + radius]]
    return {"color": [draw(unit), draw(unit), draw(unit)], "vertices": [[x, y, z] for x, y in xy]}


@st.composite
def scene_document(draw, max_vertices=400, sane=False):
    doc = {"image": {"width": draw(st.integers(1, 48)), "height": draw(st.integers(1, 48))}}
    if draw(st.booleans()):
        doc["image"]["background"] = [draw(unit), draw(unit), draw(unit)]
    if draw(st.booleans()):
        doc["animation"] = {"frames": draw(st.integers(1, 6)),
                            "translate": [draw(st.floats(-3, 3)), draw(st.floats(-3, 3))]}
    shape = draw(st.sampled_from(["few", "few", "many-vertices", "deep-overlap", "none"]))
    if shape == "few":
        doc["polygons"] = draw(st.lists(polygon(sane), min_size=1, max_size=6))
    elif shape == "many-vertices":  # a star outline of many vertices: the sweep-line check
        n = draw(st.integers(50, max_vertices))
        r = [draw(st.floats(5, 20)) for _ in range(8)]
        doc["polygons"] = [{"color": [1.0, 0.5, 0.0], "vertices": [
            [24 + r[i % 8] * math.cos(2 * math.pi * i / n), 24 + r[i % 8] * math.sin(2 * math.pi * i / n), 1.0]
            for i in range(n)]}]
    elif shape == "deep-overlap":  # the same square many times, on one plane or tilted by 1e-12
        tilt = draw(st.sampled_from([0.0, 1e-12]))
        # tilted, neighbours tie within eps_z but the ends do not: catmull's move-to-front
        # went round in cycles up to MAX_STEPS per pixel (12 s for 120 squares at 41x41);
        # a cycle now ends after as many moves as the list has members (0.2 s), so CI takes
        # the whole range too
        k = draw(st.integers(20, 120))
        doc["polygons"] = [{"color": [i / k, 0.5, 0.5], "vertices": [[4, 4, 1 + i * tilt], [40, 5, 1], [39, 40, 1],
                                                                       [3, 41, 1]]} for i in range(k)]
    return doc


@st.composite
def mutated(draw, doc):
    """Replace, drop or add one value somewhere in the document."""
    doc = json.loads(json.dumps(doc))  # a deep copy (no nan yet)
    paths = []

    def walk(node, path):
        if isinstance(node, dict):
            for k, v in node.items():
                paths.append(path + [k])
                walk(v, path + [k])
        elif isinstance(node, list):
            for i, v in enumerate(node):
                paths.append(path + [i])
                walk(v, path + [i])

    walk(doc, [])
    if not paths:
        return doc
    path = draw(st.sampled_from(paths))
    parent = doc
    for step in path[:-1]:
        parent = parent[step]
    action = draw(st.sampled_from(["replace", "replace", "drop", "add-key"]))
    if action == "replace":
        parent[path[-1]] = draw(st.sampled_from(BAD_VALUES))
    elif action == "drop" and isinstance(parent, dict):
        del parent[path[-1]]
    elif action == "drop":
        parent.pop(path[-1])
    elif isinstance(parent, dict):
        parent["unexpected"] = 1
    return doc


# SVG sources of hostile kinds, for [svg].file (method resvg) and 'aaeval import svg'
SVG_HEAD = '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="24" height="24">'


def _use_bomb(levels: int) -> str:
    defs = ['<g id="l0"><rect width="1" height="1"/></g>']
    defs += [f'<g id="l{n}">' + f'<use href="#l{n - 1}"/>' * 5 + "</g>" for n in range(1, levels + 1)]
    return SVG_HEAD + "<defs>" + "".join(defs) + f'</defs><use href="#l{levels}"/></svg>'


def _entity_bomb() -> str:
    ents = "<!ENTITY a0 'aaaaaaaaaa'>" + "".join(f"<!ENTITY a{i + 1} '{('&a%d;' % i) * 10}'>" for i in range(8))
    return f"<?xml version='1.0'?><!DOCTYPE svg [{ents}]>" + SVG_HEAD + "<title>&a8;</title></svg>"


@st.composite
def svg_source(draw):
    """``(kind, text)`` of an SVG file."""
    kind = draw(st.sampled_from(["rect", "rect", "nan", "use-bomb", "entity-bomb", "huge-path", "not-xml", "empty",
                                 "image", "external-use", "viewbox", "huge-coords"]))
    if kind == "rect":
        x, y, w = draw(st.floats(0, 10)), draw(st.floats(0, 10)), draw(st.floats(0.5, 12))
        return kind, SVG_HEAD + f'<rect x="{x!r}" y="{y!r}" width="{w!r}" height="{w!r}"/></svg>'
    if kind == "nan":
        where = draw(st.sampled_from(['<path d="M1 1 L NaN 4 L 8 2 Z"/>', '<rect x="NaN" width="4" height="4"/>',
                                      '<circle cx="4" cy="4" r="inf"/>', '<rect width="4" height="4" stroke="#000" '
                                      'stroke-width="1e300"/>', '<rect width="-4" height="4"/>']))
        return kind, SVG_HEAD + where + "</svg>"
    if kind == "use-bomb":
        return kind, _use_bomb(draw(st.integers(4, 11)))
    if kind == "entity-bomb":
        return kind, _entity_bomb()
    if kind == "huge-path":
        n = draw(st.sampled_from([2000, 20000, 100000]))
        pts = " ".join(f"L{12 + 10 * math.cos(i * 2.399):.4f} {12 + 10 * math.sin(i * 2.399):.4f}" for i in range(n))
        return kind, SVG_HEAD + f'<path d="M12 2 {pts} Z"/></svg>'
    if kind == "not-xml":
        return kind, "this is not <svg at all"
    if kind == "empty":
        return kind, ""
    if kind == "image":
        return kind, SVG_HEAD + '<image href="secret.png" width="8" height="8"/><rect width="2" height="2"/></svg>'
    if kind == "external-use":
        return kind, SVG_HEAD + '<use href="other.svg#x"/><use xlink:href="http://127.0.0.1:9/x.svg#y"/></svg>'
    if kind == "viewbox":
        return kind, ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="' + draw(st.sampled_from(
            ["0 0 10 10", "0 0 -10 10", "0 0 0 0", "nan 0 1 1"])) + '"><rect x="1" y="1" width="4" height="4"/></svg>')
    return kind, SVG_HEAD + '<rect x="1e308" y="-1e308" width="1e308" height="4"/></svg>'


@st.composite
def scene_file(draw, max_vertices=400):
    """``(kind, bytes)`` of a scene file."""
    kind = draw(st.sampled_from(["valid", "valid", "valid", "mutated", "mutated", "mutated", "hostile-size",
                                 "bytes", "truncated", "huge-frames", "svg"]))
    doc = draw(scene_document(max_vertices, sane=kind in ("valid", "huge-frames", "svg")))
    if kind == "mutated":
        doc = draw(mutated(doc))
    if kind == "hostile-size":
        doc["image"] = {"width": draw(st.sampled_from([16384, 100000, 2**31, 0, -5])),
                        "height": draw(st.sampled_from([16384, 1, 2**31]))}
    if kind == "huge-frames":  # a file's frame count, budgeted as a generator's
        doc["animation"] = {"frames": draw(st.sampled_from([10**9, 2**40, 10**6, 5000])), "translate": [0.0, 0.0]}
    if kind == "svg":  # an imported-looking scene whose source resvg draws
        doc["image"] = {"width": 24, "height": 24, "background": [1.0, 1.0, 1.0]}
        doc["svg"] = {"file": "src.svg", "scale": draw(st.sampled_from([1.0, 2.0, 0.5])), "tolerance": 0.0625,
                      "ignored": []}
    text = toml_document(doc).encode()
    if kind == "bytes":
        return kind, draw(st.binary(min_size=0, max_size=200))
    if kind == "truncated":
        return kind, text[: draw(st.integers(0, max(0, len(text) - 1)))]
    return kind, text


SANE_SPECS = ["catmull", "catmull-jagged", "point", "supersample:k=2", "supersample:k=3", "jitter:k=2,seed=3",
              "abuffer", "skia", "weiler-atherton", "weiler-atherton:window=2",
              "catmull:filter=tent", "catmull:filter=mitchell", "catmull:filter=gaussian"]


@st.composite
def method_spec(draw):
    if draw(st.booleans()):
        return draw(st.sampled_from(SANE_SPECS))
    name = draw(st.sampled_from(METHODS + ["nosuch", ""]))
    options = {
        "supersample": ["k=2", "k=3", "k=0", "k=-1", "k=2.5", "k=100000", "k=abc"],
        "jitter": ["k=2", "seed=3", "seed=-1", "k=100000", "seed=nan"],
        "catmull": ["filter=box", "filter=tent", "filter=mitchell", "filter=gaussian", "filter=nosuch",
                    "specular=none", "power=nan", "power=inf"],
        "weiler-atherton": ["window=0", "window=2", "window=-1"],
    }.get(name, []) + ["bogus=1", "k", "=3"]
    chosen = draw(st.lists(st.sampled_from(options), max_size=2, unique=True)) if draw(st.booleans()) else []
    return name + (":" + ",".join(chosen) if chosen else "")


# How the scene (or the SVG) is put in place: hostile places a reader must refuse
PLACES = ["file"] * 12 + ["link", "link-dev-zero", "dangling-link", "fifo", "dev-zero", "folder"]

SWEEP_CONFIG = """[experiment]
name = "fuzz"
reference = "supersample:k=2"
metrics = ["rmse"]
temporal = []

[[groups]]
name = "g"
scenes = [{generator = "edges", difficulty = [0.1], frames = 2, size = 8}]
methods = ["point"]
"""


@st.composite
def cli_case(draw, max_vertices=400):
    kind, data = draw(scene_file(max_vertices))
    sane = kind == "valid" and draw(st.booleans())  # half the valid scenes get plain arguments
    place = "file" if sane else draw(st.sampled_from(PLACES))
    svg_kind, svg = draw(svg_source()) if kind == "svg" or draw(st.integers(0, 19)) == 0 else (None, None)
    svg_place = draw(st.sampled_from(PLACES)) if svg is not None else "file"
    choices = (["render"] * 9 + ["hidden-lines"] if kind not in ("huge-frames", "svg")
               else ["render", "invariance", "compare"] if kind == "huge-frames" else ["render", "render", "import"])
    if not sane and kind not in ("huge-frames", "svg"):
        choices += ["invariance", "compare", "sweep"]
    command = draw(st.sampled_from(choices))
    frame = 0 if sane else draw(st.sampled_from([0, 0, 0, 1, 2, -1, 7, 10**20]))
    if command == "render":
        suffix = draw(st.sampled_from([".npy", ".npy", ".png"] + ([] if sane else [".txt"])))
        stats = draw(st.sampled_from([None, None, "stats.json"] + ([] if sane else ["SAME"])))
        spec = ("resvg" if kind == "svg" and draw(st.integers(0, 3)) else
                draw(st.sampled_from(SANE_SPECS)) if sane else draw(method_spec()))
        args = ["render", "{scene}", "-m", spec, "--frame", str(frame), "-o", "{out}" + suffix]
        if stats:
            args += ["--stats", "{out}" + suffix if stats == "SAME" else "{dir}/" + stats]
    elif command == "hidden-lines":
        stroke = draw(st.sampled_from(["0.05", "1"] + ([] if sane else ["-1", "nan", "0"])))
        args = ["hidden-lines", "{scene}", "--frame", str(frame), "--stroke", stroke, "-o", "{out}.svg"]
    elif command == "invariance":
        args = ["invariance", "{scene}", "-m", draw(st.sampled_from(["point", "catmull", "abuffer"])), "--quiet"]
    elif command == "compare":
        args = ["compare", "{scene}", "-m", "point", "-r", draw(st.sampled_from(["catmull", "supersample:k=2"])),
                "--frames", draw(st.sampled_from(["1", "all", "3"])), "--quiet", "--json", "{out}.json"]
    elif command == "import":
        svg_kind = svg_kind or "rect"
        svg = svg if svg is not None else SVG_HEAD + '<rect width="4" height="4"/></svg>'
        args = ["import", "svg", "{svg}", "-o", "{out}.toml",
                *draw(st.sampled_from([[], ["--scale", "2"], ["--tolerance", "1e-300"], ["--strict"]]))]
    else:  # a sweep into a folder with one damaged record or a planted link
        damage = draw(st.sampled_from(["unknown-field", "link-lock", "link-cell", "link-quarantine", "fifo-cell",
                                       "link-manifest"]))
        args = ["sweep", "{dir}/exp.toml", "--out", "{dir}/sweep", "--workers", "1", "--quiet",
                "--cache", "{dir}/cache", "#" + damage]
    return Case(kind, data, args, place=place, svg=None if svg is None else svg.encode(), svg_kind=svg_kind,
                svg_place=svg_place)


# --- running a case -----------------------------------------------------------------------


@dataclass
class Case:
    kind: str
    scene: bytes
    args: list[str]
    place: str = "file"  # how the scene file is put in place (PLACES)
    svg: bytes | None = None  # the scene's SVG source (src.svg beside it), if any
    svg_kind: str | None = None
    svg_place: str = "file"


@dataclass
class Outcome:
    verdict: str  # "image", "refused", or a failure: "traceback", "bad-exit", "not-one-line", "hang", "bad-output",
    # "outside-changed" (a file outside the case's folder written, truncated or moved)
    seconds: float
    code: int | None = None
    stderr: str = ""
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.verdict in ("image", "refused")


class CaseTimeout(BaseException):
    """Raised by the alarm when a case runs past its bound (BaseException: nothing catches it)."""


def _alarm(signum, frame):
    raise CaseTimeout()


def _raised_by_alarm(exc: BaseException) -> bool:
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, CaseTimeout):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _clear(path: Path) -> None:
    if path.is_symlink() or (path.exists() and not path.is_dir()):
        path.unlink()
    elif path.is_dir():
        import shutil

        shutil.rmtree(path)


def _place(path: Path, data: bytes, place: str, outside: Path) -> Path:
    """Put ``data`` at ``path`` as ``place`` says; returns the path to give the command."""
    _clear(path)
    if place == "dev-zero":
        return Path("/dev/zero")
    if place == "fifo":
        os.mkfifo(path)  # no writer: opening it to read would block forever
    elif place == "folder":
        path.mkdir()
    elif place == "link":  # a link to a real file outside the case folder
        target = outside / f"linked-{path.name}"
        target.write_bytes(data)
        os.symlink(target, path)
    elif place == "link-dev-zero":
        os.symlink("/dev/zero", path)
    elif place == "dangling-link":
        os.symlink(outside / "no-such-file", path)
    else:
        path.write_bytes(data)
    return path


def outside_digest(outside: Path) -> dict[str, bytes]:
    """The files of ``outside`` (the targets of the cases' links) and their bytes."""
    return {p.name: p.read_bytes() for p in sorted(outside.iterdir()) if p.is_file()} if outside.is_dir() else {}


def _sweep_folder(folder: Path, damage: str, outside: Path) -> None:
    """``folder/sweep``: a finished sweep of SWEEP_CONFIG (copied from the warm-up's), then damaged."""
    import json as _json
    import shutil

    sweep = folder / "sweep"
    _clear(sweep)
    (folder / "exp.toml").write_text(SWEEP_CONFIG)
    template = folder.parent / "sweep-template"
    if template.is_dir():
        shutil.copytree(template, sweep, symlinks=True)
    cells = sorted((sweep / "cells").glob("*.json")) if (sweep / "cells").is_dir() else []
    if not cells:
        return
    if damage == "unknown-field":
        record = _json.loads(cells[0].read_text())
        record["x"] = 1
        cells[0].write_text(_json.dumps(record))
    elif damage == "link-lock":
        _clear(sweep / "sweep.lock")
        os.symlink(outside / "victim.txt", sweep / "sweep.lock")
    elif damage == "link-cell":
        cells[0].unlink()
        os.symlink(outside / "victim.txt", cells[0])
    elif damage == "fifo-cell":
        cells[0].unlink()
        os.mkfifo(cells[0])
    elif damage == "link-quarantine":
        cells[0].write_text("{broken")
        os.symlink(outside / "dir", sweep / "quarantine")
    elif damage == "link-manifest":
        (sweep / "manifest.json").unlink()
        os.symlink(outside / "victim.txt", sweep / "manifest.json")


def run_case(case: Case, folder: Path, bound_s: float) -> Outcome:
    """Run one case through ``aaeval.cli.main`` in this process and judge it."""
    from aaeval.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    outside = folder.parent / "outside"  # what the case's links point at: must not change
    outside.mkdir(exist_ok=True)
    (outside / "dir").mkdir(exist_ok=True)
    (outside / "victim.txt").write_text("KEEP\n")
    scene = _place(folder / "scene.toml", case.scene, case.place, outside)
    svg = folder / "src.svg"
    _clear(svg)
    if case.svg is not None:
        svg = _place(svg, case.svg, case.svg_place, outside)
    out = folder / "out"
    if case.args[0] == "sweep":
        _sweep_folder(folder, case.args[-1][1:], outside)
    before = outside_digest(outside)
    args = [a.format(scene=scene, out=out, dir=folder, svg=svg) for a in case.args if not a.startswith("#")]
    outputs = {Path(a) for a in args if a.startswith(str(out)) or a.startswith(str(folder) + "/stats")}
    for p in outputs:
        _clear(p)
    outcome = _run_judged(main, args, outputs, out, bound_s)
    if outside_digest(outside) != before or sorted(p.name for p in (outside / "dir").iterdir()):
        return Outcome("outside-changed", outcome.seconds, outcome.code, outcome.stderr)
    return outcome


def _run_judged(main, args, outputs, out, bound_s) -> Outcome:
    err, std = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, bound_s)
    start = time.perf_counter()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
            try:
                code = main(args)
            except SystemExit as exc:  # argparse: usage and one error line, exit 2
                code = exc.code if isinstance(exc.code, int) else 1
    except CaseTimeout:
        return Outcome("hang", time.perf_counter() - start, None, err.getvalue())
    except Exception as exc:  # escaped main: the user would see a traceback
        seconds = time.perf_counter() - start
        if seconds >= bound_s or _raised_by_alarm(exc):  # the alarm landed inside a numba kernel
            return Outcome("hang", seconds, None, f"over {bound_s:g} s ({type(exc).__name__}: {exc})")
        return Outcome("traceback", seconds, None, f"{type(exc).__name__}: {exc}")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    seconds = time.perf_counter() - start
    text = err.getvalue()
    lines = [line for line in text.splitlines() if line.strip()]
    if "Traceback" in text:
        return Outcome("traceback", seconds, code, text)
    if code == 2:
        if not lines or ": error: " not in lines[-1]:
            return Outcome("not-one-line", seconds, code, text)
        if not lines[-1].startswith("aaeval") or (len(lines) > 1 and not lines[0].startswith("usage:")):
            return Outcome("not-one-line", seconds, code, text)
        written = [p.name for p in outputs if p.exists()]
        if written:
            return Outcome("bad-output", seconds, code, f"refused but wrote {written}: {text}")
        return Outcome("refused", seconds, code, lines[-1])
    if code != 0:
        return Outcome("bad-exit", seconds, code, text)
    if args[0] == "sweep":
        table = Path(args[args.index("--out") + 1]) / "results.parquet"
        return Outcome("image", seconds, code, text) if table.is_file() else Outcome(
            "bad-output", seconds, code, "sweep exit 0 without results.parquet")
    if args[0] == "invariance":
        return Outcome("image", seconds, code, text)
    image_out = Path(args[args.index("-o" if "-o" in args else "--json") + 1])
    if not image_out.is_file() or image_out.stat().st_size == 0:
        return Outcome("bad-output", seconds, code, f"exit 0 without {image_out.name}")
    if image_out.suffix == ".npy":
        image = np.load(image_out)
        if not np.all(np.isfinite(image)):
            return Outcome("bad-output", seconds, code, "non-finite pixels")
    return Outcome("image", seconds, code, text, notes=lines)


def warm_up(folder: Path) -> None:
    """Compile every method once, outside any case's time bound."""
    from aaeval.cli import main

    scene = folder / "warm.toml"
    scene.write_text(toml_document({"image": {"width": 4, "height": 4}, "polygons": [
        {"color": [1.0, 0.0, 0.0], "vertices": [[0.5, 0.5, 1.0], [3.5, 1.0, 1.0], [1.0, 3.5, 1.0]]}]}))
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        for method in METHODS:
            main(["render", str(scene), "-m", method, "-o", str(folder / "warm.npy")])
        main(["hidden-lines", str(scene), "-o", str(folder / "warm.svg")])
        # compare and invariance pay one-time imports and warm-ups (seconds, more on a loaded
        # machine) on their first call: outside any case's bound, as the methods' JIT is
        for reference in ("catmull", "supersample:k=2"):
            main(["compare", str(scene), "-m", "point", "-r", reference, "--quiet", "--json", str(folder / "w.json")])
        main(["invariance", str(scene), "-m", "point", "--quiet"])
        (folder / "warm.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
                                         '<rect width="2" height="2"/></svg>')
        main(["import", "svg", str(folder / "warm.svg"), "-o", str(folder / "warm-svg.toml")])
        # the finished sweep that sweep cases copy and damage
        (folder / "exp.toml").write_text(SWEEP_CONFIG)
        main(["sweep", str(folder / "exp.toml"), "--out", str(folder / "sweep-template"), "--workers", "1",
              "--quiet", "--cache", str(folder / "cache")])


def fuzz_environment() -> dict[str, str]:
    """Limits that make the budget checks decide, not this machine's size."""
    # AAEVAL_MAX_SECONDS: a run the budget lets through may take a few times its estimate on
    # a loaded machine, and a case has 20-30 s
    return {"AAEVAL_MAX_MEMORY": "1G", "AAEVAL_MAX_SAMPLES": str(1 << 28), "AAEVAL_MAX_SECONDS": "5"}
