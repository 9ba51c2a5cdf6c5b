"""Where and with what a sweep ran (:mod:`aaeval.sweeps.provenance`): the machine and the
library versions as the interpreter itself reports them, written as strict JSON, read back
as written, and a missing, damaged or planted file told apart."""

from __future__ import annotations

import json
import os
import platform
import socket
import sys
import time

import numpy as np
import pytest

import aaeval
from aaeval.sweeps.cache_keys import code_version
from aaeval.sweeps.provenance import PROVENANCE_FILE, provenance, read_provenance, write_provenance
from tests.helpers.sweep_util import strict_json


def test_provenance_names_this_machine_and_the_versions_the_modules_report():
    info = provenance("local processes", 3)
    assert info["machine"] == socket.gethostname() and info["cores"] == os.cpu_count()
    assert info["executor"] == "local processes" and info["workers"] == 3
    assert isinstance(info["cpu_model"], str) and info["cpu_model"]
    assert info["platform"] == platform.platform()
    versions = info["versions"]
    assert versions["python"] == "{}.{}.{}".format(*sys.version_info[:3])
    assert versions["numpy"] == np.__version__  # the module's own attribute, not the distribution's metadata
    assert versions["aaeval"] == aaeval.__version__
    assert info["code_version"] == code_version()
    written = time.strptime(info["written_at"], "%Y-%m-%dT%H:%M:%SZ")
    assert abs(time.mktime(written) - time.mktime(time.gmtime())) < 60


def test_written_provenance_is_strict_json_and_reads_back_as_written(tmp_path):
    assert read_provenance(tmp_path) is None  # a folder written before provenance existed
    info = write_provenance(tmp_path, "dask", 2)
    text = (tmp_path / PROVENANCE_FILE).read_text()
    assert strict_json(text) == info
    assert read_provenance(tmp_path) == info
    assert not [p.name for p in tmp_path.iterdir() if p.name != PROVENANCE_FILE]  # no temporary file left


def test_a_damaged_or_planted_provenance_file_is_refused_naming_it(tmp_path):
    path = tmp_path / PROVENANCE_FILE
    path.write_text('{"machine": ')
    with pytest.raises(ValueError, match=f"{path}: not a readable provenance file.*run the sweep again"):
        read_provenance(tmp_path)
    outside = tmp_path / "elsewhere.json"
    outside.write_text(json.dumps({"machine": "not this sweep's"}))
    path.unlink()
    path.symlink_to(outside)
    with pytest.raises(ValueError, match="symbolic link"):
        read_provenance(tmp_path)
