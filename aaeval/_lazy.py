"""Names of a package loaded on first use (PEP 562), so that importing the package loads
none of its modules: a reader of a sweep folder (the report) imports what it needs without
the renderers and metrics the sweep ran."""

from __future__ import annotations

import importlib
from typing import Callable


def lazy_names(package: str, module_of: dict[str, str]) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The package's ``__getattr__`` and ``__dir__`` serving each name of ``module_of``
    (name -> submodule) from ``package.submodule``, imported when the name is first asked for."""

    def __getattr__(name: str):
        module = module_of.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.{module}"), name)

    def __dir__():
        return sorted([*importlib.import_module(package).__dict__, *module_of])

    __getattr__.module_of = dict(module_of)  # what it serves, for the tests that walk imports
    return __getattr__, __dir__
