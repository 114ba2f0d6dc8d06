"""MuJoCo: the free joint's ``qpos`` / ``qvel``, and quaternion component order.

MuJoCo (like Drake and SciPy's ``scalar_first=True``) writes quaternions
``(w, x, y, z)``; featherdyn, Pinocchio, Eigen's ``coeffs`` and ROS write
``(x, y, z, w)``. A free joint's ``qpos`` is ``[x y z, qw qx qy qz]``; its
``qvel`` is the velocity of the body origin in *world* axes, then the angular
velocity in *body* axes, where featherdyn's free-flyer ``v = [ω_b; v_b]`` has
both in body axes::

    qvel = [R v_b; ω_b]

Sources: MuJoCo documentation, free joint; SciPy ``Rotation``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import QuaternionNormError, ShapeError
from ..rotation import quat_to_matrix
from ..spatial import SpatialMotion
from ..spatial.ops import matvec
from ..spatial.validation import as_array
from ..tolerances import QUATERNION_NORM
from ._common import cat, foreign_array, motion_array

__all__ = [
    "a_from_mujoco",
    "a_to_mujoco",
    "joint_matrix_from_mujoco",
    "joint_matrix_to_mujoco",
    "mujoco_velocity_map",
    "q_from_mujoco",
    "q_to_mujoco",
    "tau_from_mujoco",
    "tau_to_mujoco",
    "v_from_mujoco",
    "v_to_mujoco",
    "freeflyer_q_from_mujoco",
    "freeflyer_q_to_mujoco",
    "freeflyer_v_from_mujoco",
    "freeflyer_v_to_mujoco",
    "quat_wxyz_to_xyzw",
    "quat_xyzw_to_wxyz",
]


def _check_unit_quat(quat: np.ndarray, name: str, order: str) -> None:
    if quat.dtype.kind == "O":
        return
    norm = np.sqrt(np.sum(quat * quat, axis=-1))
    tol = QUATERNION_NORM.of(quat.dtype)
    bad = np.abs(norm - 1) > tol
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0]) if bad.ndim else ()
        where = f" at batch index {idx}" if idx else ""
        raise QuaternionNormError(
            f"{name}: expected a unit quaternion in {order} order, got norm {float(norm[idx]):.9g}{where} "
            f"(tolerance {tol:g})"
        )


def quat_xyzw_to_wxyz(quat: ArrayLike) -> np.ndarray:
    """Reorder quaternions from (x, y, z, w) (featherdyn, Pinocchio, Eigen ``coeffs``, ROS) to (w, x, y, z).

    Only the order changes; the norm is not checked (use it for any
    quaternion, unit or not).

    Args:
        quat: `(..., 4)` ``(x, y, z, w)``.

    Returns:
        `(..., 4)`::

            (w, x, y, z)

    Source: MuJoCo, SciPy ``scalar_first=True``, Drake use (w, x, y, z).
    """
    q = as_array(quat, "quat", (4,))
    return q[..., [3, 0, 1, 2]]


def quat_wxyz_to_xyzw(quat: ArrayLike) -> np.ndarray:
    """Reorder quaternions from (w, x, y, z) (MuJoCo, Drake) to featherdyn's (x, y, z, w).

    Args:
        quat: `(..., 4)` ``(w, x, y, z)``.

    Returns:
        `(..., 4)`::

            (x, y, z, w)

    Source: see :func:`quat_xyzw_to_wxyz`.
    """
    q = as_array(quat, "quat", (4,))
    return q[..., [1, 2, 3, 0]]


def freeflyer_q_to_mujoco(q: ArrayLike) -> np.ndarray:
    """A featherdyn free-flyer configuration as a MuJoCo free joint's ``qpos``.

    Args:
        q: `(..., 7)` ``[x y z, qx qy qz qw]`` (unit quaternion, checked).

    Returns:
        `(..., 7)` ``qpos``::

            [x y z, qw qx qy qz]

    Raises:
        QuaternionNormError: the quaternion is off unit norm by more than
            ``featherdyn.tolerances.QUATERNION_NORM`` for its dtype.

    Source: MuJoCo documentation, free joint (``qpos`` = position, then a
    (w, x, y, z) unit quaternion).
    """
    qq = as_array(q, "q", (7,))
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    return qq[..., [0, 1, 2, 6, 3, 4, 5]]


def freeflyer_q_from_mujoco(qpos: ArrayLike) -> np.ndarray:
    """A MuJoCo free joint's ``qpos`` as a featherdyn free-flyer configuration.

    Args:
        qpos: `(..., 7)` ``[x y z, qw qx qy qz]`` (unit quaternion, checked).

    Returns:
        `(..., 7)`::

            [x y z, qx qy qz qw]

    Source: MuJoCo documentation, free joint.
    """
    qq = foreign_array(qpos, "qpos", "MuJoCo [x y z, qw qx qy qz]", (7,))
    _check_unit_quat(qq[..., 3:], "qpos[..., 3:7]", "(w, x, y, z)")
    return qq[..., [0, 1, 2, 4, 5, 6, 3]]


def freeflyer_v_to_mujoco(q: ArrayLike, v: SpatialMotion | ArrayLike) -> np.ndarray:
    """A featherdyn free-flyer velocity as a MuJoCo free joint's ``qvel``.

    featherdyn's ``v = [ω_b; v_b]`` is the base's spatial velocity in base
    coordinates (``v_b`` the velocity of the base origin, in base axes);
    MuJoCo's ``qvel`` is the velocity of the body origin in *world* axes,
    then the angular velocity in *body* axes.

    Args:
        q: `(..., 7)` featherdyn configuration ``[x y z, qx qy qz qw]`` (for ``R``).
        v: `(..., 6)` featherdyn ``[ω_b; v_b]``.

    Returns:
        `(..., 6)` ``qvel``::

            qvel = [R v_b; ω_b],   R = quat_to_matrix(q[3:7]) (base axes in world)

    Source: MuJoCo documentation, free joint (``qvel``: linear velocity in
    the global frame, angular velocity in the local frame).
    """
    qq = as_array(q, "q", (7,))
    vv = motion_array(v, "v")
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    R = quat_to_matrix(qq[..., 3:], check_norm=False)
    return cat(matvec(R, vv[..., 3:]), vv[..., :3])


def freeflyer_v_from_mujoco(qpos: ArrayLike, qvel: ArrayLike) -> np.ndarray:
    """A MuJoCo free joint's ``qvel`` as a featherdyn free-flyer velocity.

    Args:
        qpos: `(..., 7)` MuJoCo ``[x y z, qw qx qy qz]`` (for ``R``).
        qvel: `(..., 6)` MuJoCo ``[v_world; ω_b]``.

    Returns:
        `(..., 6)` featherdyn ``[ω_b; v_b]``::

            v = [ω_b; Rᵀ v_world]

    Source: MuJoCo documentation, free joint.
    """
    q = freeflyer_q_from_mujoco(qpos)
    qv = foreign_array(qvel, "qvel", "MuJoCo [v_world; ω_body]")
    R = quat_to_matrix(q[..., 3:], check_norm=False)
    Rt = np.swapaxes(R, -1, -2)
    return cat(qv[..., 3:], matvec(Rt, qv[..., :3]))


# ---------------------------------------------------------------------------
# whole models (featherdyn.load_mjcf): qpos / qvel / qacc / qfrc and joint-space matrices
# ---------------------------------------------------------------------------
#
# load_mjcf keeps MuJoCo's joint order, so q and qpos (v and qvel) have the same layout; per joint:
#   hinge / slide  q = qpos (the joint's ref is folded into its placement),  v = qvel
#   ball           q = qpos reordered (w, x, y, z) -> (x, y, z, w),          v = qvel (ω in the body frame)
#   free           see freeflyer_q_* / freeflyer_v_* above
# The velocity map T (v = T qvel) is the identity except on free joints, where
#   T = [[0, 1], [Rᵀ, 0]]   (3×3 blocks),   so   τ_mujoco = Tᵀ τ,   M_mujoco = Tᵀ M T.
# The model is read by duck typing (joints[i].kind, idx_q, nqs, idx_v, nvs): this layer may not import Model.

_MJ_KINDS = ("revolute", "prismatic", "spherical", "free_flyer")


def _joint_slices(model: Any) -> list[tuple[str, int, int, int, int]]:
    out = []
    for i, joint in enumerate(model.joints):
        kind = joint.kind
        if kind not in _MJ_KINDS:
            raise ShapeError(f"joint {model.joint_names[i]!r}: a {kind} joint has no MuJoCo equivalent "
                             f"(MuJoCo has hinge, slide, ball and free joints)")
        out.append((kind, model.idx_q[i], model.nqs[i], model.idx_v[i], model.nvs[i]))
    return out


def q_to_mujoco(model: Any, q: ArrayLike) -> np.ndarray:
    """A featherdyn configuration of a model loaded by :func:`featherdyn.load_mjcf` as MuJoCo's ``qpos``.

    Args:
        model: the featherdyn model (same joint order as MuJoCo's).
        q: `(..., nq)`.

    Returns:
        `(..., nq)` ``qpos``, per joint::

            hinge, slide: qpos = q;   ball: (x, y, z, w) -> (w, x, y, z);   free: freeflyer_q_to_mujoco

    Source: MuJoCo documentation, joint types and the ``qpos`` layout.
    """
    qq = as_array(q, "q", (sum(model.nqs),))
    out = qq.copy()
    for kind, iq, _, _, _ in _joint_slices(model):
        if kind == "spherical":
            _check_unit_quat(qq[..., iq:iq + 4], f"q[..., {iq}:{iq + 4}]", "(x, y, z, w)")
            out[..., iq:iq + 4] = quat_xyzw_to_wxyz(qq[..., iq:iq + 4])
        elif kind == "free_flyer":
            out[..., iq:iq + 7] = freeflyer_q_to_mujoco(qq[..., iq:iq + 7])
    return out


def q_from_mujoco(model: Any, qpos: ArrayLike) -> np.ndarray:
    """MuJoCo's ``qpos`` as a featherdyn configuration (inverse of :func:`q_to_mujoco`).

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        qpos: `(..., nq)`.

    Returns:
        `(..., nq)` ``q``::

            hinge, slide: q = qpos;   ball: (w, x, y, z) -> (x, y, z, w);   free: freeflyer_q_from_mujoco

    Source: MuJoCo documentation, joint types and the ``qpos`` layout.
    """
    qq = foreign_array(qpos, "qpos", "MuJoCo qpos", (sum(model.nqs),))
    out = qq.copy()
    for kind, iq, _, _, _ in _joint_slices(model):
        if kind == "spherical":
            _check_unit_quat(qq[..., iq:iq + 4], f"qpos[..., {iq}:{iq + 4}]", "(w, x, y, z)")
            out[..., iq:iq + 4] = quat_wxyz_to_xyzw(qq[..., iq:iq + 4])
        elif kind == "free_flyer":
            out[..., iq:iq + 7] = freeflyer_q_from_mujoco(qq[..., iq:iq + 7])
    return out


def mujoco_velocity_map(model: Any, q: ArrayLike) -> np.ndarray:
    """``T`` `(..., nv, nv)` with ``v = T qvel`` at the featherdyn configuration ``q`` `(..., nq)`.

    The identity except on each free joint's block (``R`` the body's
    orientation in the world; ``T`` is orthogonal, ``T⁻¹ = Tᵀ``)::

        T_free = [[0, 1], [Rᵀ, 0]],   v = T qvel,   qfrc = Tᵀ τ,   M_mujoco = Tᵀ M T

    Source: MuJoCo documentation, free joint (``qvel``: world linear
    velocity, then body angular velocity).
    """
    qq = as_array(q, "q", (sum(model.nqs),))
    nv = sum(model.nvs)
    T = np.zeros(qq.shape[:-1] + (nv, nv), dtype=np.result_type(qq.dtype, np.float64))
    T[..., np.arange(nv), np.arange(nv)] = 1
    for kind, iq, _, iv, _ in _joint_slices(model):
        if kind == "free_flyer":
            R = quat_to_matrix(qq[..., iq + 3:iq + 7], check_norm=False)
            T[..., iv:iv + 6, iv:iv + 6] = 0
            T[..., iv:iv + 3, iv + 3:iv + 6] = np.eye(3)
            T[..., iv + 3:iv + 6, iv:iv + 3] = np.swapaxes(R, -1, -2)
    return T


def v_to_mujoco(model: Any, q: ArrayLike, v: ArrayLike) -> np.ndarray:
    """A featherdyn velocity as MuJoCo's ``qvel``.

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        q: `(..., nq)` featherdyn configuration; v: `(..., nv)`.

    Returns:
        `(..., nv)`::

            qvel = Tᵀ v       (T = mujoco_velocity_map(model, q))

    Source: MuJoCo documentation, free and ball joints.
    """
    vv = as_array(v, "v", (sum(model.nvs),))
    return matvec(np.swapaxes(mujoco_velocity_map(model, q), -1, -2), vv)


def v_from_mujoco(model: Any, qpos: ArrayLike, qvel: ArrayLike) -> np.ndarray:
    """MuJoCo's ``qvel`` as a featherdyn velocity.

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        qpos: `(..., nq)`; qvel: `(..., nv)`.

    Returns:
        `(..., nv)`::

            v = T qvel

    Source: MuJoCo documentation, free and ball joints.
    """
    q = q_from_mujoco(model, qpos)
    qv = foreign_array(qvel, "qvel", "MuJoCo qvel", (sum(model.nvs),))
    return matvec(mujoco_velocity_map(model, q), qv)


def a_from_mujoco(model: Any, qpos: ArrayLike, qvel: ArrayLike, qacc: ArrayLike) -> np.ndarray:
    """MuJoCo's ``qacc`` as a featherdyn acceleration ``a = v̇``.

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        qpos: `(..., nq)`; qvel, qacc: `(..., nv)`.

    Returns:
        `(..., nv)`: ``a = T qacc + Ṫ qvel``; on a free joint (``v_b = Rᵀ v_world``)::

            a = [ω̇_b;  Rᵀ v̇_world − ω_b × v_b]

    Source: MuJoCo documentation, free joint; the derivative of ``v = T qvel``.
    """
    q = q_from_mujoco(model, qpos)
    qv = foreign_array(qvel, "qvel", "MuJoCo qvel", (sum(model.nvs),))
    qa = foreign_array(qacc, "qacc", "MuJoCo qacc", (sum(model.nvs),))
    T = mujoco_velocity_map(model, q)
    a = matvec(T, qa)
    v = matvec(T, qv)
    for kind, _, _, iv, _ in _joint_slices(model):
        if kind == "free_flyer":
            a[..., iv + 3:iv + 6] -= np.cross(v[..., iv:iv + 3], v[..., iv + 3:iv + 6])
    return a


def a_to_mujoco(model: Any, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> np.ndarray:
    """A featherdyn acceleration as MuJoCo's ``qacc`` (inverse of :func:`a_from_mujoco`).

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        q: `(..., nq)`; v, a: `(..., nv)`.

    Returns:
        `(..., nv)` ``qacc``; on a free joint::

            qacc = [R (v̇_b + ω_b × v_b);  ω̇_b]

    Source: MuJoCo documentation, free joint.
    """
    vv = as_array(v, "v", (sum(model.nvs),))
    aa = as_array(a, "a", (sum(model.nvs),))
    aa, vv = np.broadcast_arrays(aa, vv)
    aa = aa.astype(np.result_type(aa.dtype, np.float64), copy=True)
    for kind, _, _, iv, _ in _joint_slices(model):
        if kind == "free_flyer":
            aa[..., iv + 3:iv + 6] += np.cross(vv[..., iv:iv + 3], vv[..., iv + 3:iv + 6])
    return matvec(np.swapaxes(mujoco_velocity_map(model, q), -1, -2), aa)


def tau_to_mujoco(model: Any, q: ArrayLike, tau: ArrayLike) -> np.ndarray:
    """Joint forces ``τ`` as MuJoCo generalized forces (``qfrc_bias``, ``qfrc_inverse``, ...).

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        q: `(..., nq)`; tau: `(..., nv)`.

    Returns:
        `(..., nv)`; on a free joint ``[n_b; f_b] -> [R f_b; n_b]``::

            qfrc = Tᵀ τ

    Source: MuJoCo documentation, free joint; power ``τ·v = qfrc·qvel``.
    """
    tt = as_array(tau, "tau", (sum(model.nvs),))
    return matvec(np.swapaxes(mujoco_velocity_map(model, q), -1, -2), tt)


def tau_from_mujoco(model: Any, qpos: ArrayLike, qfrc: ArrayLike) -> np.ndarray:
    """MuJoCo generalized forces as featherdyn ``τ`` (inverse of :func:`tau_to_mujoco`).

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        qpos: `(..., nq)`; qfrc: `(..., nv)`.

    Returns:
        `(..., nv)`::

            τ = T qfrc       (T orthogonal)

    Source: MuJoCo documentation, free joint.
    """
    q = q_from_mujoco(model, qpos)
    f = foreign_array(qfrc, "qfrc", "MuJoCo qfrc", (sum(model.nvs),))
    return matvec(mujoco_velocity_map(model, q), f)


def joint_matrix_to_mujoco(model: Any, q: ArrayLike, M: ArrayLike) -> np.ndarray:
    """A joint-space matrix (mass matrix, ``∂τ/∂q̈``) in MuJoCo's coordinates.

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        q: `(..., nq)`; M: `(..., nv, nv)`.

    Returns:
        `(..., nv, nv)` (``mj_fullM``'s layout)::

            M_mujoco = Tᵀ M T

    Source: MuJoCo documentation, ``mj_fullM``; kinetic energy ``½ vᵀ M v``.
    """
    mm = as_array(M, "M", (sum(model.nvs), sum(model.nvs)))
    T = mujoco_velocity_map(model, q)
    return np.swapaxes(T, -1, -2) @ mm @ T


def joint_matrix_from_mujoco(model: Any, qpos: ArrayLike, M: ArrayLike) -> np.ndarray:
    """A joint-space matrix from MuJoCo's coordinates (inverse of :func:`joint_matrix_to_mujoco`).

    Args:
        model: the featherdyn model from :func:`featherdyn.load_mjcf`.
        qpos: `(..., nq)`; M: `(..., nv, nv)`.

    Returns:
        `(..., nv, nv)`::

            M = T M_mujoco Tᵀ

    Source: MuJoCo documentation, ``mj_fullM``.
    """
    q = q_from_mujoco(model, qpos)
    mm = foreign_array(M, "M", "MuJoCo joint-space", (sum(model.nvs), sum(model.nvs)))
    T = mujoco_velocity_map(model, q)
    return T @ mm @ np.swapaxes(T, -1, -2)
