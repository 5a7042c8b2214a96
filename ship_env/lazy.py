"""Packages that import their subpackages and public names when first asked for (PEP 562 ``__getattr__``)."""

from __future__ import annotations

import importlib
from types import ModuleType


def submodule(package: str, name: str) -> ModuleType:
    """``package.name`` imported, for a package's ``__getattr__``; AttributeError where no such submodule exists
    (a ModuleNotFoundError raised inside the submodule, for a module it imports, is passed on)."""
    try:
        return importlib.import_module(f"{package}.{name}")
    except ModuleNotFoundError as error:
        if error.name != f"{package}.{name}":
            raise
    raise AttributeError(f"module {package!r} has no attribute {name!r}")
