"""Writing images: ``.npy`` (float64 linear RGB), ``.exr`` (float32 linear), ``.png`` (8-bit sRGB).

Every write goes to a temporary file beside the target and is moved into place only when
complete, so a failed run never leaves a half-written image or clobbers an earlier one.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aaeval.fileio import OutputError, atomic_write, check_outputs, linear_to_srgb8, srgb_to_linear

__all__ = ["save_image", "load_image", "linear_to_srgb8", "srgb_to_linear", "atomic_write", "check_outputs",
           "OutputError", "SUFFIXES"]

SUFFIXES = (".npy", ".exr", ".png")


def save_image(path: str | Path, image: np.ndarray) -> Path:
    """Save an (H, W, 3) linear RGB image; the format follows the suffix."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise ValueError(f"{path}: unknown image suffix {path.suffix!r}; use one of {', '.join(SUFFIXES)}")
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an (H, W, 3) image, got shape {image.shape}")
    if suffix == ".npy":
        return atomic_write(path, lambda tmp: np.save(tmp, image.astype(np.float64)))
    if suffix == ".png":
        from PIL import Image

        return atomic_write(path, lambda tmp: Image.fromarray(linear_to_srgb8(image), "RGB").save(tmp, format="PNG"))
    return atomic_write(path, lambda tmp: _write_exr(tmp, image))


def _mitsuba():
    # Mitsuba's variant is process-global and Dr.Jit reads its libLLVM path once: import
    # it the one way aaeval does, keeping any variant already set (Bitmap works in all).
    from aaeval.mitsuba_variant import import_mitsuba

    return import_mitsuba(variant=None)


def _write_exr(path: str, image: np.ndarray) -> None:
    mi = _mitsuba()
    bitmap = mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32), mi.Bitmap.PixelFormat.RGB)
    bitmap.write(str(path), mi.Bitmap.FileFormat.OpenEXR)


def load_image(path: str | Path) -> np.ndarray:
    """Load an image written by :func:`save_image` as float64 (PNG decoded to linear)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        return np.load(path)
    if suffix == ".png":
        from PIL import Image

        return srgb_to_linear(np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0)
    if suffix == ".exr":
        mi = _mitsuba()
        return np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]
    raise ValueError(f"{path}: unknown image suffix {path.suffix!r}")
