"""Forward kinematics and frame quantities: placements, velocities, spatial and classical accelerations.

The forward pass of every recursive algorithm (chapter §8.1, RBDA §5.3)::

    ᵖM_i   = ᵖM_J · M_J(q_i)               X_up[i] = (ᵖM_i)⁻¹   (motion: parent → body i)
    v_i    = X_up[i] v_λ(i) + S_i q̇_i
    a_i    = X_up[i] a_λ(i) + S_i q̈_i + v_i × (S_i q̇_i)
    ⁰M_i   = ⁰M_λ(i) · ᵖM_i

Velocities and accelerations are body-frame spatial vectors (Pinocchio's
``data.v``, ``data.a``). The *spatial* acceleration is the time derivative of
the spatial velocity; the *classical* acceleration of the frame origin adds
``ω × v`` to its linear part (chapter §7.2).
"""

from __future__ import annotations

import numpy as np

from ..errors import ShapeError
from ..frames import ReferenceFrame
from ..model import Model
from ..results import Kinematics
from ..spatial import PluckerTransform, SpatialMotion, cross_motion
from ..spatial.ops import cross3
from ._common import TreeData, batch_dtype, stack_motions, stack_transforms

__all__ = [
    "forward_kinematics",
    "frame_pose",
    "frame_velocity",
    "frame_acceleration",
    "frame_classical_acceleration",
]


def forward_kinematics(model: Model, q: np.ndarray, qd: np.ndarray | None = None,
                       qdd: np.ndarray | None = None) -> Kinematics:
    """World placements, body velocities and spatial accelerations of every body, on checked arrays.

    Args:
        model: the tree.
        q: `(..., nq)`; qd, qdd: `(..., nv)` ``q̇`` and ``q̈`` (optional; ``qdd`` needs ``qd``).

    Returns:
        :class:`~featherdyn.results.Kinematics`; the recursion is the module's.
        Gravity is *not* included in the accelerations. Public entry:
        :func:`featherdyn.forward_kinematics`.
    """
    batch, dtype = batch_dtype(q, qd, qdd)
    td = TreeData(model, dtype)
    oM: list[PluckerTransform] = []
    pM: list[PluckerTransform] = []
    vel: list[SpatialMotion] = []
    acc: list[SpatialMotion] = []
    for i in range(td.nb):
        lam = td.parents[i]
        pM_i = td.pose_in_parent(q, i)
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
        placements=stack_transforms(oM, batch, dtype),
        velocities=stack_motions(vel, batch, dtype) if qd is not None else None,
        accelerations=stack_motions(acc, batch, dtype) if qdd is not None else None,
        parent_placements=stack_transforms(pM, batch, dtype),
    )


