"""Hostile-but-fair inputs for the command line, and the one rule every case must meet.

A case is a scene file (valid, mutated, or hostile: huge, tiny, NaN, duplicate, degenerate,
self-crossing, deep overlaps, binary) and the arguments of ``aaeval render`` or
``aaeval hidden-lines``. It must end in an image (exit 0, the file written and finite) or
in a refusal (exit 2, the last stderr line ``aaeval CMD: error: ...``, nothing written),
never in a traceback, another exit code, or a case over its time bound.

Used by tests/test_fuzz.py (a few hundred cases in CI) and scripts/fuzz_cli.py (offline).
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


@st.composite
def scene_file(draw, max_vertices=400):
    """``(kind, bytes)`` of a scene file."""
    kind = draw(st.sampled_from(["valid", "valid", "valid", "mutated", "mutated", "mutated", "hostile-size",
                                 "bytes", "truncated"]))
    doc = draw(scene_document(max_vertices, sane=kind == "valid"))
    if kind == "mutated":
        doc = draw(mutated(doc))
    if kind == "hostile-size":
        doc["image"] = {"width": draw(st.sampled_from([16384, 100000, 2**31, 0, -5])),
                        "height": draw(st.sampled_from([16384, 1, 2**31]))}
    text = toml_document(doc).encode()
    if kind == "bytes":
        return kind, draw(st.binary(min_size=0, max_size=200))
    if kind == "truncated":
        return kind, text[: draw(st.integers(0, max(0, len(text) - 1)))]
    return kind, text


SANE_SPECS = ["catmull", "catmull-jagged", "point", "supersample:k=2", "supersample:k=3", "jitter:k=2,seed=3",
              "abuffer", "skia", "weiler-atherton", "weiler-atherton:window=2"]


@st.composite
def method_spec(draw):
    if draw(st.booleans()):
        return draw(st.sampled_from(SANE_SPECS))
    name = draw(st.sampled_from(METHODS + ["nosuch", ""]))
    options = {
        "supersample": ["k=2", "k=3", "k=0", "k=-1", "k=2.5", "k=100000", "k=abc"],
        "jitter": ["k=2", "seed=3", "seed=-1", "k=100000", "seed=nan"],
        "catmull": ["filter=box", "filter=nosuch", "specular=none", "power=nan", "power=inf"],
        "weiler-atherton": ["window=0", "window=2", "window=-1"],
    }.get(name, []) + ["bogus=1", "k", "=3"]
    chosen = draw(st.lists(st.sampled_from(options), max_size=2, unique=True)) if draw(st.booleans()) else []
    return name + (":" + ",".join(chosen) if chosen else "")


@st.composite
def cli_case(draw, max_vertices=400):
    kind, data = draw(scene_file(max_vertices))
    sane = kind == "valid" and draw(st.booleans())  # half the valid scenes get plain arguments
    command = draw(st.sampled_from(["render"] * 9 + ["hidden-lines"]))
    frame = 0 if sane else draw(st.sampled_from([0, 0, 0, 1, 2, -1, 7, 10**20]))
    if command == "render":
        suffix = draw(st.sampled_from([".npy", ".npy", ".png"] + ([] if sane else [".txt"])))
        stats = draw(st.sampled_from([None, None, "stats.json"] + ([] if sane else ["SAME"])))
        spec = draw(st.sampled_from(SANE_SPECS)) if sane else draw(method_spec())
        args = ["render", "{scene}", "-m", spec, "--frame", str(frame), "-o", "{out}" + suffix]
        if stats:
            args += ["--stats", "{out}" + suffix if stats == "SAME" else "{dir}/" + stats]
    else:
        stroke = draw(st.sampled_from(["0.05", "1"] + ([] if sane else ["-1", "nan", "0"])))
        args = ["hidden-lines", "{scene}", "--frame", str(frame), "--stroke", stroke, "-o", "{out}.svg"]
    return Case(kind, data, args)


# --- running a case -----------------------------------------------------------------------


@dataclass
class Case:
    kind: str
    scene: bytes
    args: list[str]


@dataclass
class Outcome:
    verdict: str  # "image", "refused", or a failure: "traceback", "bad-exit", "not-one-line", "hang", "bad-output"
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


def run_case(case: Case, folder: Path, bound_s: float) -> Outcome:
    """Run one case through ``aaeval.cli.main`` in this process and judge it."""
    from aaeval.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    scene = folder / "scene.toml"
    scene.write_bytes(case.scene)
    out = folder / "out"
    args = [a.format(scene=scene, out=out, dir=folder) for a in case.args]
    outputs = {Path(a) for a in args if a.startswith(str(out)) or a.startswith(str(folder) + "/stats")}
    for p in outputs:
        p.unlink(missing_ok=True)
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
    image_out = Path(args[args.index("-o") + 1])
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


def fuzz_environment() -> dict[str, str]:
    """Limits that make the budget checks decide, not this machine's size."""
    return {"AAEVAL_MAX_MEMORY": "1G", "AAEVAL_MAX_SAMPLES": str(1 << 28)}
