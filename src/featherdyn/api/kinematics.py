"""The public kinematics functions: forward kinematics, frame quantities and Jacobians.

``forward_kinematics``, ``frame_placement`` and the Jacobians are declared
(``api/declarations.py``); the frame velocities and accelerations check their input,
compute the forward kinematics by the chosen backend (:func:`kinematics_of`) and hand
the result to the reference post-processing in ``algorithms/kinematics.py``.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from ..algorithms import kinematics as _kin
from ..core import declared as _declared
from ..frames import LOCAL, ReferenceFrame, as_reference_frame
from ..model import Model
from ..results import Kinematics
from ..spatial_algebra import SpatialMotion
from ._backend import select_backend
from ._checks import State, as_dtype, check_state, finite_result, quiet
from .declarations import (
    DECLARATIONS,
    forward_kinematics,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_placement,
    joint_jacobians,
)
from .declared import Record

__all__ = [
    "kinematics_of",
    "forward_kinematics",
    "frame_placement",
    "frame_velocity",
    "frame_acceleration",
    "frame_classical_acceleration",
    "joint_jacobians",
    "frame_jacobian",
    "frame_jacobian_time_variation",
]

def kinematics_of(model: Model, st: State, v: np.ndarray | None, a: np.ndarray | None,
                  backend: str | None) -> Kinematics:
    """Forward kinematics of a checked state (``v``, ``a`` from it or ``None``) by the backend ``backend`` picks:
    the declared ``forward_kinematics`` (its core's batch, or its reference)."""
    if select_backend(backend, st.dtype) == "compiled":
        decl = DECLARATIONS["forward_kinematics"]
        outs = _declared.run(decl.name, model, st.batch, [st.q, v, a])
        assert isinstance(decl.result, Record)
        return cast(Kinematics, decl.result.make(model, {n: None if x is None else as_dtype(x, st.dtype)
                                                         for n, x in zip(decl.outputs, outs, strict=True)}))
    kin = quiet(_kin.forward_kinematics, model, st.q, v, a)
    finite_result(kin.placements.translation, "forward kinematics: placements")
    for what, m in (("velocities", kin.velocities), ("accelerations", kin.accelerations)):
        if m is not None:
            finite_result(m.vector, f"forward kinematics: {what}")
    return kin


def frame_velocity(model: Model, q: ArrayLike, v: ArrayLike, frame: str | int, reference: ReferenceFrame | str = LOCAL, *,
                   backend: str | None = None) -> SpatialMotion:
    """The spatial velocity of a frame `(..., 6)` in ``reference`` (Pinocchio's ``getFrameVelocity``).

    ::

        LOCAL:  ᶠv = ᶠX_b v_b      WORLD: ⁰X_f ᶠv      LOCAL_WORLD_ALIGNED: [R ω; R v]
    """
    if _dask.lazy(q, v):
        return _dask.call(frame_velocity, model, {"q": q, "v": v}, frame=frame, reference=reference, backend=backend)
    fid, ref = _frame(model, frame), as_reference_frame(reference)
    st = check_state(model, q, v=v)
    vel = quiet(_kin.frame_velocity, model, kinematics_of(model, st, st.arrays["v"], None, backend), fid, ref)
    finite_result(vel.vector, "frame_velocity")
    return vel


def frame_acceleration(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, frame: str | int, reference: ReferenceFrame | str = LOCAL, *,
                       backend: str | None = None) -> SpatialMotion:
    """The *spatial* acceleration of a frame `(..., 6)` in ``reference`` (``getFrameAcceleration``).

    The time derivative of the spatial velocity, without gravity; re-expressed
    exactly like :func:`frame_velocity`. Its linear part is **not** the
    acceleration of the frame origin: see :func:`frame_classical_acceleration`.
    """
    if _dask.lazy(q, v, a):
        return _dask.call(frame_acceleration, model, {"q": q, "v": v, "a": a}, frame=frame, reference=reference, backend=backend)
    fid, ref = _frame(model, frame), as_reference_frame(reference)
    st = check_state(model, q, v=v, a=a)
    kin = kinematics_of(model, st, st.arrays["v"], st.arrays["a"], backend)
    acc = quiet(_kin.frame_acceleration, model, kin, fid, ref)
    finite_result(acc.vector, "frame_acceleration")
    return acc


def frame_classical_acceleration(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, frame: str | int, reference: ReferenceFrame | str = LOCAL, *,
                                 backend: str | None = None) -> SpatialMotion:
    """The classical acceleration of a frame `(..., 6)` (``getFrameClassicalAcceleration``).

    Angular part ``ω̇``; linear part the classical acceleration, chapter §7.2::

        a_classical = a_spatial + [0; ω × v]      (ω, v of the frame, in the same reference)

    In ``LOCAL`` and ``LOCAL_WORLD_ALIGNED`` the linear part is the acceleration
    of the frame origin (in frame or world axes). In ``WORLD`` it is that of the
    body point passing through the world origin (Pinocchio's convention).
    """
    if _dask.lazy(q, v, a):
        return _dask.call(frame_classical_acceleration, model, {"q": q, "v": v, "a": a}, frame=frame, reference=reference, backend=backend)
    fid, ref = _frame(model, frame), as_reference_frame(reference)
    st = check_state(model, q, v=v, a=a)
    kin = kinematics_of(model, st, st.arrays["v"], st.arrays["a"], backend)
    acc = quiet(_kin.frame_classical_acceleration, model, kin, fid, ref)
    finite_result(acc.vector, "frame_classical_acceleration")
    return acc


def _frame(model: Model, frame: str | int) -> int:
    """The frame index (:meth:`Model.resolve_frame`); a non-model is left to :func:`check_state` to word."""
    return model.resolve_frame(frame) if isinstance(model, Model) else -1
