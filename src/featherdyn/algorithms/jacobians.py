"""Geometric Jacobians and their time variation.

The column block of joint ``k`` in the world-frame Jacobian of body ``b`` is
the joint's motion subspace carried to the world, for every ``k`` on the path
from the root to ``b`` (RBDA §4.5; Pinocchio's ``data.J``)::

    ⁰J_b[:, k] = ⁰X_k S_k          ⁰J̇_b[:, k] = ⁰v_k × ⁰X_k S_k

(``⁰v_k`` is body ``k``'s spatial velocity in world coordinates.) A frame's
Jacobian in ``LOCAL`` is ``ᶠX_0 ⁰J``, in ``LOCAL_WORLD_ALIGNED`` its blocks are
rotated back to world axes. With ``v_f = J q̇`` the frame velocity::

    LOCAL:                 a_f (spatial)   = J q̈ + J̇ q̇
    LOCAL_WORLD_ALIGNED:   a_f (classical) = J q̈ + J̇ q̇     ([ω̇; p̈_origin] in world axes)
"""

from __future__ import annotations

import numpy as np

from ..frames import ReferenceFrame
from ..model import Model
from ..results import Kinematics
from ..spatial import PluckerTransform, SpatialMotion
from ..spatial.ops import crm_apply
from ._common import TreeData, expand, zeros
from .kinematics import body_at, forward_kinematics, frame_pose, motion_at

__all__ = ["joint_jacobians", "joint_jacobians_at", "frame_jacobian", "frame_jacobian_at", "frame_jacobian_time_variation",
           "frame_jacobian_time_variation_at", "support"]


def support(model: Model, body: int) -> list[int]:
    """The bodies from the root to ``body`` (inclusive), root first; empty for the world."""
    path = []
    while body != -1:
        path.append(body)
        body = model.parents[body]
    return path[::-1]


def world_columns(model: Model, td: TreeData, oM: PluckerTransform, batch: tuple[int, ...]) -> np.ndarray:
    """``⁰X_k S_k`` for every joint, as `(..., nv, 6)` motion columns."""
    cols = zeros(batch, (model.nv, 6), td.dtype)
    for k in range(model.nbodies):
        S_cols = SpatialMotion._wrap(np.ascontiguousarray(td.S[k].T), None)  # (nv_k, 6)
        sk = slice(model.idx_v[k], model.idx_v[k] + model.nvs[k])
        cols[..., sk, :] = expand(body_at(oM, k)).apply(S_cols).vector
    return cols


def joint_jacobians(model: Model, kin: Kinematics) -> np.ndarray:
    """All joint columns in the world frame, `(..., 6, nv)` (Pinocchio's ``computeJointJacobians`` → ``data.J``).

    ::

        J[:, k] = ⁰X_k S_k      (the Jacobian of body b keeps the columns of its support)
    """
    batch, dtype = kin.placements.shape[:-1], kin.placements.dtype
    td = TreeData(model, dtype)
    return np.swapaxes(world_columns(model, td, kin.placements, batch), -1, -2)


def mask_support(cols: np.ndarray, model: Model, body: int) -> np.ndarray:
    """``cols`` `(..., nv, 6)` with the columns of joints outside the support of ``body`` set to zero."""
    out = np.zeros_like(cols) if cols.dtype.kind != "O" else zeros(cols.shape[:-2], cols.shape[-2:], cols.dtype)
    for k in support(model, body):
        sk = slice(model.idx_v[k], model.idx_v[k] + model.nvs[k])
        out[..., sk, :] = cols[..., sk, :]
    return out


def _to_reference(cols_world: np.ndarray, oMf: PluckerTransform, ref: ReferenceFrame) -> np.ndarray:
    """Re-express world motion columns `(..., nv, 6)` in ``ref`` for the frame at ``oMf``."""
    if ref is ReferenceFrame.WORLD:
        return cols_world
    local = expand(oMf).apply_inverse(SpatialMotion._wrap(cols_world, None)).vector
    if ref is ReferenceFrame.LOCAL:
        return local
    R = oMf.rotation[..., None, :, :]
    return np.concatenate([(R @ local[..., :3, None])[..., 0], (R @ local[..., 3:, None])[..., 0]], axis=-1)


