"""The limits aaeval runs under: the ``AAEVAL_*`` limit variables of the environment,
read by one parser, and the memory this process may use.

Every limit a user sets in the environment (``AAEVAL_MAX_SECONDS``, ``AAEVAL_MAX_SAMPLES``,
``AAEVAL_MAX_MEMORY``, ``AAEVAL_MAX_FILE_BYTES``, ``AAEVAL_DASK_TIMEOUT``, ...) is read
here, each time it is needed (a test or a script may change it between calls): unset or
empty gives the caller's default; anything but a positive, finite value of its kind is
refused in one line naming the variable, raised as the caller's ``error`` class (a
:class:`ValueError` by default), so that each caller's refusal stays the one it documents.
"""

from __future__ import annotations

import math
import os

__all__ = ["available_memory", "env_bytes", "env_number", "env_seconds"]

_UNITS = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}


def env_number(name: str, default: float, error: type[Exception] = ValueError) -> float:
    """``$name`` as a positive number (``"1e9"``, ``"600"``), else ``default`` when unset."""
    return _read(name, default, float, "a positive number", error)


def env_seconds(name: str, default: float, error: type[Exception] = ValueError) -> float:
    """``$name`` as a positive number of seconds, else ``default`` when unset."""
    return _read(name, default, float, "a positive number of seconds", error)


def env_bytes(name: str, default: int | None, error: type[Exception] = ValueError) -> int | None:
    """``$name`` as a positive size in bytes (``"512M"``, ``"8G"``, ``"1GiB"``), else ``default``
    when unset."""
    value = _read(name, None, _size, "a positive size such as 64M or 1G", error)
    return default if value is None else int(value)


def _read(name: str, default, parse, expected: str, error: type[Exception]):
    text = os.environ.get(name)
    if not text:
        return default
    try:
        value = parse(text)
    except ValueError:
        value = math.nan
    if not (value > 0 and math.isfinite(value)):
        raise error(f"{name}={text!r}: expected {expected}")
    return value


def _size(text: str) -> float:
    number, unit = text.strip().upper().removesuffix("B").removesuffix("I"), ""
    if number and number[-1] in _UNITS:
        number, unit = number[:-1], number[-1]
    return float(number) * _UNITS[unit]


def available_memory(error: type[Exception] = ValueError) -> int:
    """Bytes this process may use: MemAvailable, less where an address-space limit
    (``ulimit -v``) leaves less, and ``AAEVAL_MAX_MEMORY`` (e.g. ``8G``) if lower still."""
    avail = None
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    if avail is None:
        try:
            avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            avail = 1 << 62  # unknown: only AAEVAL_MAX_MEMORY limits
    headroom = _address_space_headroom()
    if headroom is not None:  # ulimit -v: past it an allocation fails however much RAM is free
        avail = min(avail, headroom)
    limit = env_bytes("AAEVAL_MAX_MEMORY", None, error)
    return avail if limit is None else min(avail, limit)


def _address_space_headroom() -> int | None:
    """Bytes of address space left under ``RLIMIT_AS`` (its soft limit less this process's
    ``VmSize``), or None when there is no such limit."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, AttributeError, OSError, ValueError):
        return None
    if soft == resource.RLIM_INFINITY or soft < 0:
        return None
    used = 0
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    used = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError):
        pass
    return max(0, soft - used)
