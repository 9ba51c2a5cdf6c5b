"""The ``aaeval`` command line. Each subcommand lives in its own module here and adds
itself through ``add_parser(subparsers)``; ``main`` turns known errors into one-line
messages and exit code 2."""

from __future__ import annotations

import argparse
import importlib
import sys

# one entry per subcommand module
COMMANDS = [
    "aaeval.cli.render",
    "aaeval.cli.invariance",
    "aaeval.cli.methods",
    "aaeval.cli.compare",
    "aaeval.cli.sweep",
    "aaeval.cli.report",
    "aaeval.cli.hidden_lines",
]


def _version() -> str:
    import aaeval

    return f"aaeval {aaeval.__version__}"


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="aaeval",
        description="aaeval: a research testbed for anti-aliasing quality. "
        "Render scenes with exact and baseline methods, compare them against ground truth, "
        "run sweeps and write reports.",
        epilog="Run 'aaeval COMMAND --help' for the options of a command. "
        "Method specs look like NAME or NAME:key=value,key=value (see 'aaeval methods').",
    )
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMANDS:
        importlib.import_module(name).add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    from aaeval.experiments.config import ConfigError
    from aaeval.renderers.registry import MethodError
    from aaeval.scenes import SceneError

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except (SceneError, MethodError, ConfigError, ValueError, FileNotFoundError) as exc:
        print(f"aaeval {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"aaeval {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
