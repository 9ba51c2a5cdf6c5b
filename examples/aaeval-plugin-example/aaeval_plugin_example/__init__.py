"""A minimal aaeval plugin (see docs/plugins.md): ``blur``, ``max_abs_error`` and ``halve``."""
