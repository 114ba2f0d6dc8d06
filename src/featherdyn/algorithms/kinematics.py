"""Forward kinematics and frame quantities: placements, velocities, spatial and classical accelerations.

The forward pass of every recursive algorithm (chapter §8.1, RBDA §5.3)::

    ᵖM_i   = Xtree_i · M_J(q_i)            X_up[i] = (ᵖM_i)⁻¹   (motion: parent → body i)
    v_i    = X_up[i] v_λ(i) + S_i q̇_i
    a_i    = X_up[i] a_λ(i) + S_i q̈_i + v_i × (S_i q̇_i)
    ⁰M_i   = ⁰M_λ(i) · ᵖM_i

Velocities and accelerations are body-frame spatial vectors (Pinocchio's
``data.v``, ``data.a``). The *spatial* acceleration is the time derivative of
the spatial velocity; the *classical* acceleration of the frame origin adds
``ω × v`` to its linear part (chapter §7.2).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..engine import _fast
from ..errors import ModelError, ShapeError
from ..model import Model
from ..spatial_algebra import PluckerTransform, SpatialMotion, _cross3, cross_motion
from ._common import (
    LOCAL,
    ReferenceFrame,
    TreeData,
    as_reference_frame,
    check_state,
    select_backend,
    stack_motions,
    stack_transforms,
)

__all__ = [
    "Kinematics",
    "forward_kinematics",
    "frame_placement",
    "frame_velocity",
    "frame_acceleration",
    "frame_classical_acceleration",
    "resolve_frame",
]


@dataclass(frozen=True)
class Kinematics:
    """The result of :func:`forward_kinematics` (body axis last among the batch axes).

    Attributes:
        placements: world placements ``⁰M_i`` of the bodies, batch shape `(..., nb)`.
        velocities: body velocities ``v_i`` in body coordinates `(..., nb, 6)` (``None`` if no ``v``).
        accelerations: spatial accelerations ``a_i`` in body coordinates `(..., nb, 6)`,
            without gravity (``None`` if no ``a``).
        parent_placements: ``ᵖM_i``, the pose of each body in its parent, `(..., nb)`.
    """

    model: Model
    placements: PluckerTransform
    velocities: SpatialMotion | None
    accelerations: SpatialMotion | None
    parent_placements: PluckerTransform


def _fast_kinematics(fast: Any, q: Any, v: Any, a: Any) -> Kinematics | None:
    """:func:`forward_kinematics` of one float64 state by the checked kernel, or ``None`` (general path)."""
    H = _fast._EMPTY(fast.shape_H)
    vel = _fast._EMPTY(fast.shape_V) if v is not None else _fast.NO_BODIES
    acc = _fast._EMPTY(fast.shape_V) if a is not None else _fast.NO_BODIES
    try:
        status = fast.fk(fast.MD, q, _fast.NO_VECTOR if v is None else v, _fast.NO_VECTOR if a is None else a,
                         H, vel, acc)
    except (TypeError, ValueError):  # Numba refuses the argument types
        return None
    if status != 0:
        return None
    return Kinematics(
        model=fast.model,
        placements=PluckerTransform._wrap(H[0, :, :3, :3], H[0, :, :3, 3], None, None),
        velocities=SpatialMotion._wrap(vel, None) if v is not None else None,
        accelerations=SpatialMotion._wrap(acc, None) if a is not None else None,
        parent_placements=PluckerTransform._wrap(H[1, :, :3, :3], H[1, :, :3, 3], None, None),
    )


def forward_kinematics(model: Model, q: Any, v: Any = None, a: Any = None, *, backend: str | None = None) -> Kinematics:
    """World placements, body velocities and spatial accelerations of every body.

    Args:
        model: the tree.
        q: `(..., nq)` configuration.
        v: `(..., nv)` joint velocity (optional).
        a: `(..., nv)` joint acceleration (optional; needs ``v``).

    Returns:
        :class:`Kinematics`; see the module docstring for the recursion.
        Gravity is *not* included in the accelerations.
    """
    fast = _fast.path(model, backend)
    # one float64 state: the checked kernel validates and computes (see engine/_fast.py)
    if fast is not None and (v is not None or a is None) and fast.fk is not None:
        kin = _fast_kinematics(fast, q, v, a)
        if kin is not None:
            return kin
    if a is not None and v is None:
        raise ShapeError("a: joint accelerations need joint velocities v as well")
    st = check_state(model, q, v=v, a=a)
    if select_backend(backend, st.dtype) == "compiled":
        from ..engine import _dispatch

        return _dispatch.forward_kinematics(model, st.q, st.arrays.get("v"), st.arrays.get("a"), st.dtype)
    td = TreeData(model, st.dtype)
    qd, qdd = st.arrays.get("v"), st.arrays.get("a")
    oM: list[PluckerTransform] = []
    pM: list[PluckerTransform] = []
    vel: list[SpatialMotion] = []
    acc: list[SpatialMotion] = []
    for i in range(td.nb):
        lam = td.parents[i]
        pM_i = td.pose_in_parent(st.q, i)
        X_up = pM_i.inverse()
        pM.append(pM_i)
        oM.append(pM_i if lam == -1 else oM[lam] @ pM_i)
        if qd is None:
            continue
        vJ = td.vJ(qd, i)
        vel.append(vJ if lam == -1 else X_up.apply(vel[lam]) + vJ)
        if qdd is None:
            continue
        a_i = td.vJ(qdd, i) + cross_motion(vel[i], vJ)
        acc.append(a_i if lam == -1 else X_up.apply(acc[lam]) + a_i)
    return Kinematics(
        model=model,
        placements=stack_transforms(oM, st.batch, st.dtype),
        velocities=stack_motions(vel, st.batch, st.dtype) if qd is not None else None,
        accelerations=stack_motions(acc, st.batch, st.dtype) if qdd is not None else None,
        parent_placements=stack_transforms(pM, st.batch, st.dtype),
    )


def resolve_frame(model: Model, frame: Any) -> int:
    """A frame index from a name or an index (:class:`ModelError` when unknown)."""
    if isinstance(frame, str):
        return model.frame_id(frame)
    if isinstance(frame, (int, np.integer)) and not isinstance(frame, bool):
        if not 0 <= int(frame) < len(model.frames):
            if not model.frames:
                raise ModelError(f"frame: index {frame}, but model {model.name!r} has no frames")
            raise ModelError(f"frame: index {frame} out of range 0..{len(model.frames) - 1}")
        return int(frame)
    raise ShapeError(f"frame: expected a frame name or index, got {type(frame).__name__}")


def _body_at(X: PluckerTransform, i: int) -> PluckerTransform:
    return PluckerTransform._wrap(X.rotation[..., i, :, :], X.translation[..., i, :], None, None)


def _motion_at(m: SpatialMotion, i: int) -> SpatialMotion:
    return SpatialMotion._wrap(m.vector[..., i, :], None)


def _frame_pose(model: Model, kin: Kinematics, fid: int) -> PluckerTransform:
    f = model.frames[fid]
    place = f.placement.rotation.astype(kin.placements.dtype), f.placement.translation.astype(kin.placements.dtype)
    fM = PluckerTransform._wrap(place[0], place[1], None, None)
    if f.body == -1:
        batch = kin.placements.shape[:-1]
        return PluckerTransform._wrap(np.broadcast_to(fM.rotation, batch + (3, 3)).copy(),
                                      np.broadcast_to(fM.translation, batch + (3,)).copy(), None, None)
    return _body_at(kin.placements, f.body) @ fM


def frame_placement(model: Model, q: Any, frame: Any, *, backend: str | None = None) -> PluckerTransform:
    """The world placement ``⁰M_f`` of a frame (name or index), batch shape `(...)`::

        ⁰M_f = ⁰M_body(f) · placement_f
    """
    fast = _fast.path(model, backend)
    # one float64 configuration: the checked kernel walks the frame's support (see engine/_fast.py)
    if fast is not None:
        fid_ = fast.frames.get(frame, -1) if frame.__class__ is str else frame
        if fid_.__class__ is int:
            pose = _fast._EMPTY(12)
            try:
                status = fast.frame_placement(fast.MD, q, fid_, pose)
            except (TypeError, ValueError):  # Numba refuses the argument types
                status = -1
            if status == 0:
                return PluckerTransform._wrap(pose[:9].reshape(3, 3), pose[9:], None, None)
    fid = resolve_frame(model, frame)
    return _frame_pose(model, forward_kinematics(model, q, backend=backend), fid)


def _express(model: Model, kin: Kinematics, fid: int, m_body: SpatialMotion | None, reference: ReferenceFrame,
             batch: tuple[int, ...]) -> tuple[SpatialMotion, PluckerTransform]:
    """A body-frame motion of the frame's body, re-expressed per ``reference``; also returns ⁰M_f."""
    f = model.frames[fid]
    oMf = _frame_pose(model, kin, fid)
    if m_body is None:  # a frame fixed to the world does not move
        local = SpatialMotion._wrap(np.zeros(batch + (6,), dtype=oMf.dtype), None)
    else:
        fM = PluckerTransform._wrap(f.placement.rotation.astype(oMf.dtype), f.placement.translation.astype(oMf.dtype),
                                    None, None)
        local = fM.apply_inverse(m_body)
    if reference is ReferenceFrame.LOCAL:
        return local, oMf
    if reference is ReferenceFrame.WORLD:
        return oMf.apply(local), oMf
    rot = oMf.rotation
    return SpatialMotion._wrap(np.concatenate([(rot @ local.angular[..., None])[..., 0],
                                               (rot @ local.linear[..., None])[..., 0]], axis=-1), None), oMf


