"""The frameworks' tests skip where a framework is missing (a user's machine without the extra); in CI they must
run: CI installs the `test` extra, which holds `jax` (pyproject.toml), so a missing one fails here."""

from __future__ import annotations

import importlib
import os

import pytest


@pytest.mark.skipif(os.environ.get("CI") != "true", reason="outside CI the frameworks are optional extras")
def test_ci_has_the_frameworks() -> None:
    importlib.import_module("jax")
    importlib.import_module("featherdyn.jax")
