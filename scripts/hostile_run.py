#!/usr/bin/env python3
"""Hostile run of aaeval's surfaces: plugins, the report's files, fonts, configs, tampered
sweep folders, Dask (in-process and as deployed: ``dask scheduler`` and ``dask worker`` as
separate processes, frozen and killed mid-sweep), the Python API's arguments, the budgets a
user chooses and far frames of phased animations, as an attacker or an unlucky user would
try them.

    python3 scripts/hostile_run.py [--only CATEGORY ...] [--json FILE]

Every case runs ``aaeval`` (in this process through ``aaeval.cli.main``, or in a subprocess
where a case may kill its process: FreeType on a damaged font, worker deaths) under a time
limit, and is counted by what went wrong:

- ``traceback``: an exception escaped the command, or "Traceback" reached its output;
- ``hang``: the case ran past its time limit;
- ``outside``: a file outside the sweep folder changed (a canary folder, and the targets of
  planted links, are hashed before and after every case);
- ``rows``: a sweep folder that after the case lost or doubled a row (``results.parquet``
  against the cells the config plans);
- ``exit``: an exit code the case does not allow (a refusal is 2, a finished command 0);
- ``memory``: a case run with a peak check held more than :data:`PEAK_LIMIT` resident.

All six must be 0. The counts and any failing case are printed; ``--json`` writes them.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import random
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import _thread
from collections import Counter
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
# the test modules whose fixtures the cases reuse, in the folders of the package they test
for _folder in ("plugins", "importers", "report", "sweeps", "studies"):
    sys.path.insert(0, str(ROOT / "tests" / _folder))

from aaeval.cli import main  # noqa: E402

CATEGORIES = ("plugins", "fonts", "configs", "store", "cache", "report", "studies", "dask", "api", "budgets", "phases",
              "deployed")
PROBLEMS = ("traceback", "hang", "outside", "rows", "exit", "memory")

# A case run with ``peak=`` is a memory blow-up past this many bytes of resident memory.
PEAK_LIMIT = 1 << 30
# Run ``python -m aaeval`` and write the process's peak resident bytes to $HOSTILE_PEAK_FILE at exit.
_PEAK_WRAPPER = """
import atexit, os, resource, runpy, sys
atexit.register(lambda: open(os.environ["HOSTILE_PEAK_FILE"], "w").write(
    str(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)))
sys.argv = ["aaeval", *sys.argv[1:]]
runpy.run_module("aaeval", run_name="__main__")
"""


class Run:
    def __init__(self, work: Path):
        self.work = work
        self.canary = work / "canary"
        self.canary.mkdir()
        for i in range(3):
            (self.canary / f"victim{i}.txt").write_text(f"outside the folder {i}\n")
        self.cases: list[dict] = []

    def snapshot(self) -> str:
        h = hashlib.sha256()
        for p in sorted(self.canary.rglob("*")):
            h.update(str(p).encode())
            if p.is_file() and not p.is_symlink():
                h.update(p.read_bytes())
        return h.hexdigest()

    def record(self, category: str, name: str, problems: list[str], detail: str = "") -> None:
        self.cases.append({"category": category, "name": name, "problems": problems, "detail": detail[:400]})
        mark = "ok" if not problems else "FAIL " + ",".join(problems)
        print(f"[{category}] {name}: {mark}" + (f" ({detail[:200]})" if problems else ""), flush=True)

    def cli(self, category: str, name: str, argv: list[str], *, allowed=(2,), timeout: float = 60,
            check=None, cwd: Path | None = None) -> tuple[int | None, str, str]:
        """``aaeval ARGV`` in this process under a watchdog; counted as one case."""
        before = self.snapshot()
        out, err = io.StringIO(), io.StringIO()
        fired = threading.Event()

        def bark():
            fired.set()
            _thread.interrupt_main()

        dog = threading.Timer(timeout, bark)
        problems, code, detail = [], None, ""
        old = os.getcwd()
        try:
            if cwd:
                os.chdir(cwd)
            dog.start()
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                code = main(argv)
        except SystemExit as exc:  # argparse refusing an option
            code = exc.code if isinstance(exc.code, int) else 2
        except KeyboardInterrupt:
            pass
        except BaseException as exc:  # noqa: BLE001 - the thing being counted
            import traceback

            problems.append("traceback")
            detail = "".join(traceback.format_exception_only(type(exc), exc)).strip()
        finally:
            dog.cancel()
            os.chdir(old)
        if fired.is_set():
            problems.append("hang")
        text = out.getvalue() + err.getvalue()
        if "Traceback" in text and "traceback" not in problems:
            problems.append("traceback")
            detail = text[-400:]
        if not problems and code not in allowed:
            problems.append("exit")
            detail = f"exit {code}: {err.getvalue().strip()[-300:]}"
        if code == 2 and not problems and len(err.getvalue().strip().splitlines()) > 1 and "error:" in err.getvalue():
            # a refusal is one line (warnings of a healed folder may come before it)
            lines = [ln for ln in err.getvalue().strip().splitlines() if "error:" in ln]
            if len(lines) != 1:
                problems.append("exit")
                detail = "refusal not one line: " + err.getvalue()[-300:]
        if self.snapshot() != before:
            problems.append("outside")
        if check is not None and not problems:
            extra = check(code, out.getvalue(), err.getvalue())
            if extra:
                problems.append(extra[0])
                detail = extra[1]
        self.record(category, name, problems, detail or err.getvalue().strip()[-200:])
        return code, out.getvalue(), err.getvalue()

    def sub(self, category: str, name: str, args: list[str], *, allowed=(2,), timeout: float = 120,
            env: dict | None = None, cwd: Path | None = None, check=None, peak: bool = False,
            command: list[str] | None = None) -> subprocess.CompletedProcess | None:
        """``python -m aaeval ARGS`` (or ``command``) in a subprocess (the case may kill its
        process); with ``peak``, its peak resident memory past :data:`PEAK_LIMIT` is a
        ``memory`` problem."""
        before = self.snapshot()
        full = {**os.environ, **(env or {})}
        full["PYTHONPATH"] = os.pathsep.join(p for p in [full.get("EXTRA_PYTHONPATH", ""), str(ROOT),
                                                         full.get("PYTHONPATH", "")] if p)
        peak_file = self.work / "peak.txt"
        peak_file.unlink(missing_ok=True)
        full["HOSTILE_PEAK_FILE"] = str(peak_file)
        argv = command or ([sys.executable, "-c", _PEAK_WRAPPER, *args] if peak else
                           [sys.executable, "-m", "aaeval", *args])
        problems, detail, done = [], "", None
        try:
            done = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=full, cwd=cwd)
        except subprocess.TimeoutExpired:
            problems.append("hang")
        if peak and peak_file.exists() and int(peak_file.read_text() or 0) > PEAK_LIMIT:
            problems.append("memory")
            detail = f"peak resident memory {int(peak_file.read_text()) / 2**30:.2f} GiB"
        if done is not None:
            if "Traceback" in done.stdout + done.stderr:
                problems.append("traceback")
                detail = done.stderr[-400:]
            elif done.returncode not in allowed:
                problems.append("exit")
                detail = f"exit {done.returncode}: {done.stderr.strip()[-300:]}"
            elif check is not None:
                extra = check(done)
                if extra:
                    problems.append(extra[0])
                    detail = extra[1]
        if self.snapshot() != before:
            problems.append("outside")
        self.record(category, name, problems, detail)
        return done


# ---------------------------------------------------------------------------------- plugins

BAD_METHODS = {
    "raises": lambda scene: (_ for _ in ()).throw(KeyError("the plugin's own bug")),
    "none": lambda scene: None,
    "alist": lambda scene: [[0.0]],
    "flat": lambda scene: __import__("numpy").zeros(scene.width * scene.height),
    "wrongshape": lambda scene: __import__("numpy").zeros((scene.height, scene.width)),
    "integers": lambda scene: __import__("numpy").zeros(scene.shape, dtype="int64"),
    "complex": lambda scene: __import__("numpy").zeros(scene.shape, dtype=complex),
    "nan": lambda scene: __import__("numpy").full(scene.shape, float("nan")),
    "inf": lambda scene: __import__("numpy").full(scene.shape, -float("inf")),
    "huge": lambda scene: __import__("numpy").full(scene.shape, -1e300),
    "objects": lambda scene: __import__("numpy").full(scene.shape, None, dtype=object),
    "strings": lambda scene: __import__("numpy").full(scene.shape, "x"),
    "scalar": lambda scene: 0.5,
    "bool": lambda scene: __import__("numpy").zeros(scene.shape, dtype=bool),
    "exits_sys": lambda scene: sys.exit(3),
    "interrupt_like": lambda scene: (_ for _ in ()).throw(GeneratorExit()),
    "memory": lambda scene: (_ for _ in ()).throw(MemoryError()),
    "oserror": lambda scene: open("/nonexistent/dir/file"),
    "valueerror": lambda scene: (_ for _ in ()).throw(ValueError("x" * 100_000)),
}


def _recurse(scene):
    return _recurse(scene)


def plugins(run: Run) -> None:
    from aaeval.renderers import register_method

    for name, fn in BAD_METHODS.items():
        register_method(f"hostile-{name}", summary=f"hostile: {name}", samples=lambda options: 1)(fn)
    register_method("hostile-recurses", summary="hostile: recursion", samples=lambda options: 1)(_recurse)
    names = [*BAD_METHODS, "recurses"]
    fan = ROOT / "configs" / "scenes" / "fan.toml"
    folder = run.work / "plugins"
    folder.mkdir()
    for name in names:
        out = folder / f"{name}.png"
        run.cli("plugins", f"render {name}", ["render", str(fan), "-m", f"hostile-{name}", "-o", str(out)],
                allowed=(2,), check=lambda c, o, e, out=out: ("exit", "an image was written") if out.exists() else None)
    for name in names:
        run.cli("plugins", f"compare {name}", ["compare", str(fan), "--method", f"hostile-{name}", "--method", "point",
                                                 "--reference", "catmull"], allowed=(1,))
    for name in names:
        cfg = folder / f"sweep_{name}.toml"
        cfg.write_text(f"""