def frame_velocity(model: Model, q: Any, v: Any, frame: Any, reference: Any = LOCAL, *,
                   backend: str | None = None) -> SpatialMotion:
    """The spatial velocity of a frame `(..., 6)` in ``reference`` (Pinocchio's ``getFrameVelocity``).

    ::

        LOCAL:  ᶠv = ᶠX_b v_b      WORLD: ⁰X_f ᶠv      LOCAL_WORLD_ALIGNED: [R ω; R v]
    """
    fid = resolve_frame(model, frame)
    ref = as_reference_frame(reference)
    kin = forward_kinematics(model, q, v, backend=backend)
    body = model.frames[fid].body
    assert kin.velocities is not None
    batch = kin.placements.shape[:-1]
    m = None if body == -1 else _motion_at(kin.velocities, body)
    return _express(model, kin, fid, m, ref, batch)[0]


def frame_acceleration(model: Model, q: Any, v: Any, a: Any, frame: Any, reference: Any = LOCAL, *,
                       backend: str | None = None) -> SpatialMotion:
    """The *spatial* acceleration of a frame `(..., 6)` in ``reference`` (``getFrameAcceleration``).

    The time derivative of the spatial velocity, without gravity; re-expressed
    exactly like :func:`frame_velocity`. Its linear part is **not** the
    acceleration of the frame origin: see :func:`frame_classical_acceleration`.
    """
    fid = resolve_frame(model, frame)
    ref = as_reference_frame(reference)
    kin = forward_kinematics(model, q, v, a, backend=backend)
    body = model.frames[fid].body
    assert kin.accelerations is not None
    batch = kin.placements.shape[:-1]
    m = None if body == -1 else _motion_at(kin.accelerations, body)
    return _express(model, kin, fid, m, ref, batch)[0]


