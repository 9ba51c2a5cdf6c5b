"""User names (groups, scenes, labels) as the report uses them: text, never a path or markup.

Group names come from experiment configs and may be anything TOML allows: ``fence a`` and
``fence-a``, ``$5``, ``../x``, 300 accented letters. A figure file named after a group must
be unique per name (two names that read alike must not share, and so overwrite, a file),
safe in any folder and short; matplotlib must draw the name as written, not read ``$...$``
as mathtext.
"""

from __future__ import annotations

import hashlib
import unicodedata

__all__ = ["figure_stem", "MATHTEXT_OFF"]

# rcParams for figures that show user text: "$5 to $10" is a price, not TeX
MATHTEXT_OFF = {"text.parse_math": False}

_READABLE = 40  # characters of the name kept in the file name, for people browsing figures/


def figure_stem(name: str) -> str:
    """A file-name stem for ``name``: a readable ASCII part plus a hash of the exact name.

    Distinct names give distinct stems, also on file systems that ignore case; the stem is
    stable between runs, at most ~52 ASCII characters of ``[A-Za-z0-9_-]``, never empty,
    never starting with a dot.
    """
    ascii_name = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode()
    readable = "".join(ch if ch.isalnum() else "_" for ch in ascii_name)[:_READABLE].strip("_") or "group"
    digest = hashlib.sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:10]
    return f"{readable.lower()}-{digest}"
