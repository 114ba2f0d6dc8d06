"""Backend choice and the compiled core's one-state path of the public functions (private).

Every public function (``fd.rnea`` & co.) takes ``backend=None | "reference" |
"compiled"``. The default — ``None`` — is decided here and only here:

* :func:`select_backend` picks the compiled core (:mod:`featherdyn.core`,
  C++ built at install) for float64 input when it is built, the reference
  algorithms (:mod:`featherdyn.algorithms`) otherwise (float32, SymPy object arrays);
* the declared functions' one float64 state is finished in the core's C code
  (``api/declared.py``, ``_core.declared_call``), everything else goes to the Python function;
* :func:`core_path` gives the core's handle of a model when another one-state call
  may hand its arguments to the binding as they are. The binding refuses
  (``TypeError``) anything but native-endian, aligned, C-contiguous float64
  arrays of the exact shapes and returns ``None`` (or a non-zero status) for a bad state;
  either way the call goes down its general path, which converts, validates
  and raises the reference's worded errors: the one-state path changes how
  long a call takes, never what it returns or raises. Each call site writes
  its ``try`` inline (a helper function would add a Python call, ~5 % of a
  small robot's RNEA).

``$FEATHERDYN_BACKEND=reference`` when featherdyn is imported, or
:func:`set_default_backend`, makes the reference the default.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from ..core import _core
from ..core._result_pool import result_cache_info, set_result_cache_size
from ..errors import BackendError
from ..model import Model

__all__ = [
    "set_default_backend",
    "default_backend",
    "select_backend",
    "core_path",
    "CORE",
    "set_num_threads",
    "get_num_threads",
    "set_result_cache_size",
    "result_cache_info",
    "OK",
]

#: the default backend: ``None`` (compiled for float64) or ``"reference"``; a plain global, read on every call
_DEFAULT: str | None = "reference" if os.environ.get("FEATHERDYN_BACKEND") == "reference" else None
_BACKENDS = (None, "reference", "compiled")

#: the compiled core's extension module (``featherdyn.core._core``), or ``None`` when it is not built
CORE: Any = _core

#: the status of the core's binding that computed its result
OK = 0


def set_default_backend(backend: str | None) -> None:
    """Make ``backend`` the default of every algorithm called with ``backend=None``.

    ``None`` (the default): the compiled core for float64 input when it is
    built, the reference otherwise; ``"reference"``: always the reference;
    ``"compiled"``: as ``None``. The environment variable
    ``FEATHERDYN_BACKEND=reference`` sets the initial value when featherdyn is imported.

    Raises:
        BackendError: any other value.
    """
    if backend not in _BACKENDS:
        raise BackendError(f"backend: expected None, 'reference' or 'compiled', got {backend!r}")
    global _DEFAULT
    _DEFAULT = None if backend == "compiled" else backend
    if CORE is not None:
        CORE.set_public_calls(_DEFAULT is None)


if CORE is not None:
    CORE.set_public_calls(_DEFAULT is None)

def default_backend() -> str | None:
    """The default set by :func:`set_default_backend` (``None``: the compiled core for float64 input)."""
    return _DEFAULT


def select_backend(backend: str | None, dtype: np.dtype) -> str:
    """Resolve ``backend=`` to ``"reference"`` or ``"compiled"`` for data of ``dtype``.

    ``None`` picks the compiled core for float64 input when it is built and
    the default is not the reference; ``"compiled"`` forces the core (input is
    converted to float64 — a :class:`BackendError` if it cannot be, as for
    symbolic input — and the result cast back to float32 for float32 input).

    Raises:
        BackendError: an unknown name, ``"compiled"`` without the core, or
            ``"compiled"`` for data that has no float64 value.
    """
    if backend is None:
        if dtype == np.float64 and _DEFAULT is None and CORE is not None:
            return "compiled"
        return "reference"
    if backend == "reference":
        return "reference"
    if backend == "compiled":
        if CORE is None:
            raise BackendError("backend='compiled' needs the compiled core (featherdyn.core._core, built when "
                               "featherdyn is installed with pip); use backend='reference'")
        if dtype.kind not in "fiub":
            raise BackendError(f"backend='compiled' computes in float64 and cannot take {dtype} data "
                               "(symbolic input needs backend='reference')")
        return "compiled"
    raise BackendError(f"backend: expected None, 'reference' or 'compiled', got {backend!r}")


def core_path(model: Any, backend: str | None) -> Any:
    """The compiled core's handle of ``model`` (``model._core``) when a one-state call may take it, else ``None``.

    The one-state calls of ``fd.forward_kinematics``, the derivatives and the
    constrained dynamics hand their arguments to the core's binding as they
    are (``fd.rnea`` & co. do the same in C: ``api/declared.py``); it takes only native-endian, aligned, C-contiguous float64 arrays
    of the exact lengths (exact ``numpy.ndarray``, so a masked array is never
    read through its mask) and raises ``TypeError`` for anything else. The
    ``_core.<alg>_new`` entry points return the freshly allocated result, or
    ``None`` for a bad state, a singular or an overflowed result (``fd.crba``
    & co.); the ``out=`` entry points return a non-zero status instead
    (``frame_placement``, ``fd.compile``'s methods with ``out=``). Either way
    the call goes on with its general path, which converts, checks and words
    the error.
    """
    if backend is None and _DEFAULT is None:
        try:
            return model._core
        except AttributeError:
            if CORE is None or not isinstance(model, Model):
                return None
            from ..core import _view

            try:
                return _view(model)
            except (TypeError, ValueError):  # symbolic (SymPy) model parameters: the core needs numbers
                object.__setattr__(model, "_core", None)
                return None
    return None


def set_num_threads(n: int) -> None:
    """Threads of the batched calls: the compiled core's pool, the calling thread included.

    ``n <= 0`` restores the default, every core available to the process.

    Raises:
        DTypeError: ``n`` is not an integer.
    """
    from ..errors import DTypeError

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise DTypeError(f"n: expected an integer number of threads, got {type(n).__name__} {n!r}")
    n = int(n)
    if CORE is not None:
        CORE.set_num_threads(n)


def get_num_threads() -> int:
    """The number of threads the batched calls use (the compiled core's pool; see :func:`set_num_threads`)."""
    if CORE is not None:
        return int(CORE.get_num_threads())
    import os

    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