[experiment]
name = "p"
reference = "catmull"
metrics = ["rmse"]
temporal = []
fail_above = 0.5
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = [0.1], frames = 1, size = 8}}]
methods = ["hostile-{name}", "point"]
""")
        out = folder / f"out_{name}"

        def rows(code, o, e, out=out):
            import pandas as pd

            table = pd.read_parquet(out / "results.parquet")
            if len(table) != 2 or table["key"].duplicated().any():
                return "rows", f"{len(table)} rows"
            bad = table[table["spec"] == f"hostile-{name}"]
            if bad["error"].isna().all():
                return "exit", "the hostile cell was not recorded as failed"
            if "(1 failed)" not in o:
                return "exit", o[-200:]
            return None

        run.cli("plugins", f"sweep {name}", ["sweep", str(cfg), "--out", str(out), "--workers", "1", "--quiet"],
                allowed=(3,), check=rows, timeout=120)
    _worker_deaths(run, folder)


DEATH_PLUGIN = '''
import os, signal, time
import numpy as np
from aaeval.renderers import register_method

@register_method("h-sleepy", summary="sleeps")
def sleepy(scene):
    time.sleep(300)

@register_method("h-exits", summary="os._exit")
def exits(scene):
    os._exit(3)

@register_method("h-segv", summary="SIGSEGV")
def segv(scene):
    os.kill(os.getpid(), signal.SIGSEGV)
    time.sleep(5)

@register_method("h-killed", summary="SIGKILL, as the OOM killer would")
def killed(scene):
    os.kill(os.getpid(), signal.SIGKILL)
    time.sleep(5)
'''


def _worker_deaths(run: Run, folder: Path) -> None:
    from tests.helpers.plugin_util import fake_install

    site = folder / "site"
    site.mkdir()
    (site / "hostile_death.py").write_text(DEATH_PLUGIN)
    fake_install(site, "hostile-death", {"aaeval.methods": {n: "hostile_death" for n in
                                                            ("h-sleepy", "h-exits", "h-segv", "h-killed")}})
    env = {"EXTRA_PYTHONPATH": str(site), "AAEVAL_MAX_SECONDS": "10"}
    for method, frames in (("h-exits", 3), ("h-segv", 3), ("h-killed", 3), ("h-sleepy", 1)):
        cfg = folder / f"{method}.toml"
        cfg.write_text(f"""
