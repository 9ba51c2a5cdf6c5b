"""Writing the report's figures: each as PNG (for the page), SVG and PDF (for a paper),
drawn in worker processes while the parent reads the sweep and writes the page.

The chart functions of :mod:`aaeval.report.figures` are decorated with :func:`figure` and
end in :func:`save`; :func:`drawing` opens the workers for a report and waits for them.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import inspect
import math
import multiprocessing
import os
import traceback
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import font_manager  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402

from aaeval.fileio import atomic_write  # noqa: E402

__all__ = ["FORMATS", "DPI", "drawing", "figure", "save", "twin_formats", "write_png"]

#: The formats a figure can be written in: the page shows the PNG; SVG and PDF are for papers.
FORMATS = ("png", "svg", "pdf")
DPI = 100
#: The matplotlib backend writing each paper format, imported before the workers fork so that
#: each of them does not import it again (PDF's, with fontTools' subsetter, takes half a second).
_BACKENDS = {"svg": "matplotlib.backends.backend_svg", "pdf": "matplotlib.backends.backend_pdf"}


def save(fig, path: Path) -> Path:
    """Write the figure as ``path`` with suffix ``.png`` (what the page shows), and its twins
    in the other formats of :func:`drawing`; close it; return the PNG path. Inside
    :func:`drawing` a worker process writes the files."""
    path = Path(path).with_suffix(".png")
    if _workers.executor is not None:
        _workers.submit(path, _write_files, fig, path)
    else:
        _write_files(fig, path)
    plt.close(fig)
    return path


def twin_formats() -> tuple[str, ...]:
    """The formats besides PNG that :func:`save_figure` writes now (for the page's links)."""
    return tuple(f for f in _workers.formats if f != "png")



def _write_files(fig, path: Path) -> None:
    box = write_png(fig, path)
    for fmt in _workers.formats:
        if fmt != "png":
            # a temporary file moved into place: a link planted at the name is replaced, never written through
            atomic_write(path.with_suffix(f".{fmt}"),
                         lambda tmp, fmt=fmt: fig.savefig(tmp, format=fmt, dpi=DPI, bbox_inches=box,
                                                          metadata=_metadata(fmt)))



#: Room drawn beside and above/below a figure (inches, whole pixels at :data:`DPI`) for what
#: lies outside it: legends beside the axes, long tick labels, titles above.
_ROOM = (4.0, 2.0)


def write_png(fig, path: Path):
    """Write ``path``, the PNG of ``fig``'s tight box, drawing the figure once; return the box
    (inches, with savefig's pad), for the other formats.

    ``savefig(bbox_inches=box)`` lays every text out twice: once to find the box, once more
    for the canvas of the box's size. Here the figure is drawn once on a canvas with
    :data:`_ROOM` around it, the box is measured with the renderer that drew it (its text
    extents cached), widened to whole pixels, and cut out: the same pixels savefig draws
    for the widened box (hatching aside: its pattern starts at the canvas' corner). Where
    the figure reaches beyond the room, savefig draws the box."""
    # a figure sent to a worker comes without pyplot's canvas
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    fig.set_dpi(DPI)
    width, height = fig.get_size_inches()
    across, up = _ROOM
    fig.savefig(os.devnull, format="raw", dpi=DPI,  # the pixels are read from the renderer that drew
                bbox_inches=Bbox.from_extents(-across, -up, width + across, height + up))
    renderer = canvas.renderer
    box = fig.get_tightbbox(renderer).padded(plt.rcParams["savefig.pad_inches"])
    x0, y0 = math.floor(box.x0 * DPI), math.floor(box.y0 * DPI)
    x1, y1 = math.ceil(box.x1 * DPI), math.ceil(box.y1 * DPI)
    top, left = renderer.height - round(up * DPI) - y1, round(across * DPI) + x0  # Agg's rows run downwards
    if min(top, left) >= 0 and left + x1 - x0 <= renderer.width and top + y1 - y0 <= renderer.height:
        cut = np.asarray(renderer.buffer_rgba())[top:top + y1 - y0, left:left + x1 - x0]
        atomic_write(path, lambda tmp: matplotlib.image.imsave(tmp, cut, format="png", origin="upper", dpi=DPI,
                                                                metadata=_metadata("png")))
    else:
        widened = Bbox.from_extents(x0 / DPI, y0 / DPI, x1 / DPI, y1 / DPI)
        atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=DPI, bbox_inches=widened,
                                                   metadata=_metadata("png")))
    return box



