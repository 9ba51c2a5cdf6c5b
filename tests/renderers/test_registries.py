"""One option type and one registry shape: every registry refuses a name given twice, in
one line, and unregisters; methods, generators and specular parameters share Option."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.filters.registry import FILTERS, register_filter
from aaeval.metrics import METRICS, IMAGE_METRICS, register_metric
from aaeval.metrics.masks import MASKS, register_mask
from aaeval.options import Option, OptionError, Registry
from aaeval.renderers import METHODS, register_method
from aaeval.scenes.format import SECTIONS, register_section
from aaeval.scenes.generate import GENERATORS, GeneratorError, generate_scene, register_generator
from aaeval.specular.methods import PARAMETERS, SPECULAR_METHODS, register_specular


def _toy(*args, **kwargs):
    return 0.0


# (registry, register the toy entry under "toy_entry")
REGISTRARS = {
    "methods": (METHODS, lambda: register_method("toy_entry", _toy, summary="toy")),
    "metrics": (METRICS, lambda: register_metric("toy_entry", _toy, kind="image", title="t", fmt=".3f")),
    "masks": (MASKS, lambda: register_mask("toy_entry", _toy, "toy")),
    "filters": (FILTERS, lambda: register_filter("toy_entry", "toy", 0, 0.5, {"type": "box"})),
    "generators": (GENERATORS, lambda: register_generator("toy_entry", _toy, difficulty="d",
                                                           difficulty_param=Option(float, None, "d"), params={},
                                                           size=lambda d, p: (0, 0))),
    "sections": (SECTIONS, lambda: register_section("toy_entry", _toy)),
    "specular": (SPECULAR_METHODS, lambda: register_specular("toy_entry", summary="toy")),
}


@pytest.mark.parametrize("kind", REGISTRARS)
def test_every_registry_refuses_a_duplicate_in_one_line_and_unregisters(kind):
    registry, register = REGISTRARS[kind]
    assert isinstance(registry, Registry)
    before = list(registry)
    register()
    try:
        assert "toy_entry" in registry
        with pytest.raises(ValueError) as info:
            register()
        assert "registered twice" in str(info.value) and "\n" not in str(info.value)
    finally:
        registry.unregister("toy_entry")
    assert list(registry) == before
    with pytest.raises(ValueError, match="not registered"):
        registry.unregister("toy_entry")


def test_registering_by_call_and_by_decorator_are_the_same():
    @register_method("toy_decorated", summary="toy")
    def toy(scene, **options):
        return np.zeros(scene.shape)

    try:
        assert METHODS["toy_decorated"].render is toy
    finally:
        METHODS.unregister("toy_decorated")

    @register_metric("toy_metric", kind="image", title="t", fmt=".3f")
    def toy_metric(image_true, image_test):
        return 0.0

    try:
        assert METRICS["toy_metric"].func is toy_metric and IMAGE_METRICS["toy_metric"] is toy_metric
    finally:
        METRICS.unregister("toy_metric")
    assert "toy_metric" not in IMAGE_METRICS  # the per-kind view follows


def test_one_option_type_everywhere():
    from aaeval.renderers.registry import Option as MethodOption

    assert MethodOption is Option
    assert all(isinstance(o, Option) for o in PARAMETERS.values())
    for gen in GENERATORS.values():
        assert isinstance(gen.difficulty_param, Option)
        assert all(isinstance(o, Option) for o in gen.params.values())
    for method in METHODS.values():
        assert all(isinstance(o, Option) for o in method.options.values())


@pytest.mark.parametrize("raw, expected", [("3", 3), (3, 3), (3.0, 3), (np.int64(3), 3)])
def test_an_int_option_takes_integers_from_a_spec_or_a_file(raw, expected):
    value = Option(int, 1, "n", minimum=1, maximum=9).convert(raw, "n")
    assert value == expected and type(value) is int


@pytest.mark.parametrize("raw, words", [
    (True, ["expected int", "True"]), ("2.5", ["expected int"]), (2.5, ["expected int"]),
    (0, ["an integer in [1, 9]", "got 0"]), (10, ["an integer in [1, 9]"]),
])
def test_an_int_option_refuses_in_one_line_with_its_rule(raw, words):
    with pytest.raises(OptionError) as info:
        Option(int, 1, "n", minimum=1, maximum=9).convert(raw, "n")
    for word in words:
        assert word in str(info.value)


def test_an_open_minimum_and_non_finite_floats_are_refused():
    option = Option(float, 1.0, "x", minimum=0, low_open=True)
    assert option.rule() == "a finite number > 0"
    for raw in (0, 0.0, "0", float("nan"), "inf", -1):
        with pytest.raises(OptionError, match="a finite number > 0"):
            option.convert(raw, "x")
    assert option.convert("1e-9", "x") == 1e-9


def test_an_option_in_words_refuses_every_value_in_those_words():
    option = Option(int, 1, "n", minimum=1, maximum=9, words="a whole number of things from 1 to 9")
    assert option.rule() == "a whole number of things from 1 to 9"
    for raw in (0, 10, "x", True, 2.5, 2**70):
        with pytest.raises(OptionError) as info:
            option.convert(raw, "n")
        assert str(info.value) == f"n: expected a whole number of things from 1 to 9, got {raw!r}"
    assert option.convert(9, "n") == 9


@pytest.mark.parametrize("kind, raw", [(int, "3"), (float, "0.5"), (bool, "true"), (list, "ab"), (dict, "ab")])
def test_a_value_from_a_typed_file_is_never_parsed_from_text(kind, raw):
    """A TOML string is a string: ``repeats = "3"`` is refused where ``:repeats=3`` in a spec is not."""
    option = Option(kind, None, "x")
    if kind in (int, float, bool):
        assert option.convert(raw, "x") is not None  # a spec's text is parsed
    with pytest.raises(OptionError, match="expected"):
        option.convert(raw, "x", text=False)


def test_a_generator_refuses_with_its_own_error_type():
    with pytest.raises(GeneratorError, match=r"parameter frames: must be an integer in \[1, 100000\], got 0"):
        generate_scene("fan", 12, frames=0)


# --- aaeval.registries.load: one explicit call fills every registry -------------------

_FRESH_PROCESS = r"""
import sys
from importlib import metadata

