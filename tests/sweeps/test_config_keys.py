"""The keys of an experiment config: each declared once as an Option, checked through
Option.convert, refused in one line naming the file and the key; the docs show every key."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from aaeval.options import Option
from aaeval.sweeps import load_experiment
from aaeval.sweeps.config_keys import EXPERIMENT_KEYS, GROUP_KEYS, REQUIRED, SPEED_KEYS
from tests.helpers.sweep_util import SMALL, write_config

DOCS = Path(__file__).resolve().parents[2] / "docs" / "sweeps.md"
TABLES = {"experiment": EXPERIMENT_KEYS, "groups": GROUP_KEYS, "speed": SPEED_KEYS}


@pytest.mark.parametrize("table", TABLES)
def test_every_key_is_an_option_with_a_meaning(table):
    for key, option in TABLES[table].items():
        assert isinstance(option, Option) and option.doc, key


def test_the_docs_sample_config_shows_every_key():
    text = DOCS.read_text()
    sample = text[text.index("## Configs"):]
    sample = sample[sample.index("```toml"):sample.index("```", sample.index("```toml") + 3)]
    sections = dict(re.findall(r"^\[+(experiment|groups|speed)\]+[^\n]*\n(.*?)(?=\n\[|\Z)", sample, re.S | re.M))
    for table, keys in TABLES.items():
        shown = set(re.findall(r"^([a-z_]+)(?:\.[a-z-]+)? =", sections[table], re.M))
        assert set(keys) <= shown, (table, sorted(set(keys) - shown))


def test_keys_left_out_take_their_declared_defaults(tmp_path):
    exp = load_experiment(write_config(tmp_path, SMALL.replace("fail_above = 0.1\n", "")))
    assert exp.fail_above is EXPERIMENT_KEYS["fail_above"].default is None
    assert exp.noise_estimate is EXPERIMENT_KEYS["noise_estimate"].default is True
    assert exp.max_seconds is None and exp.description == "test sweep"
    assert all(g.repeats == EXPERIMENT_KEYS["repeats"].default for g in exp.groups)
    assert all(g.frames == GROUP_KEYS["frames"].default for g in exp.groups)
    assert EXPERIMENT_KEYS["reference"].default is REQUIRED and GROUP_KEYS["methods"].default is REQUIRED
    # an integral float is an integer, as for every int option
    exp = load_experiment(write_config(tmp_path, SMALL.replace("fail_above = 0.1", "repeats = 3.0"), "f.toml"))
    assert all(g.repeats == 3 and type(g.repeats) is int for g in exp.groups)
