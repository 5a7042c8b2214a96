"""Packages that import their subpackages and public names when first asked for (PEP 562 ``__getattr__``)."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Mapping
from types import ModuleType
from typing import Any


def submodule(package: str, name: str) -> ModuleType:
    """``package.name`` imported, for a package's ``__getattr__``; AttributeError where no such submodule exists
    (a ModuleNotFoundError raised inside the submodule, for a module it imports, is passed on)."""
    try:
        return importlib.import_module(f"{package}.{name}")
    except ModuleNotFoundError as error:
        if error.name != f"{package}.{name}":
            raise
    raise AttributeError(f"module {package!r} has no attribute {name!r}")


def public_name(package: str, modules: Mapping[str, str], name: str) -> Any:
    """For a package's ``__getattr__``: its public ``name`` from the submodule that ``modules`` names,
    bound in the package (imported once), or else its submodule ``name`` (:func:`submodule`)."""
    if name in modules:
        value = getattr(importlib.import_module(f"{package}.{modules[name]}"), name)
        setattr(sys.modules[package], name, value)
        return value
    return submodule(package, name)


class FunctionsNamedAsModules(ModuleType):
    """A lazy package whose functions are named as the submodules that hold them (``zigzag`` in
    ``zigzag``): each keeps its name in the package when its module is imported (the import system
    binds each submodule to its name in its package). The package's ``_MODULES`` maps each public
    name to its submodule; set as the package's class (``sys.modules[__name__].__class__``)."""

    def __setattr__(self, name: str, value: Any) -> None:
        modules: dict[str, str] = self.__dict__.get("_MODULES", {})
        if isinstance(value, ModuleType) and modules.get(name) == name:
            value = getattr(value, name)
        super().__setattr__(name, value)
