"""The one-state fast path of the public functions (private): a model's packed arrays bound to the checked kernels.

``fd.rnea(model, q, v, a)`` with float64 C-contiguous 1-D arrays is the call a
control loop makes; it must cost about what ``pin.rnea`` costs, a couple of
microseconds, so it cannot afford the general path's NumPy validation
(~15 µs). Instead the public function calls a *checked* kernel
(:mod:`._kernels`, ``checked_*``) that validates the state inside the
compiled code — lengths, finiteness, unit quaternions — and returns a status.
Anything else (lists, float32, batches, strided or read-only arrays, a bad
state) makes the kernel refuse (``TypeError`` from Numba's dispatch, or a
non-zero status) and the public function goes on with its general path, which
converts, validates and raises the reference's worded errors. The fast path
therefore never changes *what* a call returns or raises, only how long it
takes.

Each model gets one :class:`FastPath` on first use, stored on the (immutable)
model object as ``model._fast``: the packed model arrays with a workspace, and
the kernels, so that a call does a handful of attribute lookups and one Numba
dispatch.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..model import Model

__all__ = ["FastPath", "attach"]

class FastPath:
    """A model's packed arrays and the checked kernels, bound for the public one-state calls."""

    __slots__ = (
        "MD",
        "aba",
        "crba",
        "fk",
        "frame_jacobian",
        "frame_placement",
        "frames",
        "gravity",
        "model",
        "nle",
        "nv",
        "refusals",
        "rnea",
        "shape_H",
        "shape_J",
        "shape_M",
        "shape_V",
        "singular",
    )

    def __init__(self, model: Model) -> None:
        from numba.core.errors import NumbaError

        from . import _dispatch
        from . import _kernels as _k
        from ._layout import with_workspace

        _k.lock_checked()
        #: what a checked kernel raises for arguments it cannot take (Numba's dispatch: an untypeable,
        #: unsupported — e.g. a masked array — or out-of-range argument); the caller takes its general path
        self.refusals = (TypeError, ValueError, OverflowError, NumbaError)
        self.MD = with_workspace(_dispatch.arrays_of(model).packed, model.nbodies, model.nv)
        self.nv = model.nv
        self.shape_M = (model.nv, model.nv)
        self.shape_J = (6, model.nv)
        self.singular = _dispatch.singular_messages(model)
        self.frames = model._frame_index
        self.rnea = _k.checked_rnea
        self.nle = _k.checked_nle
        self.gravity = _k.checked_gravity
        self.crba = _k.checked_crba
        self.aba = _k.checked_aba
        self.frame_jacobian = _k.checked_frame_jacobian
        self.fk = _k.checked_fk if model.nv > 0 else None
        self.frame_placement = _k.checked_frame_placement
        self.shape_H = (2, model.nbodies, 4, 4)
        self.shape_V = (model.nbodies, 6)
        self.model = model


def attach(model: Any) -> FastPath | None:
    """The fast path of ``model``, made on first use (``None``: not a Model, or no Numba, or not supported)."""
    if not isinstance(model, Model):
        return None
    try:
        return model._fast
    except AttributeError:
        pass
    from . import available

    fast: FastPath | None = None
    if available():
        try:
            fast = FastPath(model)
        except (NotImplementedError, TypeError, ValueError):
            # a joint type without a kernel, or symbolic parameters: the general path handles (or words) it
            fast = None
    object.__setattr__(model, "_fast", fast)
    return fast


_EMPTY = np.empty
#: "not wanted" for the optional vectors of the checked FK kernel
NO_VECTOR = np.empty(0)
NO_BODIES = np.empty((0, 6))
