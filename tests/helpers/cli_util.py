"""Shared by the hostile-input tests: a command line that must be refused in one line."""

from __future__ import annotations

from pathlib import Path

from aaeval.cli import main


def refused(argv, capsys, *names, written=()):
    """Run the CLI in this process: exit 2, one line on stderr naming every one of ``names``,
    no traceback, and none of the paths ``written`` created."""
    capsys.readouterr()
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for name in names:
        assert str(name) in err, (name, err)
    for path in written:
        assert not Path(path).exists(), path
    return err