from aaeval import plugins, registries
from aaeval.renderers import METHODS, MethodError, MethodSpec

assert not METHODS, list(METHODS)  # importing the package registers no method
try:
    MethodSpec.parse("catmull")
except MethodError as exc:
    print("before:", exc)

# a plugin reusing a built-in method's name, and a metric plugin counting its calls
points = {"aaeval.methods": [metadata.EntryPoint("dup", "toy_dup_plugin", "aaeval.methods")],
          "aaeval.metrics": [metadata.EntryPoint("count", "toy_count_plugin:register", "aaeval.metrics")]}
plugins._entry_points = lambda group: points.get(group, [])
registries.load()
import aaeval.metrics, aaeval.renderers, aaeval.specular.methods  # noqa: E401 - importing again loads nothing
registries.load()
import toy_count_plugin

from aaeval.filters import FILTERS
from aaeval.metrics import METRICS
from aaeval.specular.methods import SPECULAR_METHODS

print("metric plugin calls:", toy_count_plugin.CALLS)
print("point is the built-in:", METHODS["point"].render.__module__)
print("registered:", "catmull" in METHODS, "rmse" in METRICS, "tent" in FILTERS, "crow" in SPECULAR_METHODS)
print("failed:", plugins.failed("aaeval.methods"))
"""


def test_load_fills_every_registry_once_with_the_builtins_before_the_plugins(tmp_path):
    import os
    import subprocess
    import sys
    from pathlib import Path

    (tmp_path / "toy_dup_plugin.py").write_text(
        "from aaeval.renderers import register_method\n"
        "register_method('point', lambda scene: None, summary='a plugin taking a built-in name')\n")
    (tmp_path / "toy_count_plugin.py").write_text("CALLS = 0\ndef register():\n    global CALLS\n    CALLS += 1\n")
    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(root), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, "-c", _FRESH_PROCESS], env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    out = done.stdout.splitlines()
    assert out[0] == ("before: unknown method 'catmull': no method is registered in this process "
                      "(call aaeval.registries.load() first)")
    assert out[1:] == ["metric plugin calls: 1", "point is the built-in: aaeval.renderers.point",
                       "registered: True True True True", "failed: ['dup']"]
    refused = [line for line in done.stderr.splitlines() if line.startswith("aaeval: plugin 'dup'")]
    assert len(refused) == 1 and "registered twice" in refused[0], done.stderr
