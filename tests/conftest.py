"""Shared test set-up."""

import os

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Ground-truth and reference caches go to a temporary folder, never the user's.

    numba's kernel cache is configured when aaeval is imported and stays where it is.
    """
    import aaeval  # noqa: F401  (fix the numba cache folder first)

    old = os.environ.get("AAEVAL_CACHE_DIR")
    os.environ["AAEVAL_CACHE_DIR"] = str(tmp_path_factory.mktemp("aaeval-cache"))
    yield
    if old is None:
        os.environ.pop("AAEVAL_CACHE_DIR", None)
    else:
        os.environ["AAEVAL_CACHE_DIR"] = old
