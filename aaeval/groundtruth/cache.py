"""The one ground-truth cache: every Mitsuba ground truth (flat or Phong) is rendered once.

:func:`groundtruth` renders a scene's ground truth (the flat-colour one of
:mod:`aaeval.groundtruth.flat`, or for a scene with ``[shaded]`` objects the Phong one of
:mod:`aaeval.groundtruth.phong`, with its specular channel) or reads it back from disk.

An entry is keyed by what determines it and nothing else:

- the scene at that frame (:func:`scene_digest`: size, background, every polygon's
  vertices and colour in file order, and for shaded scenes the expanded triangles, their
  normal fields, materials and light; not the file's path);
- the options that change pixels (spp, sampler, seed, and the pixel filter: a group judged
  through filter F needs ``mitsuba:filter=F``, cached like the box; the box leaves the key
  as it was before filters were keyed, so existing box entries stay valid);
- the Mitsuba version;
- the source code that turns a scene into Mitsuba's scene and shades it
  (:data:`CODE_FILES`, hashed by :func:`code_digest`): editing the conversion gives new
  keys, so stale ground truth is never served (no version number to bump by hand).

The variant is not part of the key: CUDA, LLVM and scalar renders of one key are all
valid ground truths (it is recorded in the ``.json`` note beside the image). Files are
written atomically, so concurrent workers and interrupted runs never leave a half-written
entry; an entry that cannot be read (damaged) is rendered again and replaced, with a
warning naming the file.
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import json
import os
import stat
import warnings
import zipfile
from pathlib import Path
from typing import NamedTuple

import numpy as np

import aaeval
from aaeval.groundtruth.flat import DEFAULT_SAMPLER, DEFAULT_SPP
from aaeval.imageio import atomic_write
from aaeval.scenes import Scene
from aaeval.scenes.shaded import expand_shaded, has_shaded

__all__ = [
    "CACHE_ENV",
    "CODE_FILES",
    "GroundTruth",
    "cache_dir",
    "cache_root",
    "code_digest",
    "scene_digest",
    "groundtruth_key",
    "groundtruth_path",
    "groundtruth",
    "groundtruth_image",
    "groundtruth_phong",
]

CACHE_ENV = "AAEVAL_CACHE_DIR"

# Source files (relative to the aaeval package) whose code decides a ground-truth image
# beyond the scene data the digest covers: the conversion to Mitsuba, the Phong
# integrator, and the near-tie rule that resolves nearly coplanar groups before Mitsuba
# sees them (with the clipper it uses).
CODE_FILES = ("groundtruth/flat.py", "groundtruth/phong.py", "scenes/depth.py",
              "weiler_atherton/near_ties.py", "weiler_atherton/clipper.py")
# The native modules that conversion calls (the window clip, the clipper, the near-tie
# regions): their compiled bytes join the key, so a rebuild from changed C++ gives new keys.
NATIVE_MODULES = ("aaeval.native.catmull", "aaeval.native.weiler_atherton")


class GroundTruth(NamedTuple):
    """A ground truth: ``image`` (H, W, 3) linear RGB, ``specular`` (H, W) for shaded
    scenes (the specular term alone) else None, ``hit`` True when read from the cache."""

    image: np.ndarray
    specular: np.ndarray | None
    hit: bool


def cache_root() -> Path:
    """The folder of every cache of this machine: ``$AAEVAL_CACHE_DIR``, default ``~/.cache/aaeval``
    (ground truths here, the sweeps' reference images in :mod:`aaeval.sweeps.reference_cache`)."""
    return Path(os.environ.get(CACHE_ENV) or Path.home() / ".cache" / "aaeval").expanduser()


def cache_dir() -> Path:
    """Folder of cached ground truths: ``cache_root()/groundtruth``."""
    return cache_root() / "groundtruth"


@functools.lru_cache(maxsize=None)
def code_digest(files: tuple[str, ...] = CODE_FILES, root: Path | None = None) -> str:
    """SHA-256 (hex, 16 digits) of the source of ``files``, paths inside ``root`` (the aaeval package)."""
    root = Path(aaeval.__file__).parent if root is None else Path(root)
    h = hashlib.sha256()
    for rel in files:
        h.update(rel.encode() + b"\0" + (root / rel).read_bytes() + b"\0")
    if files == CODE_FILES:
        for name in NATIVE_MODULES:
            h.update(name.encode() + b"\0" + Path(importlib.import_module(name).__file__).read_bytes() + b"\0")
    return h.hexdigest()[:16]


def scene_digest(scene: Scene) -> str:
    """SHA-256 of everything in a scene that shows in its ground truth, at its current frame.

    Width, height, background and each polygon's vertices and colour in file order, as
    little-endian float64 bytes; for a scene with ``[shaded]`` objects, the same of the
    expanded scene plus every polygon's normal field, material and the light. The source
    path, frame number and animation settings are left out: two files with the same
    geometry share one digest.
    """
    if has_shaded(scene):
        expanded = expand_shaded(scene)
        field = expanded.field
        h = hashlib.sha256(b"shaded\0" + _core_digest(expanded.scene).encode())
        for array in (field.shaded, field.G, field.ka, field.kd, field.ks, field.n):
            h.update(np.ascontiguousarray(array, dtype="<f8").tobytes())
        if field.light is not None:
            h.update(field.light.kind.encode())
            h.update(np.ascontiguousarray(field.light.vector, dtype="<f8").tobytes())
        return h.hexdigest()
    return _core_digest(scene)


def _core_digest(scene: Scene) -> str:
    arrays = scene.arrays
    h = hashlib.sha256()
    h.update(np.array([scene.width, scene.height, len(scene.polygons)], dtype="<i8").tobytes())
    h.update(np.ascontiguousarray(scene.background, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(arrays.length, dtype="<i8").tobytes())
    h.update(np.ascontiguousarray(arrays.vertices, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(arrays.colors, dtype="<f8").tobytes())
    return h.hexdigest()


def _mitsuba_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("mitsuba")
    except PackageNotFoundError:  # a source build
        import mitsuba

        return mitsuba.__version__


def groundtruth_key(scene: Scene, *, spp: int, sampler: str, seed: int, filter: str = "box") -> str:
    """Hex key of a ground truth (see the module docstring for what it covers)."""
    config = {
        "scene": scene_digest(scene),
        "spp": int(spp),
        "sampler": sampler,
        "seed": int(seed),
        "mitsuba": _mitsuba_version(),
        "code": code_digest(),
    }
    if filter != "box":  # the box's key is the one it had before filters were keyed
        config["filter"] = str(filter)
    return hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()[:32]


def groundtruth_path(scene: Scene, *, spp: int, sampler: str, seed: int, filter: str = "box") -> Path:
    """Where the cached ground truth of this configuration lives (it may not exist yet)."""
    return cache_dir() / f"{groundtruth_key(scene, spp=spp, sampler=sampler, seed=seed, filter=filter)}.npz"


def groundtruth(
    scene: Scene,
    *,
    spp: int = DEFAULT_SPP,
    sampler: str = DEFAULT_SAMPLER,
    seed: int = 0,
    variant: str = "auto",
    cache: bool = True,
    filter: str = "box",
) -> GroundTruth:
    """The Mitsuba ground truth of ``scene`` (Phong for ``[shaded]`` scenes), cached on disk.

    ``filter``: a pixel filter of :data:`aaeval.filters.FILTERS` (Mitsuba's matching
    ``rfilter``; flat-coloured scenes only), part of the cache key.
    """
    if filter != "box" and has_shaded(scene):
        raise ValueError(f"mitsuba: filter={filter} supports flat-coloured scenes only, not [shaded] objects")
    render = _render_phong if has_shaded(scene) else _render_flat
    options = {"spp": spp, "sampler": sampler, "seed": seed}
    if filter != "box":
        options["filter"] = filter
    if not cache:
        return GroundTruth(*render(scene, variant=variant, **options), False)
    path = groundtruth_path(scene, **options)
    stored = _read(path, scene)
    if stored is not None:
        return GroundTruth(*stored, True)
    image, specular = render(scene, variant=variant, **options)
    arrays = {"image": image} if specular is None else {"image": image, "specular": specular}
    atomic_write(path, lambda tmp: np.savez(tmp, **arrays))  # tmp ends in .npz: kept as is
    _write_note(path, scene, **options)
    return GroundTruth(image, specular, False)


def groundtruth_image(scene: Scene, **options) -> tuple[np.ndarray, bool]:
    """``(image, hit)`` of :func:`groundtruth` (same options)."""
    truth = groundtruth(scene, **options)
    return truth.image, truth.hit


def groundtruth_phong(scene: Scene, **options) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(image, specular, hit)`` of :func:`groundtruth` for a scene with ``[shaded]`` objects."""
    if not has_shaded(scene):
        raise ValueError(f"{scene.source}: the Phong ground truth needs a scene with [shaded] objects")
    return tuple(groundtruth(scene, **options))


def _render_flat(scene: Scene, *, filter: str = "box", **options) -> tuple[np.ndarray, None]:
    from aaeval.groundtruth import flat

    if filter != "box":
        from aaeval.filters import get_filter

        options["rfilter"] = dict(get_filter(filter).mitsuba)
    return flat.render_mitsuba(scene, **options), None


def _render_phong(scene: Scene, **options) -> tuple[np.ndarray, np.ndarray]:
    from aaeval.groundtruth import phong

    return phong.render_mitsuba_phong(scene, **options)


def _read(path: Path, scene: Scene) -> tuple[np.ndarray, np.ndarray | None] | None:
    """The cached arrays of ``scene``, or None (missing, or damaged: named, rendered again).

    The entry is read as untrusted input: a regular file only (a FIFO would block the read),
    each member's shape and dtype taken from its header before its data is inflated (a few
    MB can claim gigabytes), and pixels that are not finite refused."""
    if not os.path.lexists(path):
        return None
    wanted = {"image": scene.shape}
    if has_shaded(scene):
        wanted["specular"] = scene.shape[:2]
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            raise ValueError("not a regular file")
        with zipfile.ZipFile(path) as archive:
            members = {name.removesuffix(".npy"): name for name in archive.namelist()}
            if set(members) != set(wanted):
                raise ValueError(f"holds {sorted(members)}, this scene needs {sorted(wanted)}")
            arrays = {name: _member(archive, members[name], shape) for name, shape in wanted.items()}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        warnings.warn(f"damaged ground-truth cache entry {path} ({exc}); rendering it again", stacklevel=3)
        return None
    return arrays["image"], arrays.get("specular")


def _member(archive: zipfile.ZipFile, name: str, shape: tuple[int, ...]) -> np.ndarray:
    """One ``.npy`` member of an entry, of ``shape`` and float64, finite; checked from its
    header before its data is read."""
    with archive.open(name) as f:
        readers = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}
        version = np.lib.format.read_magic(f)
        if version not in readers:
            raise ValueError(f"{name}: unsupported .npy version {version}")
        stored, fortran, dtype = readers[version](f)
        if tuple(stored) != tuple(shape) or dtype != np.float64 or fortran:
            raise ValueError(f"{name} is {dtype} of shape {tuple(stored)}, not this scene's float64 {tuple(shape)}")
        data = np.frombuffer(f.read(np.dtype(dtype).itemsize * int(np.prod(shape)) + 1), dtype=np.uint8)
    if data.size != np.dtype(dtype).itemsize * int(np.prod(shape)):
        raise ValueError(f"{name} holds {data.size} bytes where its header promises more or fewer")
    array = data.view(dtype).reshape(shape).copy()
    if not np.isfinite(array).all():
        raise ValueError(f"{name} has pixels that are not finite")
    return array


def _write_note(path: Path, scene: Scene, **options) -> None:
    import mitsuba as mi

    note = {
        **options,
        "source": scene.source,
        "frame": scene.frame,
        "shaded": has_shaded(scene),
        "variant": mi.variant(),
        "mitsuba": _mitsuba_version(),
        "code": code_digest(),
    }
    atomic_write(path.with_suffix(".json"), lambda tmp: Path(tmp).write_text(json.dumps(note, indent=1) + "\n"))