[experiment]
name = "d"
reference = "catmull"
metrics = ["rmse"]
temporal = []
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = [0.1], frames = {frames}, size = 8}}]
methods = ["{method}", "point"]
""")
        out = folder / f"out_{method}"

        def check(done, out=out, frames=frames, method=method):
            import pandas as pd

            table = pd.read_parquet(out / "results.parquet")
            if len(table) != 2 * frames or table["key"].duplicated().any():
                return "rows", f"{len(table)} rows of {2 * frames}"
            if not table[table["spec"] == "point"]["error"].isna().all():
                return "exit", "a point cell failed"
            if table[table["spec"] == method]["error"].isna().any():
                return "exit", "a dying cell was not recorded as failed"
            return None

        start = time.monotonic()
        run.sub("plugins", f"sweep 2 workers {method}", ["sweep", str(cfg), "--out", str(out), "--workers", "2",
                                                          "--quiet"], allowed=(3,), env=env, timeout=150, check=check)
        print(f"    ({time.monotonic() - start:.1f} s)", flush=True)


# ---------------------------------------------------------------------------------- fonts

def _dejavu() -> bytes:
    from aaeval.importers.text import DEFAULT_FONT
    from aaeval.scenes.sources import font_path

    return font_path(".", DEFAULT_FONT).read_bytes()


def fonts(run: Run) -> None:
    from test_fonts_damaged import _table_dir, damaged_fonts

    folder = run.work / "fonts"
    folder.mkdir()
    named = damaged_fonts()
    for name, (data, word) in named.items():
        (folder / name).write_bytes(data)
        run.cli("fonts", f"import {name}", ["import", "text", "Hello 0123", "--font", name, "-o", "x.toml"],
                cwd=folder, check=lambda c, o, e, word=word: None if word in e else ("exit", e[-200:]))
    data = _dejavu()
    rng = random.Random(36)
    tables = _table_dir(data)
    mutated = {}
    for k in range(24):  # bytes of one table overwritten with noise
        tag = rng.choice(sorted(tables))
        _, off, length = tables[tag]
        b = bytearray(data)
        n = min(length, rng.choice([4, 16, 64, 512]))
        start = off + rng.randrange(max(1, length - n + 1))
        b[start:start + n] = bytes(rng.randrange(256) for _ in range(n))
        mutated[f"noise-{tag.strip().replace('/', '_')}-{k}.ttf"] = bytes(b)
    for k in range(16):  # a directory entry's offset or length set wild
        tag = rng.choice(sorted(tables))
        pos, off, length = tables[tag]
        b = bytearray(data)
        if k % 2:
            struct.pack_into(">I", b, pos + 8, rng.choice([0, len(data) - 1, len(data) + 7, 0xFFFFFFF0]))
        else:
            struct.pack_into(">I", b, pos + 12, rng.choice([0, 1, len(data), 0xFFFFFFF0]))
        mutated[f"dir-{tag.strip().replace('/', '_')}-{k}.ttf"] = bytes(b)
    for k, cut in enumerate((12, 100, 1000, len(data) // 2, len(data) - 1)):
        mutated[f"cut-{k}.ttf"] = data[:cut]
    mutated["empty.ttf"] = b""
    mutated["text.ttf"] = b"this is not a font\n" * 100
    mutated["woff2-real-magic.woff2"] = b"wOF2" + bytes(100)
    mutated["otto.otf"] = b"OTTO" + data[4:]
    mutated["ttc.ttc"] = b"ttcf" + data[4:]
    for name, blob in mutated.items():
        (folder / name).write_bytes(blob)
        run.cli("fonts", f"import {name}", ["import", "text", "Hello 0123", "--font", name, "-o", f"{name}.toml"],
                cwd=folder, allowed=(0, 2))
    # WOFF is read
    from fontTools.ttLib import TTFont

    font = TTFont(io.BytesIO(data))
    font.flavor = "woff"
    font.save(str(folder / "f.woff"))
    run.cli("fonts", "import f.woff", ["import", "text", "Hi 01", "--font", "f.woff", "-o", "w.toml"], cwd=folder,
            allowed=(0,))
    # the freetype method, in subprocesses (FreeType is native code)
    assert main(["import", "text", "Hi 01", "-o", str(folder / "good.toml")]) == 0
    text = (folder / "good.toml").read_text()
    pick = [*named, "f.woff", *rng.sample(sorted(mutated), 10)]
    for name in pick:
        scene = folder / f"scene-{name}.toml"
        scene.write_text(text.replace('font = "matplotlib:DejaVuSans.ttf"', f'font = "{name}"'))
        run.sub("fonts", f"freetype {name}", ["render", str(scene), "-m", "freetype", "-o", str(folder / f"{name}.png")],
                allowed=(0, 2) if name not in named else (2,), timeout=60)


# ---------------------------------------------------------------------------------- configs

CONFIG = """
[experiment]
name = "c"
reference = "catmull"
metrics = ["rmse"]
temporal = []
{head}
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = {levels}, frames = {frames}, size = 8}}]
methods = {methods}
{group}
"""


def configs(run: Run) -> None:
    folder = run.work / "configs"
    folder.mkdir()
    base = {"head": "", "levels": "[0.1]", "frames": "2", "methods": '["point"]', "group": ""}
    cases = {
        "repeats 1e9": {"head": "repeats = 1000000000"},
        "repeats float": {"head": "repeats = 1e9"},
        "repeats 0": {"head": "repeats = 0"},
        "repeats -1": {"head": "repeats = -1"},
        "repeats text": {"head": 'repeats = "5"'},
        "repeats bool": {"head": "repeats = true"},
        "repeats 1001": {"head": "repeats = 1001"},
        "fail_above nan": {"head": "fail_above = nan"},
        "fail_above inf": {"head": "fail_above = inf"},
        "fail_above -1": {"head": "fail_above = -1"},
        "fail_above 0": {"head": "fail_above = 0"},
        "fail_above text": {"head": 'fail_above = "0.1"'},
        "max_seconds 0": {"head": "max_seconds = 0"},
        "max_seconds nan": {"head": "max_seconds = nan"},
        "max_seconds inf": {"head": "max_seconds = inf"},
        "max_seconds 1e9": {"head": "max_seconds = 1e9"},
        "max_seconds text": {"head": 'max_seconds = "60"'},
        "noise_estimate text": {"head": 'noise_estimate = "yes"'},
        "unknown key": {"head": "surprise = 1"},
        "primary unknown": {"head": 'primary = "nope"'},
        "metric unknown": {"head": 'metrics = ["nope"]'.replace("metrics", "primary = \"rmse\"\nmetrics_x")},
        "frames 1e6 list": {"group": "frames = [" + ", ".join(map(str, range(1_000_000))) + "]", "frames": "100000"},
        "frames repeated": {"group": "frames = [0, 0, 1]"},
        "frames outside": {"group": "frames = [0, 5]"},
        "frames negative": {"group": "frames = [-1]"},
        "frames floats": {"group": "frames = [0.5]"},
        "frames empty": {"group": "frames = []"},
        "frames text": {"group": 'frames = "some"'},
        "frames nested": {"group": "frames = [[0]]"},
        "ladder 1e5": {"levels": "[" + ", ".join(str(i * 1e-6) for i in range(1, 100_001)) + "]"},
        "ladder repeated": {"levels": "[0.1, 0.1]"},
        "ladder text": {"levels": '["hard"]'},
        "ladder nan": {"levels": "[nan]"},
        "ladder inf": {"levels": "[inf]"},
        "ladder empty": {"levels": "[]"},
        "ladder tables": {"levels": "[{a = 1}]"},
        "size huge": {"levels": "[0.1]", "group": ""},
        "method unknown": {"methods": '["nope"]'},
        "method option bad": {"methods": '["supersample:k=-1"]'},
        "method option huge": {"methods": '["supersample:k=100000"]'},
        "methods repeated": {"methods": '["point", "point"]'},
        "methods empty": {"methods": "[]"},
        "methods text": {"methods": '"point"'},
        "options text": {"group": 'options = "x"'},
        "options nan": {"group": "options = { spp = [nan] }"},
        "animate bad": {"group": 'animate = { frames = -1, translate = [0, 0] }'},
        "animate huge": {"group": 'animate = { frames = 100000000, translate = [0, 0] }'},
        "cells 300k": {"frames": "100000", "methods": '["supersample:k=1", "supersample:k=2", "supersample:k=3"]'},
    }
    for name, change in cases.items():
        values = {**base, **change}
        if name == "size huge":
            text = CONFIG.format(**values).replace("size = 8", "size = 100000000")
        else:
            text = CONFIG.format(**values)
        cfg = folder / f"{name.replace(' ', '_')}.toml"
        cfg.write_text(text)
        run.cli("configs", name, ["sweep", str(cfg), "--out", str(folder / "out"), "--dry-run"], allowed=(2,),
                timeout=30, check=lambda c, o, e: ("exit", f"{len(e)}-character error") if len(e) > 1500 else None)
    raw = {
        "toml nested 2000": "[experiment]\nname = " + "[" * 2000 + "]" * 2000 + "\n",
        "toml nested tables": "x = " + "{a = " * 1500 + "1" + "}" * 1500 + "\n",
        "toml binary": "\x00\x01\x02 garbage",
        "toml invalid utf8": None,
        "toml empty": "",
        "toml huge string": '[experiment]\nname = "' + "x" * 5_000_000 + '"\n',
        "toml no groups": '[experiment]\nname = "x"\nreference = "catmull"\n',
        "toml groups table": '[experiment]\nname = "x"\nreference = "catmull"\n[groups]\nname = "g"\n',
        "toml speed text": CONFIG.format(**base) + 'speed = "fast"\n',
        "toml speed huge": CONFIG.format(**base).replace('temporal = []', 'temporal = []\nmax_seconds = 1') +
        '[[speed]]\nscenes = [{generator = "edges", difficulty = [0.1], size = 2048, frames = 1}]\n'
        'methods = ["supersample:k=8"]\nrepeats = 1000\n',
        "toml speed small": CONFIG.format(**base) + '[[speed]]\nscenes = [{generator = "edges", difficulty = [0.1], '
        'size = 8}]\nmethods = ["point"]\n',
    }
    for name, text in raw.items():
        cfg = folder / f"{name.replace(' ', '_')}.toml"
        if text is None:
            cfg.write_bytes(b'[experiment]\nname = "\xff\xfe"\n')
        else:
            cfg.write_text(text)
        run.cli("configs", name, ["sweep", str(cfg), "--out", str(folder / "out"), "--dry-run"], allowed=(2,),
                timeout=30, check=lambda c, o, e: ("exit", f"{len(e)}-character error") if len(e) > 1500 else None)
    for name, value in (("env max_seconds text", "soon"), ("env max_seconds 0", "0"), ("env max_seconds -5", "-5")):
        cfg = folder / "env.toml"
        cfg.write_text(CONFIG.format(**base))
        os.environ["AAEVAL_MAX_SECONDS"] = value
        try:
            run.cli("configs", name, ["sweep", str(cfg), "--out", str(folder / f"out_{value}"), "--workers", "1",
                                      "--quiet"], allowed=(2,), timeout=60)
        finally:
            del os.environ["AAEVAL_MAX_SECONDS"]


# ---------------------------------------------------------------------------------- store

def _cache_sweep() -> str:
    """The config the cache cases damage a finished sweep of: ``SMALL`` (tests/helpers/
    sweep_util.py) with only its group of three still cells. Every case reruns the whole
    sweep from its damaged cache; the reference cache is read the same way for any group,
    and SMALL's nine cells (two groups, an animation) cost twice the time for the same reads."""
    from tests.helpers.sweep_util import SMALL

    head, *groups = SMALL.split("[[groups]]")
    (still,) = [g for g in groups if 'name = "stability"' in g]
    return head + "[[groups]]" + still


