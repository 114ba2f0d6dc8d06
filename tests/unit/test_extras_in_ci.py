"""CI installs the ``test`` extra: the modules whose tests skip without an optional dependency must be there.

``tests/unit/test_torch_ops.py`` and ``test_jax_ops.py`` skip (``pytest.importorskip``) where torch or jax is not
installed, as on a developer's machine without the ``torch`` or ``jax`` extra; in CI (``CI=true``, set by GitHub Actions and most CI
services) that skip would hide the whole module, so this test fails there instead when one is missing (or featherdyn's module cannot load: a core built without
XLA's FFI headers).
"""

from __future__ import annotations

import importlib
import os

import pytest


@pytest.mark.parametrize("module", ["torch", "featherdyn.torch", "jax", "featherdyn.jax"])
def test_optional_dependency_is_installed_in_ci(module: str) -> None:
    if os.environ.get("CI", "").lower() != "true":
        pytest.skip("not in CI (CI=true): the optional dependencies may be missing here")
    try:
        importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - a CI without the test extra
        pytest.fail(f"CI runs without {module!r} (pyproject.toml's `test` extra has it): {exc}")
