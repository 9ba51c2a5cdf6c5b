"""Pieces every chart of the report uses: titles placed without a layout engine, legends
beside the axes, images drawn opaque."""

from __future__ import annotations

import numpy as np

__all__ = ["suptitle", "placed_title", "opaque_rgba", "legend"]


def suptitle(fig, text: str, fontsize: float = 10) -> None:
    """A figure title just above the top row's titles (figures use no layout engine:
    constrained layout cost most of the report's time; the tight bounding box keeps it)."""
    top = max((ax.get_position().y1 for ax in fig.axes), default=1.0)
    fig.suptitle(text, y=top + 0.42 / fig.get_figheight(), va="bottom", fontsize=fontsize)


def placed_title(ax, text: str, **kw) -> None:
    """An axes title at its usual place, for an axes whose y axis is log, categorical or
    hidden. Matplotlib's automatic placement lays the y axis out once more per title, at
    every draw, to dodge an offset text above it; such an axis never shows one."""
    ax.set_title(text, y=1.0, **kw)


def opaque_rgba(srgb8: np.ndarray) -> np.ndarray:
    """uint8 sRGB as the float32 RGBA matplotlib turns it into (the same pixels): given
    uint8 RGB it resamples a float64 copy, a fifth of an image grid's drawing time."""
    rgba = np.empty(srgb8.shape[:2] + (4,), np.float32)
    np.divide(srgb8, np.float32(255), out=rgba[..., :3], dtype=np.float32)
    rgba[..., 3] = 1.0
    return rgba


def legend(ax, *, outside: bool = True, **kw) -> None:
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    if outside:
        ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0, **kw)
    else:
        ax.legend(handles, labels, **kw)
