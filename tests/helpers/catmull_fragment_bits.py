"""Digests of the Catmull kernel's visible fragments on the same-bits scenes.

``tests/helpers/same_bits.py`` records images; this records what ``visible_fragments`` returns
(pixel, polygon, area, centroid), with and without centroids, on the same 115 scenes, so
the fragments sink is held to the numba kernel's bits as well. Recorded by the numba
kernel before it was deleted (``tests/data/same_bits_catmull_fragments.json``) with::

    python3 -m tests.helpers.catmull_fragment_bits record

and a newly shipped scene's entries alone (the rest kept) with ``... add``.
"""

from __future__ import annotations

import hashlib
import json
import sys
from collections.abc import Iterator

import numpy as np

from aaeval.catmull import visible_fragments
from tests.helpers.same_bits import DATA, scenes

FILE = DATA / "same_bits_catmull_fragments.json"


def fragments_digest(fragments) -> str:
    """SHA-256 of every field's bytes (int64 / float64) and length."""
    h = hashlib.sha256()
    for field, dtype in zip(fragments, (np.int64, np.int64, np.float64, np.float64, np.float64)):
        a = np.ascontiguousarray(field, dtype=dtype)
        h.update(repr(a.shape).encode() + a.tobytes())
    return h.hexdigest()


def fragment_digests(skip: set[str] = frozenset()) -> Iterator[tuple[str, str]]:
    for scene_id, make in scenes():
        if scene_id in skip:
            continue
        scene = make()
        for centroids in (True, False):
            key = f"{scene_id}|centroids={centroids}"
            yield key, fragments_digest(visible_fragments(scene, centroids=centroids, threads=1))


if __name__ == "__main__":
    # record: every scene again; add: only the scenes the file does not hold yet (a newly
    # shipped scene), every recorded entry left as it is
    if sys.argv[1:] not in (["record"], ["add"]):
        raise SystemExit("usage: python3 -m tests.helpers.catmull_fragment_bits {record,add}")
    digests = {}
    if sys.argv[1] == "add":
        digests = json.loads(FILE.read_text())
    digests.update(fragment_digests(skip={key.split("|", 1)[0] for key in digests}))
    FILE.write_text(json.dumps(digests, indent=1, sort_keys=True) + "\n")
    print(FILE)
