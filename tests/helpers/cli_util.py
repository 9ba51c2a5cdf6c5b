"""Shared by the hostile-input tests: a command line that must be refused in one line."""

from __future__ import annotations

from aaeval.cli import main


def refused(argv, capsys, *names):
    """Run the CLI: exit 2, one line on stderr naming every one of ``names``, no traceback."""
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for name in names:
        assert str(name) in err, err
    return err
