"""Access to Pinocchio for the verification tool: the import, and the types it hands back.

Pinocchio is an optional dependency (``pip install 'featherdyn[verify]'``);
it is imported only when a check runs.
"""

from __future__ import annotations

from types import ModuleType
from typing import Any, TypeAlias

from ..errors import MissingDependencyError

__all__ = ["PinModel", "PinValue", "require_pinocchio", "pinocchio_version"]

# Pinocchio ships no type information: to a type checker its objects are ``Any``; these names say which.

#: a ``pinocchio.Model``.
PinModel: TypeAlias = Any

#: a Pinocchio value: ``SE3``, ``Motion``, ``Force``, ``Inertia``, or a ``ReferenceFrame`` constant.
PinValue: TypeAlias = Any


def require_pinocchio() -> ModuleType:
    """Import and return ``pinocchio``, or raise :class:`MissingDependencyError` saying how to install it."""
    try:
        import pinocchio
    except ImportError:
        raise MissingDependencyError(
            "Pinocchio is not installed: `pip install pin` (or `pip install 'featherdyn[verify]'`); "
            "note that the PyPI package named 'pinocchio' is an unrelated project"
        ) from None
    return pinocchio


def pinocchio_version() -> str:
    """Pinocchio's version, or ``"not installed"``."""
    try:
        return str(require_pinocchio().__version__)
    except MissingDependencyError:
        return "not installed"
