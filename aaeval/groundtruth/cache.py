"""Ground-truth images cached on disk, so each one is rendered once.

A cached image is keyed by what determines it and nothing else: the scene's geometry at
that frame (size, background, every polygon's vertices and colour, in file order — not
the file's path), the render options that change pixels (spp, sampler, seed), the
Mitsuba version and :data:`GROUNDTRUTH_VERSION` (bumped whenever the conversion to
Mitsuba changes). The variant is not part of the key: CUDA, LLVM and scalar renders of
one key are all valid ground truths (it is recorded beside the image).

Files are written atomically (temporary file, then ``os.replace``), so concurrent
workers and interrupted runs never leave a broken entry.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from aaeval.groundtruth.mitsuba import DEFAULT_SAMPLER, DEFAULT_SPP
from aaeval.imageio import atomic_write
from aaeval.scenes import Scene

__all__ = [
    "GROUNDTRUTH_VERSION",
    "CACHE_ENV",
    "cache_dir",
    "scene_digest",
    "groundtruth_key",
    "groundtruth_path",
    "groundtruth_image",
]

GROUNDTRUTH_VERSION = 1
CACHE_ENV = "AAEVAL_CACHE_DIR"


def cache_dir() -> Path:
    """Folder of cached ground truths: ``$AAEVAL_CACHE_DIR/groundtruth``, default ``~/.cache/aaeval/groundtruth``."""
    root = os.environ.get(CACHE_ENV) or Path.home() / ".cache" / "aaeval"
    return Path(root).expanduser() / "groundtruth"


def scene_digest(scene: Scene) -> str:
    """SHA-256 of everything in a core scene that shows in the image, at its current frame.

    Width, height, background and each polygon's vertices and colour in file order, as
    little-endian float64 bytes. The source path, frame number and animation settings are
    left out: two files with the same geometry share one digest.
    """
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


def groundtruth_key(scene: Scene, *, spp: int, sampler: str, seed: int) -> str:
    """Hex key of a ground-truth image (see the module docstring for what it covers)."""
    config = {
        "scene": scene_digest(scene),
        "spp": int(spp),
        "sampler": sampler,
        "seed": int(seed),
        "mitsuba": _mitsuba_version(),
        "groundtruth": GROUNDTRUTH_VERSION,
    }
    return hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()[:32]


def groundtruth_path(scene: Scene, *, spp: int, sampler: str, seed: int) -> Path:
    """Where the cached image of this configuration lives (it may not exist yet)."""
    return cache_dir() / f"{groundtruth_key(scene, spp=spp, sampler=sampler, seed=seed)}.npy"


def groundtruth_image(
    scene: Scene,
    *,
    spp: int = DEFAULT_SPP,
    sampler: str = DEFAULT_SAMPLER,
    seed: int = 0,
    variant: str = "auto",
    cache: bool = True,
) -> tuple[np.ndarray, bool]:
    """The Mitsuba ground truth of ``scene`` and whether it came from the cache.

    Returns
    -------
    image : ndarray, shape (H, W, 3), float64
        Linear RGB, row 0 at the top.
    hit : bool
        True when the image was read from the cache (nothing was rendered).
    """
    from aaeval.groundtruth import mitsuba as gt

    if not cache:
        return gt.render_mitsuba(scene, spp=spp, sampler=sampler, seed=seed, variant=variant), False
    path = groundtruth_path(scene, spp=spp, sampler=sampler, seed=seed)
    image = _read(path, scene.shape)
    if image is not None:
        return image, True
    image = gt.render_mitsuba(scene, spp=spp, sampler=sampler, seed=seed, variant=variant)
    atomic_write(path, lambda tmp: np.save(tmp, image))
    _write_note(path, scene, spp=spp, sampler=sampler, seed=seed)
    return image, False


def _read(path: Path, shape: tuple[int, ...]) -> np.ndarray | None:
    try:
        image = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError):  # missing or unreadable: render it again
        return None
    # a file of the wrong shape cannot be this key's image: render again, overwrite it
    return image if image.shape == shape and image.dtype == np.float64 else None


def _write_note(path: Path, scene: Scene, **options) -> None:
    import mitsuba as mi

    note = {
        **options,
        "source": scene.source,
        "frame": scene.frame,
        "variant": mi.variant(),
        "mitsuba": _mitsuba_version(),
        "groundtruth": GROUNDTRUTH_VERSION,
    }
    atomic_write(path.with_suffix(".json"), lambda tmp: Path(tmp).write_text(json.dumps(note, indent=1) + "\n"))
