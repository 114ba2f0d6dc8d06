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

import numpy as np
from numpy.typing import ArrayLike

from .._validation import as_array
from ..errors import QuaternionNormError
from ..rotation import quat_to_matrix
from ..spatial_algebra import SpatialMotion
from ..tolerances import QUATERNION_NORM
from ._common import _cat, _foreign_array, _matvec, _motion_array

__all__ = [
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
    qq = _foreign_array(qpos, "qpos", "MuJoCo [x y z, qw qx qy qz]", (7,))
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
    vv = _motion_array(v, "v")
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    R = quat_to_matrix(qq[..., 3:], check_norm=False)
    return _cat(_matvec(R, vv[..., 3:]), vv[..., :3])


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
    qv = _foreign_array(qvel, "qvel", "MuJoCo [v_world; ω_body]")
    R = quat_to_matrix(q[..., 3:], check_norm=False)
    Rt = np.swapaxes(R, -1, -2)
    return _cat(qv[..., 3:], _matvec(Rt, qv[..., :3]))