CACHE_SWEEP_CELLS = 3


def _finished(work: Path, config: str | None = None, name: str = "finished") -> Path:
    """A finished sweep of ``config`` (``SMALL`` of tests/helpers/sweep_util.py by default)
    in ``work/name``, with its own reference cache."""
    from tests.helpers.sweep_util import SMALL

    base = work / name
    base.mkdir()
    (base / "exp.toml").write_text(SMALL if config is None else config)
    assert main(["sweep", str(base / "exp.toml"), "--out", str(base / "out"), "--workers", "1", "--quiet",
                 "--cache", str(base / "cache")]) == 0
    return base


def _copy(base: Path, dest: Path) -> Path:
    shutil.copytree(base, dest, symlinks=True)
    return dest


BAD_VALUES = [None, "text", 7, 1.5, True, [1], {"a": 1}, float("inf")]


def store(run: Run, base: Path) -> None:
    from aaeval.sweeps.record import RECORD_FIELDS

    n = 0
    rng = random.Random(5)
    for field in RECORD_FIELDS:
        for value in rng.sample(BAD_VALUES, 3):
            n += 1
            dest = _copy(base, run.work / f"store{n}")
            cells = sorted((dest / "out" / "cells").glob("*.json"))
            victim = cells[n % len(cells)]
            text = victim.read_text()
            record = json.loads(text)
            record[field] = value
            victim.write_text(json.dumps(record))
            _store_case(run, dest, f"{field} = {value!r}")
            shutil.rmtree(dest)
    import numpy as np

    for damage in ("complex", "shape", "sparse", "objects", "truncated", "int", "link", "fifo", "folder"):
        n += 1
        dest = _copy(base, run.work / f"store{n}")
        images = sorted((dest / "out" / "images").glob("*.npy"))
        image = images[0]
        if damage == "complex":
            np.save(image, np.zeros((12, 12, 3), dtype=complex))
        elif damage == "shape":
            np.save(image, np.zeros((13, 12, 3)))
        elif damage == "sparse":
            with open(image, "wb") as f:
                np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False,
                                                         "shape": (50_000, 50_000, 1)})
                f.truncate(f.tell() + 50_000 * 50_000 * 8)
        elif damage == "objects":
            np.save(image, np.full((12, 12, 3), None, dtype=object), allow_pickle=True)
        elif damage == "truncated":
            image.write_bytes(image.read_bytes()[:100])
        elif damage == "int":
            np.save(image, np.zeros((12, 12, 3), dtype=np.int64))
        elif damage == "link":
            image.unlink()
            os.symlink(run.canary / "victim0.txt", image)
        elif damage == "fifo":
            image.unlink()
            os.mkfifo(image)
        else:
            image.unlink()
            image.mkdir()
        _store_case(run, dest, f"image {damage}")
        shutil.rmtree(dest)
    manifest_damages = {
        "no experiment": lambda m: m.pop("experiment"),
        "experiment list": lambda m: m.update(experiment=["x"]),
        "metrics text": lambda m: m.update(metrics="rmse"),
        "cells numbers": lambda m: m.update(cells=[1, 2]),
        "cells no key": lambda m: [c.pop("key") for c in m["cells"]],
        "frame text": lambda m: [c.update(frame="0") for c in m["cells"]],
        "fail_above nan": lambda m: m.update(fail_above=float("nan")),
        "scenes list": lambda m: m.update(scenes=[]),
        "group_temporal text": lambda m: m.update(group_temporal="x"),
        "not an object": None,
    }
    for name, damage in manifest_damages.items():
        n += 1
        dest = _copy(base, run.work / f"store{n}")
        path = dest / "out" / "manifest.json"
        if damage is None:
            path.write_text("[1, 2, 3]")
        else:
            manifest = json.loads(path.read_text())
            damage(manifest)
            path.write_text(json.dumps(manifest))
        run.cli("store", f"manifest {name} (report)", ["report", str(dest / "out"), "--quiet"], allowed=(2,),
                timeout=120)
        shutil.rmtree(dest)
    # a reference cache entry with non-finite metadata or another shape
    for name in ("noise inf", "shape"):
        n += 1
        dest = _copy(base, run.work / f"store{n}")
        cache = dest / "cache" / "references"
        meta = sorted(cache.glob("*.json"))[0]
        if name == "noise inf":
            meta.write_text('{"render_s": 0.1, "noise_rmse": Infinity, "intensity_sum": 1, "host": "h"}')
        else:
            np.save(meta.with_suffix(".npy"), np.zeros((3, 3, 3)))
        shutil.rmtree(dest / "out" / "references")
        _store_case(run, dest, f"reference cache {name}")
        shutil.rmtree(dest)


