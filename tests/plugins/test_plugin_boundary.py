"""A plugin method's failures are input errors.

Whatever a method does wrong, raising, recursing without end, returning None, a list, a
1-D array, the wrong shape, integers, complex numbers, NaN or infinity, ``aaeval render``
says so in one line naming the method and the rule (exit 2, nothing written, no
traceback), and ``aaeval compare`` shows the failed row and exits non-zero.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.plugin_util import fake_install

ROOT = Path(__file__).resolve().parents[2]
FAN = ROOT / "configs" / "scenes" / "fan.toml"

BAD_METHODS = '''
import numpy as np
from aaeval.renderers import register_method

def _shape(scene):
    return (scene.height, scene.width, 3)

BEHAVIOURS = {
    "raises": lambda scene: (_ for _ in ()).throw(KeyError("the plugin's own bug")),
    "none": lambda scene: None,
    "alist": lambda scene: [[0.0]],
    "flat": lambda scene: np.zeros(scene.width * scene.height),
    "wrongshape": lambda scene: np.zeros((scene.height, scene.width)),
    "integers": lambda scene: np.zeros(_shape(scene), dtype=np.int64),
    "complex": lambda scene: np.zeros(_shape(scene), dtype=complex),
    "nan": lambda scene: np.full(_shape(scene), np.nan),
    "inf": lambda scene: np.full(_shape(scene), -np.inf),
    "huge": lambda scene: np.full(_shape(scene), -1e300),
    "exits": lambda scene: __import__("sys").exit(3),
    "generatorexit": lambda scene: (_ for _ in ()).throw(GeneratorExit()),
}

def _recurse(scene):
    return _recurse(scene)

for name, fn in BEHAVIOURS.items():
    register_method(f"bad-{name}", summary=f"test plugin: {name}", samples=lambda options: 1)(fn)
register_method("bad-recurses", summary="test plugin: recursion", samples=lambda options: 1)(_recurse)
'''

RULES = {
    "raises": "failed: KeyError: \"the plugin's own bug\"",
    "recurses": "failed: RecursionError",
    "none": "returned NoneType",
    "alist": "returned list",
    "flat": "returned shape",
    "wrongshape": "returned shape",
    "integers": "returned dtype int64",
    "complex": "returned dtype complex128",
    "nan": "NaN or infinite",
    "inf": "NaN or infinite",
    "huge": "magnitude 1e+300",
    "exits": "failed: SystemExit: 3",  # sys.exit(3) in a plugin made render exit 3, saying nothing
    "generatorexit": "failed: GeneratorExit",
}


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    site = tmp_path_factory.mktemp("site")
    (site / "aaeval_bad_methods.py").write_text(BAD_METHODS)
    fake_install(site, "aaeval-bad-methods", {"aaeval.methods": {"bad": "aaeval_bad_methods"}})
    return site


def run(site: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(site), str(ROOT), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "aaeval", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


@pytest.mark.slow
@pytest.mark.parametrize("behaviour", sorted(RULES))
def test_render_refuses_a_bad_result_in_one_line(site, tmp_path, behaviour):
    out = tmp_path / "out.npy"
    done = run(site, "render", str(FAN), "-m", f"bad-{behaviour}", "-o", str(out), cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert f"'bad-{behaviour}'" in lines[0] and RULES[behaviour] in lines[0], lines[0]
    assert not out.exists()


@pytest.mark.slow
def test_compare_shows_the_failed_row_and_exits_non_zero(site, tmp_path):
    done = run(site, "compare", str(FAN), "-m", "point", "-m", "bad-nan", "--reference", "catmull",
               "--format", "csv", cwd=tmp_path)
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr
    assert "bad-nan failed on frame" in done.stderr and "NaN or infinite" in done.stderr
    assert "point" in done.stdout  # the method that worked keeps its row