def _metadata(fmt: str) -> dict:
    # no creation dates: the same data gives the same files
    return {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[fmt]



class _Workers:
    """Processes forked once per report that build and write the figures while the parent
    reads the sweep and writes the page: building and drawing are most of the report's time.
    They live for the whole report, so matplotlib's caches (fonts, text extents) serve
    every figure, and the parent's memory is not copied again for each one. Each file is
    written by one process, so the output is the same as drawing them in turn."""

    def __init__(self):
        self.executor: ProcessPoolExecutor | None = None
        self.formats: tuple[str, ...] = ("png",)
        self.jobs: list[tuple[Path, Future]] = []

    def open(self, count: int, formats: tuple[str, ...]) -> None:
        self.formats = formats
        if count:
            for fmt in formats:
                if fmt in _BACKENDS:
                    importlib.import_module(_BACKENDS[fmt])  # forked at the first job, with what the parent holds then
            self.executor = ProcessPoolExecutor(count, mp_context=multiprocessing.get_context("fork"),
                                                initializer=_in_worker)

    def submit(self, path: Path, work, *args, **kwargs) -> None:
        self.jobs.append((path, self.executor.submit(_job, work, args, kwargs)))

    def close(self, check: bool = True) -> None:
        """Wait for the jobs (``check=False``: for the running ones only, the queued ones are
        dropped) and raise if one failed."""
        executor, jobs = self.executor, self.jobs
        self.executor, self.formats, self.jobs = None, ("png",), []
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=not check)
        failed = []
        for path, job in jobs:
            if job.cancelled():
                continue
            if job.exception() is not None:  # never ran: its arguments would not pickle, or a worker died
                traceback.print_exception(job.exception())
            if job.exception() is not None or not job.result():
                failed.append(path)
        if failed and check:
            raise RuntimeError(f"drawing {', '.join(p.name for p in failed)} failed (its error is printed above)")


def _in_worker() -> None:
    _workers.executor = None  # a worker draws its figures itself


def _job(work, args, kwargs) -> bool:
    """Run one figure's work in a worker; its error is printed there (the parent names the figure)."""
    try:
        work(*args, **kwargs)
    except BaseException:  # noqa: BLE001 - reported to the parent as a failed figure
        traceback.print_exc()
        return False
    return True


_workers = _Workers()


def figure(draw):
    """A figure function ``draw(..., path, ...)``: inside :func:`drawing` the whole call,
    building the figure as well as writing it, runs in a worker process (its arguments
    are sent there), and the PNG's path is returned at once."""
    signature = inspect.signature(draw)

    @functools.wraps(draw)
    def call(*args, **kwargs):
        if _workers.executor is None:
            return draw(*args, **kwargs)
        path = Path(signature.bind(*args, **kwargs).arguments["path"]).with_suffix(".png")
        _workers.submit(path, call, *args, **kwargs)  # by its module name: the worker runs it itself
        return path

    return call


@contextlib.contextmanager
def drawing(formats=FORMATS):
    """Within this block the figure functions and :func:`save_figure` write ``formats``
    (PNG always, for the page; SVG and PDF, for papers, cost most of the drawing time: PDF
    subsets its fonts) in worker processes, as many as the cores this process may use (none where
    ``os.fork`` is missing); leaving it waits for them all and raises if one failed."""
    unknown = set(formats) - set(FORMATS)
    if unknown:
        raise ValueError(f"unknown figure format(s) {', '.join(sorted(unknown))}; known: {', '.join(FORMATS)}")
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    _workers.open(cores if hasattr(os, "fork") and cores > 1 else 0,
                  tuple(f for f in FORMATS if f in formats or f == "png"))
    with contextlib.ExitStack() as stack:
        if "pdf" in formats:
            from aaeval.report import pdf_fonts  # fontTools' subsetter: only for a report writing PDFs

            pdf_fonts.prepare_base(font_manager.findfont(font_manager.FontProperties()))  # once, shared by the workers
            stack.enter_context(pdf_fonts.subsets_from_base())
        try:
            yield
        except BaseException:
            _workers.close(check=False)  # the body's error is the one to see
            raise
        _workers.close()