def forward_kinematics_at(model: Model, q: np.ndarray, qd: np.ndarray | None = None, qdd: np.ndarray | None = None
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """:func:`forward_kinematics` as the core's arrays: ``(⁰M, ᵖM, v, a)``, homogeneous `(..., nb, 4, 4)` twice,
    then `(..., nb, 6)` (``None`` without ``qd``, ``qdd``) — the declaration's reference."""
    if qdd is not None and qd is None:
        raise ShapeError("a: needs v as well (got v=None)")
    kin = forward_kinematics(model, q, qd, qdd)
    return (kin.placements.homogeneous(), kin.parent_placements.homogeneous(),
            None if kin.velocities is None else kin.velocities.vector,
            None if kin.accelerations is None else kin.accelerations.vector)


def placements_at(model: Model, q: np.ndarray) -> np.ndarray:
    """The bodies' world placements ``⁰M_i`` `(..., nb, 4, 4)` (homogeneous), the declaration's reference."""
    return forward_kinematics(model, q).placements.homogeneous()


def frame_placement_at(model: Model, q: np.ndarray, frame: int) -> tuple[np.ndarray, np.ndarray]:
    """``(R, p)`` `(..., 3, 3)`, `(..., 3)` of a frame's world placement ``⁰M_f = ⁰M_body(f) · placement_f``."""
    oMf = frame_pose(model, forward_kinematics(model, q), frame)
    return oMf.rotation, oMf.translation


def body_at(X: PluckerTransform, i: int) -> PluckerTransform:
    """Body ``i`` of per-body transforms: rotation `(..., nb, 3, 3)` → `(..., 3, 3)`, translation likewise."""
    return PluckerTransform._wrap(X.rotation[..., i, :, :], X.translation[..., i, :], None, None)


def motion_at(m: SpatialMotion, i: int) -> SpatialMotion:
    """Body ``i`` of per-body motions: `(..., nb, 6)` → `(..., 6)`."""
    return SpatialMotion._wrap(m.vector[..., i, :], None)


def frame_pose(model: Model, kin: Kinematics, fid: int) -> PluckerTransform:
    """The world placement ``⁰M_f = ⁰M_body(f) · placement_f`` of frame ``fid``, batch shape `(...)`."""
    f = model.frames[fid]
    place = f.placement.rotation.astype(kin.placements.dtype), f.placement.translation.astype(kin.placements.dtype)
    fM = PluckerTransform._wrap(place[0], place[1], None, None)
    if f.body == -1:
        batch = kin.placements.shape[:-1]
        return PluckerTransform._wrap(np.broadcast_to(fM.rotation, batch + (3, 3)).copy(),
                                      np.broadcast_to(fM.translation, batch + (3,)).copy(), None, None)
    return body_at(kin.placements, f.body) @ fM


def _express(model: Model, kin: Kinematics, fid: int, m_body: SpatialMotion | None, reference: ReferenceFrame,
             batch: tuple[int, ...]) -> tuple[SpatialMotion, PluckerTransform]:
    """A body-frame motion of the frame's body, re-expressed per ``reference``; also returns ⁰M_f."""
    f = model.frames[fid]
    oMf = frame_pose(model, kin, fid)
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


def frame_velocity(model: Model, kin: Kinematics, fid: int, ref: ReferenceFrame) -> SpatialMotion:
    """The spatial velocity of a frame `(..., 6)` in ``reference`` (Pinocchio's ``getFrameVelocity``).

    ::

        LOCAL:  ᶠv = ᶠX_b v_b      WORLD: ⁰X_f ᶠv      LOCAL_WORLD_ALIGNED: [R ω; R v]
    """
    body = model.frames[fid].body
    assert kin.velocities is not None
    batch = kin.placements.shape[:-1]
    m = None if body == -1 else motion_at(kin.velocities, body)
    return _express(model, kin, fid, m, ref, batch)[0]


def frame_acceleration(model: Model, kin: Kinematics, fid: int, ref: ReferenceFrame) -> SpatialMotion:
    """The *spatial* acceleration of a frame `(..., 6)` in ``reference`` (``getFrameAcceleration``).

    The time derivative of the spatial velocity, without gravity; re-expressed
    exactly like :func:`frame_velocity`. Its linear part is **not** the
    acceleration of the frame origin: see :func:`frame_classical_acceleration`.
    """
    body = model.frames[fid].body
    assert kin.accelerations is not None
    batch = kin.placements.shape[:-1]
    m = None if body == -1 else motion_at(kin.accelerations, body)
    return _express(model, kin, fid, m, ref, batch)[0]


def frame_classical_acceleration(model: Model, kin: Kinematics, fid: int, ref: ReferenceFrame) -> SpatialMotion:
    """The classical acceleration of a frame `(..., 6)` (``getFrameClassicalAcceleration``).

    Angular part ``ω̇``; linear part the classical acceleration, chapter §7.2::

        a_classical = a_spatial + [0; ω × v]      (ω, v of the frame, in the same reference)

    In ``LOCAL`` and ``LOCAL_WORLD_ALIGNED`` the linear part is the acceleration
    of the frame origin (in frame or world axes). In ``WORLD`` it is that of the
    body point passing through the world origin (Pinocchio's convention).
    """
    body = model.frames[fid].body
    assert kin.velocities is not None and kin.accelerations is not None
    batch = kin.placements.shape[:-1]
    if body == -1:
        return _express(model, kin, fid, None, ref, batch)[0]
    vel = _express(model, kin, fid, motion_at(kin.velocities, body), ref, batch)[0]
    acc = _express(model, kin, fid, motion_at(kin.accelerations, body), ref, batch)[0]
    lin = acc.linear + cross3(vel.angular, vel.linear)
    return SpatialMotion._wrap(np.concatenate([acc.angular, lin], axis=-1), None)


def frame_velocity_at(model: Model, q: np.ndarray, qd: np.ndarray, frame: int, reference: ReferenceFrame
                      ) -> np.ndarray:
    """:func:`frame_velocity` of the state `(..., 6)` (the declaration's reference)."""
    return frame_velocity(model, forward_kinematics(model, q, qd), frame, reference).vector


def frame_acceleration_at(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, frame: int,
                          reference: ReferenceFrame) -> np.ndarray:
    """:func:`frame_acceleration` of the state `(..., 6)` (the declaration's reference)."""
    return frame_acceleration(model, forward_kinematics(model, q, qd, qdd), frame, reference).vector


def frame_classical_acceleration_at(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, frame: int,
                                    reference: ReferenceFrame) -> np.ndarray:
    """:func:`frame_classical_acceleration` of the state `(..., 6)` (the declaration's reference)."""
    return frame_classical_acceleration(model, forward_kinematics(model, q, qd, qdd), frame, reference).vector
