"""Argument types and output checks shared by ``featherdyn`` (:mod:`featherdyn.tools.cli`) and ``featherdyn bench``.

Everything a command can refuse is refused here, before any work: a bad
number, an output file whose folder does not exist. The command line prints
the :class:`~featherdyn.errors.FeatherdynError` as one line and exits with 2.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..errors import FeatherdynError

__all__ = ["positive_int", "positive_float", "check_writable", "plural"]


def positive_int(text: str) -> int:
    """An argparse type: an integer ``>= 1``."""
    try:
        val = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if val < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {val}")
    return val


def positive_float(text: str) -> float:
    """An argparse type: a finite number ``> 0``."""
    try:
        val = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (val > 0 and val < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {text!r}")
    return val


def check_writable(path: str | os.PathLike[str] | None, option: str) -> None:
    """Refuse an output ``path`` that cannot be written (checked before the run, not after it).

    Raises:
        FeatherdynError: its folder does not exist or is not writable, or ``path`` is a directory.
    """
    if path is None:
        return
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise FeatherdynError(f"cannot write {option} {p}: it is a directory")
    if not folder.is_dir():
        raise FeatherdynError(f"cannot write {option} {p}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise FeatherdynError(f"cannot write {option} {p}: permission denied")


def plural(n: int, noun: str) -> str:
    """``n`` and ``noun``, the noun in the plural unless ``n`` is 1: ``"1 chunk"``, ``"3 chunks"``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"
