"""The one parser of the environment's limits (aaeval/limits.py): one rule for every
``AAEVAL_*`` limit, each refusal one line naming the variable, raised as its caller's error."""

from __future__ import annotations

import pytest

from aaeval.limits import available_memory, env_bytes, env_number, env_seconds
from aaeval.readlimits import FileLimitError, max_file_bytes
from aaeval.renderers import MethodError, MethodSpec
from aaeval.renderers.budget import check_budget
from aaeval.scenes import parse_scene

NAME = "AAEVAL_TEST_LIMIT"


@pytest.mark.parametrize("text, expected", [("1", 1), ("4K", 4096), ("512M", 512 << 20), ("512mb", 512 << 20),
                                            ("1GiB", 1 << 30), ("1.5G", 3 << 29), ("2T", 2 << 40)])
def test_sizes_read_in_binary_units(monkeypatch, text, expected):
    monkeypatch.setenv(NAME, text)
    assert env_bytes(NAME, None) == expected


@pytest.mark.parametrize("read", [env_bytes, env_number, env_seconds])
@pytest.mark.parametrize("text", ["0", "-5", "inf", "nan", "soon", "1e999"])
def test_a_value_that_is_not_positive_and_finite_is_refused_naming_the_variable(monkeypatch, read, text):
    monkeypatch.setenv(NAME, text)
    with pytest.raises(ValueError, match=rf"^{NAME}='{text}': expected a positive"):
        read(NAME, 1)


@pytest.mark.parametrize("read", [env_bytes, env_number, env_seconds])
def test_unset_or_empty_gives_the_default(monkeypatch, read):
    monkeypatch.delenv(NAME, raising=False)
    assert read(NAME, 7) == 7
    monkeypatch.setenv(NAME, "")
    assert read(NAME, 7) == 7


def test_each_caller_refuses_in_its_own_error(monkeypatch):
    monkeypatch.setenv("AAEVAL_MAX_FILE_BYTES", "-1K")
    with pytest.raises(FileLimitError, match="AAEVAL_MAX_FILE_BYTES"):
        max_file_bytes()
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "inf")
    with pytest.raises(MethodError, match="AAEVAL_MAX_MEMORY"):
        available_memory(MethodError)
    scene = parse_scene({"image": {"width": 4, "height": 4},
                         "polygons": [{"color": [1, 1, 1], "vertices": [[0, 0, 1], [4, 0, 1], [0, 4, 1]]}]})
    spec = MethodSpec.parse("point")
    monkeypatch.delenv("AAEVAL_MAX_MEMORY")
    monkeypatch.setenv("AAEVAL_MAX_SECONDS", "0")
    with pytest.raises(MethodError, match="AAEVAL_MAX_SECONDS='0'"):
        check_budget(scene, spec.method, spec.options)


def test_the_memory_limit_lowers_what_is_available(monkeypatch):
    monkeypatch.delenv("AAEVAL_MAX_MEMORY", raising=False)
    free = available_memory()
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "1M")
    assert available_memory() == min(free, 1 << 20)
