"""Reading a TOML file with one clear error for the two ways it can fail."""

from __future__ import annotations

import gc
import tomllib
from contextlib import contextmanager
from pathlib import Path
from typing import Any


def read_toml(path: str | Path, error: type[Exception], what: str) -> tuple[dict[str, Any], str]:
    """Parse ``path``; an unreadable file or bad TOML raises ``error`` naming the file.

    Returns the document and its text.
    """
    from aaeval.readlimits import FileLimitError, read_bytes

    path = Path(path)
    try:  # a regular file within the size limit, checked before reading (aaeval.readlimits)
        data = read_bytes(path, what=what)
    except FileLimitError as exc:
        raise error(str(exc)) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:  # a binary file, or text in another encoding
        raise error(f"{path}: {what} is not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset {exc.start}); "
                    "TOML files are UTF-8") from None
    if len(data) >= FAST_READER_BYTES:
        document = _fast_loads(text)
        if document is not None:
            return document, text
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML ({exc})") from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise error(f"{path}: {what} nests arrays or tables too deeply for the TOML reader") from None


# Files from this size on are read by rtoml (Rust) when it is installed: tomllib, pure
# Python, took 12.7 s on a 28 MB scene of 100,000 triangles, rtoml 3.6 s (the same
# documents: both follow TOML 1.0). Smaller files, and any file rtoml refuses (bad TOML, or
# nesting beyond its recursion limit), go through tomllib, so every error keeps its text.
FAST_READER_BYTES = 1 << 20


def _fast_loads(text: str) -> dict[str, Any] | None:
    try:
        import rtoml
    except ImportError:
        return None
    try:
        return rtoml.loads(text)
    except Exception:  # tomllib says what is wrong, in the words the tests expect
        return None


@contextmanager
def collector_paused():
    """Python's cyclic garbage collector off for the block.

    A large document is millions of lists, floats and tables made in one go and freed by
    reference counting; none of them forms a cycle. The collector still walks them every few
    thousand allocations while they are made and checked: 2.1 of the 5.6 s outside the render
    of a 100,000-triangle scene. Nesting is allowed (an outer pause is kept).
    """
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def refuse_unknown_keys(table, allowed: set[str], where: str, error: type[Exception]) -> None:
    """Raise ``error`` naming every key of ``table`` that is not in ``allowed``."""
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise error(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")
