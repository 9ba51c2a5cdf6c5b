"""The ``aaeval`` command line. Each subcommand lives in its own module here and declares
its ``NAME`` and ``HELP`` (and ``EPILOG`` where it has one), its description as its module
docstring (what ``aaeval COMMAND --help`` prints, so written for users), its options in
``add_arguments(parser)`` where it has any, and ``run(args)`` where the command itself runs
(``import`` hands each of its kinds a ``run`` of its own); ``main`` turns known errors into
one-line messages and exit code 2.

Exit codes: 0 success; 1 a sweep left cells not run (they run on the next sweep); 2 an
input error (one line on stderr, nothing written); 128 + N when stopped by signal N:
130 Ctrl-C (SIGINT), 143 SIGTERM (``kill PID``), 129 SIGHUP (terminal closed). An
interrupted command stops its workers first and keeps every finished result.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import inspect
import signal
import sys

# one entry per subcommand module
COMMANDS = [
    "aaeval.cli.render",
    "aaeval.cli.invariance",
    "aaeval.cli.methods",
    "aaeval.cli.metrics",
    "aaeval.cli.compare",
    "aaeval.cli.sweep",
    "aaeval.cli.report",
    "aaeval.cli.study",
    "aaeval.cli.hidden_lines",
    "aaeval.cli.import_content",
]


def _version() -> str:
    import aaeval

    return f"aaeval {aaeval.__version__}"


@functools.cache
def build_parser() -> argparse.ArgumentParser:
    """The command line's parser, built once per process: its commands and options are
    fixed (no choice depends on the registries), and a script or test calling :func:`main`
    hundreds of times otherwise builds every subparser each time."""
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
        add_command(sub, importlib.import_module(name))
    return parser


def add_command(sub, command) -> None:
    """The subparser of one command module, built from what the module declares."""
    p = sub.add_parser(command.NAME, help=command.HELP, description=inspect.cleandoc(command.__doc__),
                       epilog=getattr(command, "EPILOG", None))
    if hasattr(command, "add_arguments"):
        command.add_arguments(p)
    if hasattr(command, "run"):
        p.set_defaults(run=command.run)


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised where the program is, so that cleanup runs as for Ctrl-C."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _raise_interrupted(signum, frame) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def _signals_interrupt():
    """SIGTERM and SIGHUP interrupt like Ctrl-C while a command runs (main thread only)."""
    caught = [s for s in (signal.SIGTERM, getattr(signal, "SIGHUP", None)) if s is not None]
    try:
        previous = {s: signal.signal(s, _raise_interrupted) for s in caught}
    except ValueError:  # not the main thread: leave signals alone
        previous = {}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


#: The longest error line printed: a message that echoes a value back (a million-element
#: list in a config) would otherwise be megabytes on one line.
MAX_ERROR_CHARS = 1000


def _one_line(message) -> str:
    text = " ".join(str(message).split("\n")).strip()
    if len(text) > MAX_ERROR_CHARS:
        cut = len(text) - MAX_ERROR_CHARS
        text = f"{text[:MAX_ERROR_CHARS - 200]} ...[{cut} characters cut]... {text[-200:]}"
    return text


def main(argv: list[str] | None = None) -> int:
    from aaeval.registries import load

    load()  # every built-in method, filter and metric, then the plugins
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        with _signals_interrupt():
            return int(args.run(args) or 0)
    # SceneError, MethodError and ConfigError are ValueErrors: caught here without importing
    # the sweep machinery (pandas, scipy), which a plain render does not need at start-up
    except ValueError as exc:
        print(f"aaeval {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except OSError as exc:  # a full disk, a vanished folder, permissions: named, no traceback
        detail = f"{exc.strerror}: {exc.filename}" if exc.strerror and exc.filename else str(exc)
        print(f"aaeval {args.command}: error: {_one_line(detail)}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"aaeval {args.command}: error: out of memory (a smaller image, fewer samples or "
              "AAEVAL_MAX_MEMORY to refuse such requests up front)", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        signum = exc.signum if isinstance(exc, Interrupted) else signal.SIGINT
        print(f"aaeval {args.command}: interrupted ({signal.Signals(signum).name})", file=sys.stderr)
        return 128 + signum


if __name__ == "__main__":
    sys.exit(main())
