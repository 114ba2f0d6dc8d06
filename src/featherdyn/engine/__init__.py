"""The compiled engine: Numba kernels over flat per-model arrays (docs/architecture.md, "Two implementations").

The reference algorithms (:mod:`featherdyn.algorithms`) read like the book;
this package computes the same quantities fast:

* :mod:`._layout` flattens a :class:`~featherdyn.Model` into a few flat
  arrays (parents, joint codes, axes, joint placements, inertias as ten
  parameters, ``idx_q`` / ``idx_v``);
* :mod:`._kernels` holds generic kernels over those arrays — one *core* per
  algorithm computing one state (FK, RNEA with ``f_ext`` and a gravity flag,
  gravity, CRBA, ABA, frame Jacobian, frame placement), *checked* entry points
  that validate one state inside the kernel, and batched FK / Jacobian forms
  running a core over states with ``prange``. They are compiled on first use
  and cached on disk by Numba (``cache=True``), once for every model;
* :mod:`._lanes` runs batched RNEA, CRBA and ABA eight states at a time in
  SIMD lanes, bit-identical per state to the scalar cores;
* :mod:`._fast` is the one-state fast path of ``fd.rnea`` & co.: a call with
  one float64 state goes straight to a checked kernel, and anything the kernel
  refuses (other types, batches, a bad state) takes the general path;
* :mod:`._dispatch` is the general path for float64 input (or with
  ``backend="compiled"``), after the reference's input checks: batches,
  broadcasting, conversions;
* :func:`compile_model` (``fd.compile``) binds the kernels to one model for
  control loops: the model's arrays and a workspace travel as *one* argument,
  so a call costs little more than Numba's dispatch of the state arrays.

Nothing is compiled per model: a per-model specialisation (the arrays baked
into generated, disk-cached code) was measured at 4–6 s of compilation per
model for a saving of ~0.08 µs per call, so the kernels stay generic and are
compiled once per machine (Numba's cache; a few minutes the very first time,
then ~0.5 s to load in a new process, most of it Numba's own start-up). Importing :mod:`featherdyn` compiles nothing and does not
import Numba; this package is imported on the first compiled call.
"""

from __future__ import annotations

import importlib.util
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .compiled import CompiledModel

__all__ = ["available", "compile_model", "compile", "CompiledModel", "kernel_cache_is_cold"]

_AVAILABLE: bool | None = None


def available() -> bool:
    """Whether Numba is installed (the compiled backend can be used)."""
    global _AVAILABLE
    if _AVAILABLE is None:
        _AVAILABLE = importlib.util.find_spec("numba") is not None
    return _AVAILABLE


#: the modules whose kernels Numba caches on disk (the others hold only helpers inlined into these)
_CACHED_MODULES = ("_cores", "_entries", "_lanes")


def kernel_cache_is_cold() -> bool:
    """Whether the first compiled call on this machine will compile the kernels (about a minute).

    Numba keeps compiled kernels in index files (``*.nbi``) in the engine's
    ``__pycache__`` or under ``$NUMBA_CACHE_DIR``; a source newer than its
    index is compiled again. ``False`` without Numba (nothing is compiled).
    """
    import os
    from pathlib import Path

    if not available():
        return False
    here = Path(__file__).resolve().parent
    custom = os.environ.get("NUMBA_CACHE_DIR")
    for stem in _CACHED_MODULES:
        source = here / f"{stem}.py"
        folder = Path(custom) if custom else here / "__pycache__"
        index = list(folder.rglob(f"{stem}.*.nbi")) if folder.is_dir() else []
        if not index or max(p.stat().st_mtime for p in index) < source.stat().st_mtime:
            return True
    return False


def compile_model(model: Any, *, warmup: bool = True) -> CompiledModel:
    """The compiled engine bound to ``model``: see :func:`featherdyn.engine.compiled.compile_model`."""
    from .compiled import compile_model as _compile

    return _compile(model, warmup=warmup)


compile = compile_model  # fd.compile(model) is the documented spelling


def __getattr__(name: str) -> Any:
    if name == "CompiledModel":
        from .compiled import CompiledModel

        return CompiledModel
    raise AttributeError(f"module 'featherdyn.engine' has no attribute {name!r}")
