"""Cost of the ``cvvdp`` temporal metric (ColorVideoVDP on the CPU) per sweep cell.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_cvvdp.py [--repeats N] [--sizes 24,64,256] [--frames F]``

One cell of a sweep's temporal table is one call on a method's frames against the
reference's. For each size the model is warmed up (loading its tables, the first pyramid),
then timed ``--repeats`` times on a drifting soft bar with popping; the median and the
fastest wall time and the median process CPU time are printed (the metric runs PyTorch on
one thread).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from aaeval.metrics.video import cvvdp


def animation(size: int, frames: int) -> tuple[np.ndarray, np.ndarray]:
    x = np.arange(size) + 0.5
    truth = np.array([0.1 + 0.4 * np.clip(1.0 - np.abs(x - size / 2 - 0.15 * t) / 3.0, 0.0, 1.0)
                      for t in range(frames)])
    truth = np.repeat(truth[:, None, :, None], size, axis=1).repeat(3, axis=3)
    alternate = np.where(np.arange(frames) % 2 == 0, 1.0, -1.0)[:, None, None, None]
    return truth, truth * (1.0 + 0.2 * alternate)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sizes", default="24,64,256")
    parser.add_argument("--frames", type=int, default=16)
    args = parser.parse_args(argv)
    import torch

    print(f"torch {torch.__version__}")
    for size in (int(s) for s in args.sizes.split(",")):
        truth, test = animation(size, args.frames)
        cvvdp(truth, test)  # warm-up
        wall, cpu = [], []
        for _ in range(args.repeats):
            w, c = time.perf_counter(), time.process_time()
            jod = cvvdp(truth, test)
            wall.append(time.perf_counter() - w)
            cpu.append(time.process_time() - c)
        print(f"{size}x{size} x {args.frames} frames: median {statistics.median(wall):.2f} s, fastest "
              f"{min(wall):.2f} s wall, {statistics.median(cpu):.2f} s CPU; {jod:.3f} JOD")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