def _store_case(run: Run, dest: Path, name: str, category: str = "store", cells: int = 9) -> None:
    """Rerun the sweep on a tampered folder: it must heal (one cell or none to run again),
    keep its ``cells`` rows, none doubled; the table is rebuilt."""
    def rows(code, o, e):
        import pandas as pd

        table = pd.read_parquet(dest / "out" / "results.parquet")
        if len(table) != cells or table["key"].duplicated().any():
            return "rows", f"{len(table)} rows"
        if category == "cache" and "damaged reference cache entry" not in e:  # used as if sound: rows silently wrong
            return "rows", "the damaged cache entry was read as sound"
        return None

    run.cli(category, name, ["sweep", str(dest / "exp.toml"), "--out", str(dest / "out"), "--workers", "1", "--quiet",
                            "--cache", str(dest / "cache")], allowed=(0,), timeout=120, check=rows)


# ---------------------------------------------------------------------------------- cache

def _cache_note(note: Path, edit) -> None:
    data = json.loads(note.read_text())
    edit(data)
    note.write_text(json.dumps(data))


#: Damage to one reference cache entry: the rerun must name it, render it again and keep every row.
CACHE_DAMAGES = {
    "noise Infinity": lambda note, image: _cache_note(note, lambda d: d.update(noise_rmse="Infinity")),
    "noise bare Infinity": lambda note, image: note.write_text(note.read_text().replace(
        '"noise_rmse": ', '"noise_rmse": Infinity, "was": ', 1)),
    "noise 1e308": lambda note, image: _cache_note(note, lambda d: d.update(noise_rmse=1e308)),
    "noise text": lambda note, image: _cache_note(note, lambda d: d.update(noise_rmse="loud")),
    "noise list": lambda note, image: _cache_note(note, lambda d: d.update(noise_rmse=[1, 2])),
    "noise null": lambda note, image: _cache_note(note, lambda d: d.update(noise_rmse=None)),
    "strata text": lambda note, image: _cache_note(note, lambda d: d.update(noise_by_metric={"rmse": ["a", 0, 0]})),
    "strata negative": lambda note, image: _cache_note(note, lambda d: d.update(noise_by_metric={"rmse": [-1, 0, 0]})),
    "sum wrong": lambda note, image: _cache_note(note, lambda d: d.update(intensity_sum=12345.0)),
    "field missing": lambda note, image: _cache_note(note, lambda d: d.pop("host")),
    "note not json": lambda note, image: note.write_text("{"),
    "nan image": lambda note, image: np.save(image, np.full(np.load(image).shape, np.nan)),
    "image of another shape": lambda note, image: np.save(image, np.zeros((3, 3, 3))),
    "image header claims 3.5 GB": lambda note, image: _huge_header(image),
    "image a FIFO": lambda note, image: (image.unlink(), os.mkfifo(image)),
    "note a link outside": lambda note, image: (note.unlink(), os.symlink("/etc/hostname", note)),
}


