"""Reading a TOML file with one clear error for the two ways it can fail."""

from __future__ import annotations

import tomllib
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
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML ({exc})") from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise error(f"{path}: {what} nests arrays or tables too deeply for the TOML reader") from None


def refuse_unknown_keys(table, allowed: set[str], where: str, error: type[Exception]) -> None:
    """Raise ``error`` naming every key of ``table`` that is not in ``allowed``."""
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise error(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")
