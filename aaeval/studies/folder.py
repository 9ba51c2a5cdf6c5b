"""A study folder's record and the rules every part of a study is held to: the error a refusal
raises, the limits on what a ``study.toml`` may hold, and the rule that a study reads and writes
only the files of its own folder (never through a link)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping


#: The longest title or note of a summary, in characters.
MAX_TEXT = 4000
#: The most entries of a list in a summary (methods, pairs, scenes drawn).
MAX_ITEMS = 64
#: The folders a study writes into beside its README; never links, which would take the writes elsewhere.
OUTPUT_FOLDERS = ("hidden-lines", "figures")


class StudyError(ValueError):
    """A study folder, its ``study.toml`` or its README breaks a rule; the message names the file."""


@dataclass(frozen=True)
class Study:
    """One study folder, read and checked (:func:`aaeval.studies.study.load_study`)."""

    folder: Path
    paper: str
    seed: str
    config: Path
    readme: Path
    results: Path
    summaries: tuple[Mapping[str, Any], ...] = field(default_factory=tuple)
    experiment: Any = field(default=None, compare=False, repr=False)  # the config, read once
    drawings: Path | None = None  # where hidden-lines/ and figures/ are written (default: the study folder)

    @property
    def output(self) -> Path:
        return self.drawings if self.drawings is not None else self.folder


def refuse_link(path: Path) -> None:
    """A study reads and writes in its own folder only: a link there is refused, whatever it points at."""
    if path.is_symlink():
        raise StudyError(f"{path}: is a symbolic link; a study reads and writes only the files in its own folder")


def brief(value: Any, limit: int = 60) -> str:
    """A value of study.toml as an error message quotes it: its repr, cut to ``limit`` characters."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + "..."