def frame_classical_acceleration(model: Model, q: Any, v: Any, a: Any, frame: Any, reference: Any = LOCAL, *,
                                 backend: str | None = None) -> SpatialMotion:
    """The classical acceleration of a frame `(..., 6)` (``getFrameClassicalAcceleration``).

    Angular part ``ω̇``; linear part the classical acceleration, chapter §7.2::

        a_classical = a_spatial + [0; ω × v]      (ω, v of the frame, in the same reference)

    In ``LOCAL`` and ``LOCAL_WORLD_ALIGNED`` the linear part is the acceleration
    of the frame origin (in frame or world axes). In ``WORLD`` it is that of the
    body point passing through the world origin (Pinocchio's convention).
    """
    fid = resolve_frame(model, frame)
    ref = as_reference_frame(reference)
    kin = forward_kinematics(model, q, v, a, backend=backend)
    body = model.frames[fid].body
    assert kin.velocities is not None and kin.accelerations is not None
    batch = kin.placements.shape[:-1]
    if body == -1:
        return _express(model, kin, fid, None, ref, batch)[0]
    vel = _express(model, kin, fid, _motion_at(kin.velocities, body), ref, batch)[0]
    acc = _express(model, kin, fid, _motion_at(kin.accelerations, body), ref, batch)[0]
    lin = acc.linear + _cross3(vel.angular, vel.linear)
    return SpatialMotion._wrap(np.concatenate([acc.angular, lin], axis=-1), None)
