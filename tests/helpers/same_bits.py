"""The scene list and image digests behind the kernels' same-bits regression.

Every kernel family's images on every scene here are kept as SHA-256 digests
(``tests/data/same_bits_<family>.json``); the kernels must give the same bytes
(``tests/native/test_same_bits.py``), so a change that moves any bit of any image shows, and is
either a fault or recorded again on purpose.

The exact filters' digests (``catmull:filter=...``) were recorded again from the native
kernels when the second route through them was deleted: the one route left takes a pixel
holding two irregular pieces over what both hide as the second's piece less their overlap,
takes the tent's integrals by the shoelace formulas and a cubic's four edge nodes as one
vector, integrates a piece alone in front of its pixel along its own edges cut to the
pixel's column, and reads the Gaussian's basis from polynomials (``gauss_table`` in
``src/catmull/filter_basis.hpp``); the two-layer case now grows its scratch space instead
of falling back to the pixel integrator when it is short. These move the images by
rounding only. Before they were recorded, the images whose digests changed (553 of the 805
catmull entries, all of them exact-filter images; the box filter's and every other
family's entries did not change) were checked against the independent quadrature oracle
(``tests/helpers/filter_oracle.py``, GEOS visible regions) within ``tests/filters/test_filters.py``'s
tolerance (1e-9): 545 of them, the largest gap 8.5e-13. The 512 x 512 benchmark scene's
five, where the oracle takes too long, were checked against the deleted route's images
within its former tolerance (1e-13; the largest gap 7.8e-14); three Gaussian images of the
largest scenes (generated random@30 and random@300, shipped content/pangram), whose order-14
oracle ran past a quarter of an hour each, were not checked.

Record a family with::

    python3 -m tests.helpers.same_bits record <family>

A shaded scene's digest is kept once per numpy route (a list): its shading calls numpy's
float64 ``**``, exp, log and arccos, which numpy computes with AVX-512 code where the CPU
has it and with libm elsewhere, a few units in the last place apart
(``tests/helpers/catmull_fragment_bits.py`` holds its fragments' bits). Record only the scenes a file does not hold yet (a newly shipped scene), every recorded
entry left as it is, with ``python3 -m tests.helpers.same_bits add <family>``. Record both routes of the
shaded entries with::

    python3 -m tests.helpers.same_bits reshade <family>

The scenes: random interpenetrating triangles and concave stars, degenerate placements
(shared vertices, pixel-boundary edges, equal depths), near-coplanar stacks, every shipped
scene (holes, content, shaded), generated benchmark-like scenes.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from aaeval.catmull.filtered import filter_sums
from aaeval.filters.exact import divide_by_weight
from aaeval.filters import get_filter
from aaeval.renderers import render
from aaeval.scenes import Scene, load_scene, parse_scene
from aaeval.scenes.shaded import has_shaded
from aaeval.scenes.generate import generate_scene, random_triangles
from tests.helpers.randomscenes import degenerate_scene, random_scene

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parents[1] / "data"

FILTERS = ("tent", "bspline", "mitchell", "catmullrom", "gaussian")

# the methods each kernel family renders: the digests of a family change only with its port
FAMILY_METHODS: dict[str, tuple[str, ...]] = {
    "catmull": ("catmull", "catmull-jagged", *(f"catmull:filter={f}" for f in FILTERS)),
    "weiler_atherton": ("weiler-atherton",),
    "samplers": ("point", "supersample:k=3", "jitter:k=4,seed=7", "abuffer", "msaa:samples=4"),
}


# per process, for the tests that run on one worker (xdist_group "same_bits"): the scenes,
# and the images of the exact filters
_MADE: dict[str, Scene] = {}
_RECORDED: dict[str, np.ndarray] = {}


def made(scene_id: str, make: Callable[[], Scene]) -> Scene:
    """The scene ``scene_id``, made once in this process."""
    if scene_id not in _MADE:
        _MADE[scene_id] = make()
    return _MADE[scene_id]


def recorded_image(scene_id: str, scene: Scene, spec: str) -> np.ndarray:
    """:func:`render_recorded` of ``spec`` on scene ``scene_id`` (an exact filter's kept for
    this process; a refusal is raised every time)."""
    key = f"{scene_id}|{spec}"
    if key in _RECORDED:
        return _RECORDED[key]
    image = render_recorded(scene, spec)
    if ":filter=" in spec:
        _RECORDED[key] = image
    return image


def render_recorded(scene: Scene, spec: str) -> np.ndarray:
    """The image of ``spec`` as the digests were recorded: an exact filter's pixel sums
    divided by the film's weights (what ``catmull:filter=...`` renders); every other spec
    (and a shaded scene, which the filters refuse) as rendered."""
    name, _, option = spec.partition(":filter=")
    if name == "catmull" and option and not has_shaded(scene):
        filt = get_filter(option)
        return divide_by_weight(filter_sums(scene, filt), scene, filt)
    return render(scene, spec)


def near_tie_stack(seed: int, k: int = 4) -> Scene:
    """k large quads over one plane, each tilted by about 1e-12: near-coplanar ties."""
    rng = np.random.default_rng(seed)
    polys = []
    for i in range(k):
        x0, y0 = rng.uniform(0, 4, 2)
        xy = np.array([[x0, y0], [x0 + 9, y0 + 1], [x0 + 8, y0 + 8], [x0 - 1, y0 + 7]])
        tilt = rng.uniform(-1e-12, 1e-12, 2)
        z = 3.0 + tilt[0] * xy[:, 0] + tilt[1] * xy[:, 1]
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": np.column_stack([xy, z]).tolist()})
    return parse_scene({"image": {"width": 13, "height": 12}, "polygons": polys}, source=f"<stack {seed}>")


def scenes() -> Iterator[tuple[str, Callable[[], Scene]]]:
    """``(scene id, make)`` for every scene of the regression, in a fixed order."""
    for seed in range(40):
        yield f"random-{seed}", lambda seed=seed: random_scene(seed, tilt=0.0 if seed % 5 == 0 else 1.0)
    for seed in range(30):
        yield f"degenerate-{seed}", lambda seed=seed: degenerate_scene(seed)
    for seed in range(10):
        yield f"near-tie-{seed}", lambda seed=seed: near_tie_stack(seed, k=2 + seed % 4)
    for path in sorted((ROOT / "configs" / "scenes").rglob("*.toml")):
        name = path.relative_to(ROOT / "configs" / "scenes").as_posix()
        yield f"shipped:{name}", lambda path=path: load_scene(path)
    for name, difficulty in (("fan", 7), ("fan", 40), ("sliver", 3.0), ("sliver", 40.0), ("picket", 0.7),
                             ("picket", 3.3), ("random", 30), ("random", 300), ("edges", 0.05), ("edges", 0.3),
                             ("shininess", 50), ("curvature", 0.5)):
        yield f"generated:{name}@{difficulty}", lambda n=name, d=difficulty: parse_scene(generate_scene(n, d))
    yield "bench:512-2000x40", lambda: _benchmark_like(512, 2000, 40.0)


def _benchmark_like(size: int, count: int, extent: float) -> Scene:
    """bench_methods' random-triangle scene at one size (seeded)."""
    return random_triangles(count, size, size, size=extent, seed=0)


