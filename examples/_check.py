"""Helpers shared by the example scripts: comparisons that print what they compare and stop on failure.

Every example imports these (``examples/`` is on ``sys.path`` when a script
runs). A failed comparison raises ``SystemExit`` with a message, so the
script exits with status 1 and ``tests/integration/test_examples.py`` fails.
"""

from __future__ import annotations

import importlib
import importlib.metadata
import re
import sys
from pathlib import Path
from typing import Any

import numpy as np

# the 6×6 swap between featherdyn's [angular; linear] and Pinocchio's [linear; angular]
P6 = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])


def needs(*modules: str) -> None:
    """Stop the example with one line (exit status 1, no traceback) when a module it imports is missing.

    ``modules`` are module names, or distribution names with a hyphen (``"example-robot-data"``, whose
    robot files ``fd.load_robot`` reads). Called before the example's other imports. The line names the install command of the script's first
    line, ``# needs: featherdyn[EXTRA] …`` (the smallest of ``pyproject.toml``'s extras that has them).
    """
    missing = []
    for name in modules:
        try:
            if "-" in name:  # a distribution without a module of its name (example-robot-data: robot files)
                importlib.metadata.distribution(name)
            else:
                importlib.import_module(name)
        except (ImportError, importlib.metadata.PackageNotFoundError):
            missing.append(name.split(".")[0])
    if not missing:
        return
    script = Path(sys.modules["__main__"].__file__ or sys.argv[0])
    first = script.read_text(encoding="utf-8").split("\n", 1)[0]
    found = re.match(r"# needs: featherdyn\[([\w,]+)\]", first)
    extra = found[1] if found else "examples"
    raise SystemExit(f"{script.name} needs {' and '.join(missing)}, not installed: pip install \"featherdyn[{extra}]\" "
                     f"(from a clone of featherdyn: pip install \".[{extra}]\" in its folder)")


def section(title: str) -> None:
    """Print a section header (mirrors the ``# %%`` cell markers)."""
    print(f"\n=== {title} ===")


def show(label: str, value: Any, precision: int = 4) -> None:
    """Print a labelled number, vector or matrix."""
    with np.printoptions(precision=precision, suppress=True, linewidth=110):
        arr = np.asarray(value)
        if arr.ndim >= 2:
            print(f"  {label} =\n{arr}")
        else:
            print(f"  {label} = {arr}")


def max_abs(a: Any, b: Any) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b))) if a.size else 0.0


def check(label: str, got: Any, expected: Any, tol: float = 1e-9) -> float:
    """Assert ``got ≈ expected`` (max abs difference ``<= tol``); print the difference."""
    err = max_abs(got, expected)
    ok = err <= tol
    print(f"  [{'ok' if ok else 'FAIL'}] {label}: max |Δ| = {err:.2e} (tol {tol:.0e})")
    if not ok:
        raise SystemExit(f"FAILED: {label}: max |Δ| = {err:.3e} > {tol:.1e}")
    return err


def check_true(label: str, condition: Any) -> None:
    """Assert a boolean claim."""
    ok = bool(condition)
    print(f"  [{'ok' if ok else 'FAIL'}] {label}")
    if not ok:
        raise SystemExit(f"FAILED: {label}")


def differs(label: str, got: Any, claimed: Any, at_least: float = 1e-6, *, note: str = "erratum confirmed") -> float:
    """Assert that ``got`` and ``claimed`` differ by more than ``at_least`` (a claim of the chapter that does not hold)."""
    err = max_abs(got, claimed)
    ok = err > at_least
    print(f"  [{note if ok else 'FAIL'}] {label}: max |Δ| = {err:.3g}")
    if not ok:
        raise SystemExit(f"FAILED: expected {label} to differ, but max |Δ| = {err:.3e} <= {at_least:.1e}")
    return err
