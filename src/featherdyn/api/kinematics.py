"""The public kinematics functions: forward kinematics, frame quantities and Jacobians.

Each function checks its input, computes the forward kinematics by the chosen
backend (:func:`kinematics_of`) and hands the result to the reference
post-processing in ``algorithms/kinematics.py`` and ``algorithms/jacobians.py``;
one float64 state first hands its arguments to the compiled core's binding as they are.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import core as _compiled
from ..algorithms import kinematics as _kin
from ..core._model_view import CoreHandle
from ..errors import ShapeError
from ..frames import LOCAL, ReferenceFrame, as_reference_frame
from ..model import Model
from ..results import Kinematics
from ..spatial_algebra import PluckerTransform, SpatialMotion
from ._backend import CORE, OK, core_path, public_call, select_backend
from ._checks import State, check_state, finite_result, quiet
from .declarations import frame_jacobian, frame_jacobian_time_variation, joint_jacobians

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

_EMPTY = np.empty
_F64 = np.dtype(np.float64)


def _kinematics(model: Model, H: np.ndarray, Hp: np.ndarray, vel: np.ndarray | None, acc: np.ndarray | None,
                dtype: np.dtype) -> Kinematics:
    """The :class:`Kinematics` of the core's arrays (homogeneous placements, body-frame motions) in ``dtype``."""
    def cast(x: np.ndarray) -> np.ndarray:
        return x if dtype == _F64 else x.astype(dtype)

    return Kinematics(
        model=model,
        placements=PluckerTransform._wrap(cast(H[..., :3, :3]), cast(H[..., :3, 3]), None, None),
        velocities=SpatialMotion._wrap(cast(vel), None) if vel is not None else None,
        accelerations=SpatialMotion._wrap(cast(acc), None) if acc is not None else None,
        parent_placements=PluckerTransform._wrap(cast(Hp[..., :3, :3]), cast(Hp[..., :3, 3]), None, None),
    )


def kinematics_of(model: Model, st: State, v: np.ndarray | None, a: np.ndarray | None,
                  backend: str | None) -> Kinematics:
    """Forward kinematics of a checked state (``v``, ``a`` from it or ``None``) by the backend ``backend`` picks."""
    if select_backend(backend, st.dtype) == "compiled":
        kin = _kinematics(model, *_compiled.kinematics(model, st.q, v, a), st.dtype)
    else:
        kin = quiet(_kin.forward_kinematics, model, st.q, v, a)
    finite_result(kin.placements.translation, "forward kinematics: placements")
    for what, m in (("velocities", kin.velocities), ("accelerations", kin.accelerations)):
        if m is not None:
            finite_result(m.vector, f"forward kinematics: {what}")
    return kin


def forward_kinematics(model: Model, q: ArrayLike, v: ArrayLike | None = None, a: ArrayLike | None = None, *, backend: str | None = None) -> Kinematics:
    """World placements, body velocities and spatial accelerations of every body.

    Args:
        model: the tree.
        q: `(..., nq)` configuration.
        v: `(..., nv)` joint velocity (optional).
        a: `(..., nv)` joint acceleration (optional; needs ``v``).
        backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

    Returns:
        :class:`~featherdyn.results.Kinematics`, gravity *not* included in the accelerations::

            ᵖM_i = ᵖM_J · M_J(q_i),   ⁰M_i = ⁰M_λ(i) · ᵖM_i
            v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    """
    core = core_path(model, backend)
    if core is not None and (v is not None or a is None):
        shape = (core.nb, 4, 4)
        H, Hp = _EMPTY(shape), _EMPTY(shape)
        vel = None if v is None else _EMPTY((core.nb, 6))
        acc = None if a is None else _EMPTY((core.nb, 6))
        try:
            if CORE.fk(core.cm, q, v, a, H, Hp, vel, acc) == OK:
                return _kinematics(model, H, Hp, vel, acc, _F64)
        except TypeError:  # arguments the binding does not take as they are: the general path converts
            pass
    if _dask.lazy(q, v, a):
        return _dask.call(forward_kinematics, model, {"q": q, "v": v, "a": a}, backend=backend)
    if a is not None and v is None:
        raise ShapeError("a: joint accelerations need joint velocities v as well")
    st = check_state(model, q, optional=("v", "a"), v=v, a=a)
    return kinematics_of(model, st, st.arrays.get("v"), st.arrays.get("a"), backend)


def _general_frame_placement(model: Model, q: ArrayLike, frame: str | int, *, backend: str | None = None) -> PluckerTransform:
    """The world placement ``⁰M_f`` of a frame (name or index), batch shape `(...)`::

        ⁰M_f = ⁰M_body(f) · placement_f
    """
    if _dask.lazy(q):
        return _dask.call(frame_placement, model, {"q": q}, frame=frame, backend=backend)
    fid = _frame(model, frame)
    st = check_state(model, q)
    oMf = quiet(_kin.frame_pose, model, kinematics_of(model, st, None, None, backend), fid)
    finite_result(oMf.translation, "frame_placement")
    return oMf


#: one float64 state finished in the compiled core (``_backend.public_call``)
frame_placement = public_call("frame_placement", _general_frame_placement, (
    CoreHandle, PluckerTransform, "rotation", "translation", "source", "target"))


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