def frame_jacobian(model: Model, kin: Kinematics, fid: int, ref: ReferenceFrame) -> np.ndarray:
    """The geometric Jacobian of frame ``fid``, `(..., 6, nv)`, rows ``[ω; v]`` (``getFrameJacobian``).

    ``frame_velocity(model, q, v, frame, reference) = J @ v``; ``kin`` holds the placements.
    """
    batch, dtype = kin.placements.shape[:-1], kin.placements.dtype
    td = TreeData(model, dtype)
    body = model.frames[fid].body
    cols = mask_support(world_columns(model, td, kin.placements, batch), model, body)
    return np.swapaxes(_to_reference(cols, frame_pose(model, kin, fid), ref), -1, -2)


def frame_jacobian_at(model: Model, q: np.ndarray, frame: int, reference: ReferenceFrame) -> np.ndarray:
    """:func:`frame_jacobian` at the configurations ``q`` `(..., nq)`: `(..., 6, nv)` (public:
    :func:`featherdyn.frame_jacobian`)."""
    return frame_jacobian(model, forward_kinematics(model, q), frame, reference)


def frame_jacobian_time_variation(model: Model, kin: Kinematics, qd: np.ndarray, fid: int,
                                  ref: ReferenceFrame) -> np.ndarray:
    """``J̇ = dJ/dt`` of :func:`frame_jacobian` along ``q̇ = v``, `(..., 6, nv)` (``getFrameJacobianTimeVariation``).

    ::

        WORLD:   ⁰J̇[:, k] = ⁰v_k × ⁰J[:, k]
        LOCAL:   ᶠJ̇ = ᶠX_0 ⁰J̇ − ᶠv × ᶠJ
        LWA:     J̇ = blkdiag([ω]×, [ω]×) J_LWA + blkdiag(R, R) ᶠJ̇      (ω, R of the frame in the world)

    and the classical acceleration identity ``a_classical = J q̈ + J̇ q̇`` in LOCAL_WORLD_ALIGNED.
    """
    assert kin.velocities is not None
    batch, dtype = kin.placements.shape[:-1], kin.placements.dtype
    td = TreeData(model, dtype)
    body = model.frames[fid].body
    cols = mask_support(world_columns(model, td, kin.placements, batch), model, body)
    dcols = zeros(batch, (model.nv, 6), dtype)
    for k in support(model, body):
        sk = slice(model.idx_v[k], model.idx_v[k] + model.nvs[k])
        v_world = body_at(kin.placements, k).apply(motion_at(kin.velocities, k)).vector
        dcols[..., sk, :] = crm_apply(v_world[..., None, :], cols[..., sk, :])
    if ref is ReferenceFrame.WORLD:
        return np.swapaxes(dcols, -1, -2)
    oMf = frame_pose(model, kin, fid)
    J_local = _to_reference(cols, oMf, ReferenceFrame.LOCAL)
    v_local = (J_local * qd[..., :, None]).sum(axis=-2)  # ᶠv = J q̇
    dJ_local = _to_reference(dcols, oMf, ReferenceFrame.LOCAL) - crm_apply(v_local[..., None, :], J_local)
    if ref is ReferenceFrame.LOCAL:
        return np.swapaxes(dJ_local, -1, -2)
    R = oMf.rotation[..., None, :, :]
    w_world = (oMf.rotation @ v_local[..., :3, None])[..., 0]
    J_lwa = _to_reference(cols, oMf, ReferenceFrame.LOCAL_WORLD_ALIGNED)
    rot_dJ = np.concatenate([(R @ dJ_local[..., :3, None])[..., 0], (R @ dJ_local[..., 3:, None])[..., 0]], axis=-1)
    wx = np.concatenate([w_world, np.zeros_like(w_world)], axis=-1)[..., None, :]
    # blkdiag([ω]×, [ω]×) J = [ω × J_ω; ω × J_v] = crm([ω; 0]) J
    return np.swapaxes(crm_apply(wx, J_lwa) + rot_dJ, -1, -2)


def joint_jacobians_at(model: Model, q: np.ndarray) -> np.ndarray:
    """:func:`joint_jacobians` at ``q`` `(..., 6, nv)` (public: :func:`featherdyn.joint_jacobians`)."""
    return joint_jacobians(model, forward_kinematics(model, q))


def frame_jacobian_time_variation_at(model: Model, q: np.ndarray, qd: np.ndarray, frame: int,
                                     reference: ReferenceFrame) -> np.ndarray:
    """:func:`frame_jacobian_time_variation` at ``(q, q̇)`` `(..., 6, nv)` (public:
    :func:`featherdyn.frame_jacobian_time_variation`)."""
    return frame_jacobian_time_variation(model, forward_kinematics(model, q, qd), qd, frame, reference)