def digest(image: np.ndarray) -> str:
    """SHA-256 of the image's float64 bytes and shape."""
    image = np.ascontiguousarray(image, dtype=np.float64)
    return hashlib.sha256(repr(image.shape).encode() + image.tobytes()).hexdigest()


def digests_of(family: str, only: set[str] | None = None) -> Iterator[tuple[str, str]]:
    """``(scene id|spec, digest)`` of every scene (or those in ``only``) and method of
    ``family``; a method that refuses a scene (a shaded scene for a flat method, say) records
    the refusal's type."""
    for scene_id, make in scenes():
        if only is not None and scene_id not in only:
            continue
        scene = made(scene_id, make)
        for spec in FAMILY_METHODS[family]:
            try:
                yield f"{scene_id}|{spec}", digest(recorded_image(scene_id, scene, spec))
            except (ValueError, NotImplementedError) as error:
                yield f"{scene_id}|{spec}", f"refused: {type(error).__name__}"


def matches(got: str, expected: str | list[str]) -> bool:
    """Whether a digest is the recorded one (one of a shaded scene's, one per numpy route)."""
    return got in expected if isinstance(expected, list) else got == expected


def record(family: str) -> Path:
    DATA.mkdir(exist_ok=True)
    out = DATA / f"same_bits_{family}.json"
    digests = dict(digests_of(family))
    out.write_text(json.dumps(digests, indent=1, sort_keys=True) + "\n")
    return out


def add_new(family: str) -> Path:
    """Record the digests of the scenes the file does not hold yet (a scene newly shipped or
    generated), leaving every recorded entry as it is: a new scene has no earlier bits to
    keep, and nothing already recorded is taken again from the kernels under test. A new
    shaded scene then needs ``reshade`` for its second numpy route."""
    out = DATA / f"same_bits_{family}.json"
    digests = json.loads(out.read_text())
    recorded = {key.split("|", 1)[0] for key in digests}
    new = {scene_id for scene_id, _ in scenes() if scene_id not in recorded}
    digests.update(digests_of(family, only=new))
    out.write_text(json.dumps(digests, indent=1, sort_keys=True) + "\n")
    return out


def shaded_digests(family: str) -> dict[str, str]:
    """The digests of ``family`` on the shaded scenes, by this process's numpy route."""
    shaded = {scene_id for scene_id, make in scenes() if has_shaded(made(scene_id, make))}
    return {key: value for key, value in digests_of(family, only=shaded)}


def _numpy_baseline_env() -> dict[str, str]:
    """The environment of a process whose numpy dispatches none of its optimised paths."""
    umath = np._core._multiarray_umath
    on = [feature for feature in umath.__cpu_dispatch__ if umath.__cpu_features__.get(feature)]
    return {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(on)}


def reshade(family: str) -> Path:
    """Record the shaded scenes' digests of ``family`` by both numpy routes (this process's
    and one with numpy's dispatched code turned off), leaving every other entry as it is."""
    out = DATA / f"same_bits_{family}.json"
    digests = json.loads(out.read_text())
    other = subprocess.run([sys.executable, "-m", "tests.helpers.same_bits", "shaded", family], cwd=ROOT,
                           env=_numpy_baseline_env(), check=True, capture_output=True, text=True)
    routes = (shaded_digests(family), json.loads(other.stdout))
    for key in routes[0]:
        found = sorted({route[key] for route in routes})
        digests[key] = found if len(found) > 1 else found[0]
    out.write_text(json.dumps(digests, indent=1, sort_keys=True) + "\n")
    return out


if __name__ == "__main__":
    from aaeval import registries

    registries.load()  # the methods whose images are recorded
    commands = {"record": record, "reshade": reshade, "add": add_new, "shaded": lambda f: json.dumps(shaded_digests(f))}
    if len(sys.argv) != 3 or sys.argv[1] not in commands or sys.argv[2] not in FAMILY_METHODS:
        raise SystemExit(f"usage: python3 -m tests.helpers.same_bits {{record,reshade,add}} {{{','.join(FAMILY_METHODS)}}}")
    print(commands[sys.argv[1]](sys.argv[2]))