def _huge_header(image: Path) -> None:
    with open(image, "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False, "shape": (12000, 12000, 3)})
        f.write(b"\0" * 4096)


def cache(run: Run, base: Path) -> None:
    """The reference cache read as input: each damaged entry is named, rendered again and
    replaced (the rerun keeps every row); a cache path that is not a folder is refused.
    ``base`` is a finished sweep of :func:`_cache_sweep`."""
    for n, (name, damage) in enumerate(CACHE_DAMAGES.items()):
        dest = _copy(base, run.work / f"cache{n}")
        notes = sorted((dest / "cache" / "references").glob("*.json"))
        for note in notes:  # every entry: the rerun reads them all from the cache
            damage(note, note.with_suffix(".npy"))
        shutil.rmtree(dest / "out")
        _store_case(run, dest, f"reference cache {name}", "cache", CACHE_SWEEP_CELLS)
        shutil.rmtree(dest)
    dest = _copy(base, run.work / "cache-file")
    (dest / "file").write_text("")
    run.cli("cache", "cache path is a file", ["sweep", str(dest / "exp.toml"), "--out", str(dest / "fresh"),
                                              "--workers", "1", "--quiet", "--cache", str(dest / "file")],
            allowed=(2,), timeout=60)


# ---------------------------------------------------------------------------------- studies

STUDY = """
[study]
paper = "E. Catmull, a test"
seed = "000_test.txt"

[[summaries]]
kind = KIND
group = "GROUP"
steady = ["catmull"]

[[summaries]]
kind = "pixel"
group = "fence"
pixel = PIXEL
"""


def studies(run: Run) -> None:
    """``aaeval study`` on hostile study folders: each refused in one line before any sweep,
    nothing written outside, or (the sound one) regenerated."""
    from test_study_boundary import CONFIG as STUDY_CONFIG  # the boundary tests' small config

    from aaeval.studies.readme import BEGIN, END

    cases = {
        "sound": ({}, (0,)),
        "missing group": ({"GROUP": "nowhere"}, (2,)),
        "kind a list": ({"KIND": '["sums"]'}, (2,)),
        "pixel of booleans": ({"PIXEL": "[true, true]"}, (2,)),
        "pixel outside": ({"PIXEL": "[99, 99]"}, (2,)),
        "hidden-lines a link outside": ({"LINK": "hidden-lines"}, (0, 2)),
        "figures a link outside": ({"LINK": "figures"}, (0, 2)),
        "results a link outside": ({"LINK": "results"}, (2,)),
        "README 3 GiB sparse": ({"SPARSE": True}, (2,)),
        "title with the end marker": ({"TITLE": END}, (0,)),
    }
    for n, (name, (edit, allowed)) in enumerate(cases.items()):
        folder = run.work / f"study{n}"
        folder.mkdir()
        (folder / "config.toml").write_text(STUDY_CONFIG)
        study = STUDY.replace("KIND", edit.get("KIND", '"sums"')).replace("GROUP", edit.get("GROUP", "fence"))
        study = study.replace("PIXEL", edit.get("PIXEL", "[1, 2]"))
        if "TITLE" in edit:
            study = study.replace('kind = "pixel"', f'kind = "pixel"\ntitle = "{edit["TITLE"]}"')
        (folder / "study.toml").write_text(study)
        readme = folder / "README.md"
        readme.write_text(f"# Test\n\n{BEGIN}\nold\n{END}\n")
        if edit.get("SPARSE"):
            with open(readme, "r+b") as f:
                f.truncate(3 << 30)
        if "LINK" in edit:
            os.symlink(run.canary, folder / edit["LINK"])
        run.cli("studies", name, ["study", str(folder), "--workers", "1", "--quiet"], allowed=allowed, timeout=120)
        if name == "title with the end marker":  # the README written is one the next run accepts
            run.cli("studies", f"{name} (again)", ["study", str(folder), "--workers", "1", "--quiet"], allowed=(0,),
                    timeout=120)
        shutil.rmtree(folder)


# ---------------------------------------------------------------------------------- report

def report(run: Run, base: Path) -> None:
    dest = _copy(base, run.work / "report1")
    out = dest / "out"
    assert main(["report", str(out), "--quiet"]) == 0
    outputs = [p for d in ("figures", "tables", "viewer") for p in (out / d).iterdir()] + [out / "index.html"]
    for i, p in enumerate(outputs):
        p.unlink()
        os.symlink(run.canary / f"victim{i % 3}.txt", p)
    run.cli("report", "one run over every output planted as a link", ["report", str(out), "--quiet"], allowed=(0,),
            timeout=180)
    for p in outputs:  # each planted link is a case: replaced by a regular file, its target untouched
        problems = [] if p.is_file() and not p.is_symlink() else ["outside"]
        run.record("report", f"link {p.relative_to(out)}", problems)
    dest = _copy(base, run.work / "report2")
    out = dest / "out"
    from tests.helpers.links_util import plant_markup

    from aaeval.sweeps import SweepStore
    from aaeval.sweeps.report_files import write_sweep_files

    plant_markup(out)
    write_sweep_files(SweepStore(out))  # the tables the report reads are the sweep's: written again from the cells
    run.cli("report", "markup in every field", ["report", str(out), "--quiet"], allowed=(0,), timeout=180)
    page = (out / "index.html").read_text() if (out / "index.html").is_file() else ""
    stray = "alert(" in page.replace("alert(&#x27;x&#x27;)", "")
    # the fields the report's page shows (as tests/report/test_hostile_report.py checks them);
    # markup elsewhere may not show, but must not show unescaped (stray)
    for f in ("reference_kind", "error", "host", "experiment", "group", "description"):
        escaped = f"&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt;{f}" in page
        run.record("report", f"markup in {f}", [] if escaped and not stray else ["outside"],
                   "" if escaped else "not found escaped")


# ---------------------------------------------------------------------------------- dask

def dask(run: Run) -> None:
    from tests.helpers.sweep_util import SMALL

    folder = run.work / "dask"
    folder.mkdir()
    cfg = folder / "exp.toml"
    cfg.write_text(SMALL)
    os.environ["AAEVAL_DASK_TIMEOUT"] = "3"
    os.environ["AAEVAL_DASK_WORKER_TIMEOUT"] = "3"
    try:
        run.cli("dask", "unreachable", ["sweep", str(cfg), "--out", str(folder / "o1"), "--scheduler",
                                        "tcp://127.0.0.1:9", "-q"], timeout=60)
        run.cli("dask", "bad address", ["sweep", str(cfg), "--out", str(folder / "o2"), "--scheduler",
                                        "nonsense://x", "-q"], timeout=60)
        server = socket.socket()
        server.bind(("127.0.0.1", 0))
        server.listen(8)
        held, stop = [], threading.Event()

        def accept():
            server.settimeout(0.2)
            while not stop.is_set():
                with contextlib.suppress(OSError):
                    held.append(server.accept()[0])

        t = threading.Thread(target=accept, daemon=True)
        t.start()
        run.cli("dask", "silent peer", ["sweep", str(cfg), "--out", str(folder / "o3"), "--scheduler",
                                        f"tcp://127.0.0.1:{server.getsockname()[1]}", "-q"], timeout=60)
        stop.set()
        t.join()
        server.close()
        from test_sweep_dask_loss import local_cluster

        with local_cluster(0) as cluster:
            run.cli("dask", "no workers", ["sweep", str(cfg), "--out", str(folder / "o4"), "--scheduler",
                                           cluster.scheduler_address, "-q"], timeout=60)
        with local_cluster(1) as cluster:
            def rows(code, o, e):
                import pandas as pd

                table = pd.read_parquet(folder / "o5" / "results.parquet")
                return None if len(table) == 9 and not table["key"].duplicated().any() else ("rows", str(len(table)))

            run.cli("dask", "a sweep on a 1-worker cluster", ["sweep", str(cfg), "--out", str(folder / "o5"),
                                                              "--scheduler", cluster.scheduler_address, "-q"],
                    allowed=(0,), timeout=180, check=rows)
    finally:
        os.environ.pop("AAEVAL_DASK_TIMEOUT", None)
        os.environ.pop("AAEVAL_DASK_WORKER_TIMEOUT", None)


# ---------------------------------------------------------------------------------- api

def _api_call(run: Run, name: str, fn, *, refused: tuple = (), timeout: float = 60, check=None) -> None:
    """One call of the Python API under a watchdog: it returns (``check`` may say what is
    wrong with the result) or raises one of ``refused`` in one line; anything else that
    escapes is a traceback."""
    before = run.snapshot()
    fired = threading.Event()

    def bark():
        fired.set()
        _thread.interrupt_main()

    dog = threading.Timer(timeout, bark)
    problems, detail = [], ""
    try:
        dog.start()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            result = fn()
        if not refused and check is not None:
            extra = check(result)
            if extra:
                problems.append(extra[0])
                detail = extra[1]
        elif refused:
            problems.append("exit")
            detail = f"returned {type(result).__name__} where a refusal was due"
    except KeyboardInterrupt:
        pass
    except BaseException as exc:  # noqa: BLE001 - the thing being counted
        text = str(exc)
        if not isinstance(exc, refused) if refused else True:
            problems.append("traceback")
            detail = f"{type(exc).__name__}: {text[:300]}"
        elif "\n" in text.strip():
            problems.append("exit")
            detail = "refusal not one line: " + text[:300]
    finally:
        dog.cancel()
    if fired.is_set():
        problems.append("hang")
    if run.snapshot() != before:
        problems.append("outside")
    run.record("api", name, problems, detail)


def api(run: Run) -> None:
    import numpy as np

    import aaeval
    from aaeval.sweeps.config_keys import ConfigError
    from aaeval.renderers import MethodError
    from aaeval.scenes import SceneError
    from tests.helpers.sweep_util import SMALL

    folder = run.work / "api"
    folder.mkdir()
    cfg = folder / "exp.toml"
    cfg.write_text(SMALL)
    square = {"image": {"width": 8, "height": 6, "background": [0.0, 0.0, 0.0]},
              "polygons": [{"color": [1.0, 0.5, 0.25], "vertices": [[1.5, 1.0, 0], [6.25, 1.0, 0], [6.25, 4.5, 0]]}]}
    wrong = aaeval.ArgumentError
    content = (aaeval.ArgumentError, SceneError, MethodError, ConfigError)
    cases = {
        "render an array": lambda: aaeval.render(np.zeros((4, 4, 3))),
        "render None": lambda: aaeval.render(None),
        "render bytes path": lambda: aaeval.render(b"configs/scenes/fan.toml"),
        "render a number for a spec": lambda: aaeval.render(square, 3),
        "render a list for a spec": lambda: aaeval.render(square, ["catmull"]),
        "render frame '1'": lambda: aaeval.render(square, "catmull", frame="1"),
        "render frame None": lambda: aaeval.render(square, "catmull", frame=None),
        "render frame True": lambda: aaeval.render(square, "catmull", frame=True),
        "render frame 2.5": lambda: aaeval.render(square, "catmull", frame=2.5),
        "render frame 400 digits": lambda: aaeval.render(square, "catmull", frame=10**400),
        "render frame outside": lambda: aaeval.render(square, "catmull", frame=3),
        "compare frames 2.5": lambda: aaeval.compare(square, "point", frames=2.5),
        "compare frames True": lambda: aaeval.compare(square, "point", frames=True),
        "compare a list for a metric": lambda: aaeval.compare(square, "point", metrics=[["rmse"]]),
        "compare a number for specs": lambda: aaeval.compare(square, 3),
        "compare repeats 1e9": lambda: aaeval.compare(square, "point", repeats=10**9),
        "compare repeats 400 digits": lambda: aaeval.compare(square, "point", repeats=10**400),
        "compare repeats 0": lambda: aaeval.compare(square, "point", repeats=0),
        "sweep config None": lambda: aaeval.sweep(None, folder / "o"),
        "sweep out bytes": lambda: aaeval.sweep(cfg, b"o"),
        "sweep out None": lambda: aaeval.sweep(cfg, None),
        "sweep workers 0": lambda: aaeval.sweep(cfg, folder / "o", workers=0),
        "sweep workers -1": lambda: aaeval.sweep(cfg, folder / "o", workers=-1),
        "sweep workers 1.5": lambda: aaeval.sweep(cfg, folder / "o", workers=1.5),
        "sweep workers True": lambda: aaeval.sweep(cfg, folder / "o", workers=True),
        "sweep scheduler ''": lambda: aaeval.sweep(cfg, folder / "o", scheduler=""),
        "sweep unknown option": lambda: aaeval.sweep(cfg, folder / "o", wrokers=2),
        "open_sweep None": lambda: aaeval.open_sweep(None),
        "open_sweep bytes": lambda: aaeval.open_sweep(b"o"),
        "load_scene a number": lambda: aaeval.load_scene(7),
        "load_scene NUL": lambda: aaeval.load_scene("fan\0.toml"),
    }
    for name, fn in cases.items():
        _api_call(run, name, fn, refused=content if "1e9" in name or "outside" in name else (wrong,))

    def shape(result):
        got = getattr(result, "shape", None)
        return None if got == (6, 8, 3) else ("exit", f"shape {got}")

    _api_call(run, "render a document", lambda: aaeval.render(square, "catmull", frame=np.int64(0)), check=shape)

    def rows(result):
        table = aaeval.open_sweep(result).results
        if len(table) != 9 or table["key"].duplicated().any() or not table["error"].isna().all():
            return "rows", f"{len(table)} rows"
        return None

    _api_call(run, "sweep workers=1", lambda: aaeval.sweep(cfg, folder / "ok", workers=1), check=rows, timeout=300)
    script = folder / "noguard.py"
    script.write_text("import sys, aaeval\ntry:\n"
                      f"    aaeval.sweep({str(cfg)!r}, {str(folder / 'noguard')!r}, workers=2)\n"
                      "except aaeval.SweepIncomplete as exc:\n    print(exc, file=sys.stderr)\n    sys.exit(3)\n")

    def guard(done):
        if "__main__" not in done.stderr.strip().splitlines()[-1]:
            return "exit", done.stderr[-300:]
        return None

    run.sub("api", "sweep() without a __main__ guard", [], command=[sys.executable, str(script)], allowed=(3,),
            check=guard, cwd=folder, timeout=300)


# ---------------------------------------------------------------------------------- budgets

def budgets(run: Run) -> None:
    from tests.helpers.sweep_util import SMALL

    folder = run.work / "budgets"
    folder.mkdir()
    fan = str(ROOT / "configs" / "scenes" / "fan.toml")
    thin = str(ROOT / "configs" / "scenes" / "shaded" / "thin-highlight.toml")
    big = "9" * 400
    out = str(folder / "x.png")
    cli_cases = {
        "crow k=1000 under 512M": (["render", thin, "-m", "catmull:specular=crow,k=1000", "-o", out],
                                   {"AAEVAL_MAX_MEMORY": "512M"}),
        "crow k=300 under 4G": (["render", thin, "-m", "catmull:specular=crow,k=300", "-o", out],
                                {"AAEVAL_MAX_MEMORY": "4G"}),
        "compare repeats 1e9": (["compare", fan, "-m", "point", "-r", "catmull", "--repeats", "1000000000"], {}),
        "compare repeats 400 digits": (["compare", fan, "-m", "point", "-r", "catmull", "--repeats", big], {}),
        "supersample k 400 digits": (["render", fan, "-m", f"supersample:k={big}", "-o", out], {}),
        "jitter seed 400 digits": (["render", fan, "-m", f"jitter:seed={big}", "-o", out], {}),
        "power=2": (["render", fan, "-m", "catmull:specular=amanatides,power=2", "-o", out], {}),
        "threads=5000": (["render", fan, "-m", "catmull:threads=5000", "-o", out], {}),
        "render frame 400 digits": (["render", fan, "-m", "point", "--frame", big, "-o", out], {}),
        "scheduler ''": (["sweep", str(folder / "exp.toml"), "--out", str(folder / "o"), "--scheduler", ""], {}),
    }
    (folder / "exp.toml").write_text(SMALL)
    for name, (argv, env) in cli_cases.items():
        for key, value in env.items():
            os.environ[key] = value
        try:
            run.cli("budgets", name, argv, timeout=120,
                    check=lambda c, o, e: ("exit", "an image was written") if Path(out).exists() else None)
        finally:
            for key in env:
                os.environ.pop(key, None)
    configs = {
        "config power=2": ('methods = ["catmull", "catmull-jagged"]',
                           'methods = ["catmull:specular=amanatides,power=2"]'),
        "config threads=5000": ('methods = ["catmull", "catmull-jagged"]', 'methods = ["catmull:threads=5000"]'),
        "config size 400 digits": ("frames = 3, size = 12", f"frames = 3, size = {big}"),
        "config frames 400 digits": ("frames = 3, size = 12", f"frames = {big}, size = 12"),
        "config speed threads=5000": ("fail_above = 0.1", "fail_above = 0.1\n[[speed]]\nscenes = [{generator = "
                                      "\"edges\", difficulty = [0.1], size = 256}]\nmethods = [\"catmull\"]\n"
                                      "threads = 5000"),
    }
    for name, (old, new) in configs.items():
        cfg = folder / f"{name.replace(' ', '_')}.toml"
        cfg.write_text(SMALL.replace(old, new, 1))
        dest = folder / f"out_{name.replace(' ', '_')}"
        run.cli("budgets", name, ["sweep", str(cfg), "--out", str(dest), "-q"],
                check=lambda c, o, e, dest=dest: ("exit", "the folder was written") if dest.exists() else None)


# ---------------------------------------------------------------------------------- phases

def phases(run: Run) -> None:
    folder = run.work / "phases"
    folder.mkdir()
    for kind in ("random", "r2"):
        scene = folder / f"{kind}.toml"
        scene.write_text(f"""
[image]
width = 1
height = 1
background = [0.0, 0.0, 0.0]

[animation]
frames = 100000000
translate = [0.0, 0.0]
phases = "{kind}"

[[polygons]]
color = [1.0, 1.0, 1.0]
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
""")
        for frame in ("99999999", "12345678"):
            run.sub("phases", f"{kind}: render frame {frame}", ["render", str(scene), "-m", "catmull", "--frame", frame,
                                                               "-o", str(folder / f"{kind}_{frame}.png")],
                    allowed=(0,), peak=True, timeout=120)
        run.sub("phases", f"{kind}: compare every frame", ["compare", str(scene), "-m", "point", "-r", "catmull",
                                                           "--frames", "all", "-q"], peak=True, timeout=120)


# ---------------------------------------------------------------------------------- deployed Dask

def deployed(run: Run) -> None:
    """``dask scheduler`` and ``dask worker`` as separate processes, a sweep through them;
    then a scheduler frozen (SIGSTOP) and one killed mid-sweep."""
    import importlib.util

    import pandas as pd

    from tests.helpers.sweep_util import MANY, SMALL

    spec = importlib.util.spec_from_file_location("deployed_test", ROOT / "tests" / "sweeps" /
                                                  "test_sweep_dask_deployed.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    folder = run.work / "deployed"
    folder.mkdir()
    (folder / "small.toml").write_text(SMALL)
    (folder / "many.toml").write_text(MANY)
    env = {"AAEVAL_DASK_TIMEOUT": "5", "AAEVAL_CACHE_DIR": str(folder / "cache")}
    cluster = module.Deployed(folder)
    try:
        def same_rows(done):
            table = pd.read_parquet(folder / "o1" / "results.parquet")
            if len(table) != 9 or table["key"].duplicated().any() or not table["error"].isna().all():
                return "rows", f"{len(table)} rows, errors {table['error'].dropna().unique()[:2]}"
            return None

        run.sub("deployed", "sweep through separate processes", ["sweep", str(folder / "small.toml"), "--out",
                                                                 str(folder / "o1"), "--scheduler", cluster.address,
                                                                 "-q"], allowed=(0,), env=env, check=same_rows,
                timeout=300)
        for name, sig in (("frozen", signal.SIGSTOP), ("killed", signal.SIGKILL)):
            out = folder / f"o_{name}"
            timer = threading.Thread(target=_signal_after_cells, args=(out, cluster.scheduler.pid, sig), daemon=True)
            timer.start()

            def one_line(done, out=out):
                if done.stderr.count("\n") != 1:
                    return "exit", done.stderr[-300:]
                kept = len(list((out / "cells").glob("*.json")))
                if not 1 <= kept == len(pd.read_parquet(out / "results.parquet")):
                    return "rows", f"{kept} cells"
                return None

            run.sub("deployed", f"scheduler {name} mid-sweep", ["sweep", str(folder / "many.toml"), "--out", str(out),
                                                                "--scheduler", cluster.address, "-q"],
                    allowed=(1,), env=env, check=one_line, timeout=180)
            timer.join(5)
            if name == "frozen":
                os.kill(cluster.scheduler.pid, signal.SIGCONT)
    finally:
        cluster.stop()


def _signal_after_cells(out: Path, pid: int, sig: int) -> None:
    from tests.helpers.sweep_util import wait_for_cells

    wait_for_cells(out, 3, 240)
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, sig)


def main_run(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", choices=CATEGORIES, default=list(CATEGORIES))
    parser.add_argument("--json", help="write the counts and every case here")
    args = parser.parse_args(argv)
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="aaeval-hostile-") as tmp:
        run = Run(Path(tmp))
        base = _finished(run.work) if {"store", "report"} & set(args.only) else None
        for category in args.only:
            t0 = time.monotonic()
            if category == "cache":
                cache(run, _finished(run.work, _cache_sweep(), "finished-cache"))
            elif category in ("store", "report"):
                globals()[category](run, base)
            else:
                globals()[category](run)
            print(f"== {category}: {time.monotonic() - t0:.0f} s", flush=True)
    counts = Counter(p for c in run.cases for p in c["problems"])
    per = Counter(c["category"] for c in run.cases)
    summary = {"cases": len(run.cases), "per_category": dict(per), "seconds": round(time.monotonic() - start),
               **{p: counts.get(p, 0) for p in PROBLEMS},
               "failing": [c for c in run.cases if c["problems"]]}
    print(json.dumps({k: v for k, v in summary.items() if k != "failing"}, indent=1))
    for c in summary["failing"]:
        print(f"FAIL [{c['category']}] {c['name']}: {c['problems']} {c['detail'][:300]}")
    if args.json:
        Path(args.json).write_text(json.dumps(summary, indent=1))
    return 0 if not summary["failing"] else 1


if __name__ == "__main__":
    sys.exit(main_run())
