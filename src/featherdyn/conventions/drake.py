"""Drake (monogram notation) and the classical acceleration.

Drake's ``SpatialVelocity`` ``[ω; v]`` and ``SpatialForce`` ``[τ; f]`` are
ordered like featherdyn's, but Drake changes the reference point
(``Shift``) and the axes (``R_AE * V_E``) in two separate steps, and its
``SpatialAcceleration`` is the *classical* acceleration ``[α; a_Bo]`` (of a
body point), not Featherstone's spatial one. The conversion between the two
accelerations is the same for Pinocchio's ``getFrameClassicalAcceleration``::

    a_O(classical) = v̇_O(spatial) + ω × v_O

Sources: Drake ``multibody/math/spatial_{velocity,force,acceleration,vector}.h``;
chapter §2.1, §2.2 and §7.2; RBDA (2008) §2.11.
"""

from __future__ import annotations

from typing import overload

import numpy as np
from numpy.typing import ArrayLike

from ..errors import SpatialTypeError
from ..frames import Frame, merge_frames
from ..spatial import SpatialForce, SpatialMotion
from ..spatial.ops import matvec
from ..spatial.validation import as_array, check_rotation
from ._common import cat, featherdyn_array, force_array, foreign_array, motion_array

__all__ = [
    "classical_to_spatial_acceleration",
    "drake_reexpress",
    "drake_shift_acceleration",
    "drake_shift_force",
    "drake_shift_velocity",
    "spatial_to_classical_acceleration",
]


def spatial_to_classical_acceleration(a_spatial: SpatialMotion | ArrayLike, v: SpatialMotion | ArrayLike) -> np.ndarray:
    """Featherstone's spatial acceleration to the classical one (Drake's ``SpatialAcceleration``).

    The spatial acceleration's linear part is the rate of change of ``v_O``
    at the *fixed* point O; the classical one is the acceleration of the
    *body point* that is at O now (what an accelerometer there measures,
    without gravity). Both are expressed in the same frame (any frame: world,
    body, ...); ``v`` is the body's spatial velocity in that frame. The
    result is returned as a plain array on purpose: a classical acceleration
    does not transform as a motion vector.

    Args:
        a_spatial: `(..., 6)` spatial acceleration ``[ω̇; v̇_O]`` (:class:`SpatialMotion` or raw).
        v: `(..., 6)` spatial velocity ``[ω; v_O]`` in the same frame.

    Returns:
        `(..., 6)` classical acceleration ``[ω̇; a_O]``::

            a_O = v̇_O + ω × v_O,   angular part unchanged

    Source: chapter §7.2; RBDA (2008) §2.11; Pinocchio ``getFrameClassicalAcceleration``.
    """
    a = motion_array(a_spatial, "a_spatial")
    vv = motion_array(v, "v")
    merge_frames(
        getattr(a_spatial, "frame", None), getattr(v, "frame", None), "spatial_to_classical_acceleration(a_spatial, v)"
    )
    lin = a[..., 3:] + np.cross(vv[..., :3], vv[..., 3:])
    return cat(a[..., :3], lin)


def classical_to_spatial_acceleration(a_classical: ArrayLike, v: SpatialMotion | ArrayLike, frame: Frame = None) -> SpatialMotion:
    """A classical acceleration (Drake's ``SpatialAcceleration``) to Featherstone's spatial one.

    Args:
        a_classical: `(..., 6)` ``[ω̇; a_O]``, ``a_O`` the acceleration of the body
            point at the frame origin (raw array).
        v: `(..., 6)` spatial velocity ``[ω; v_O]`` in the same frame.
        frame: optional frame tag of the result (defaults to ``v``'s).

    Returns:
        :class:`SpatialMotion` `(..., 6)` ``[ω̇; v̇_O]``::

            v̇_O = a_O − ω × v_O

    Source: chapter §7.2; RBDA (2008) §2.11.
    """
    if isinstance(a_classical, SpatialMotion):
        raise SpatialTypeError(
            "a_classical: got a SpatialMotion; a classical acceleration is not a spatial motion vector and is "
            "passed as a raw (..., 6) array [ω̇; a_O] (as returned by spatial_to_classical_acceleration)"
        )
    a = foreign_array(a_classical, "a_classical", "classical [ω̇; a_O]")
    vv = motion_array(v, "v")
    tag = merge_frames(frame, getattr(v, "frame", None), "classical_to_spatial_acceleration(frame, v)")
    lin = a[..., 3:] - np.cross(vv[..., :3], vv[..., 3:])
    return SpatialMotion.from_vector(cat(a[..., :3], lin), tag)


def drake_shift_velocity(V_WBo_E: SpatialMotion | ArrayLike, p_BoBq_E: ArrayLike) -> SpatialMotion:
    """Drake ``SpatialVelocity::Shift``: the spatial velocity of frame Bq, fixed to B at offset ``p``.

    Drake's ``SpatialVelocity`` stores ``[ω; v]`` like featherdyn. Shifting is
    featherdyn's change of reference point (a ``PluckerTransform`` with
    ``R = 1`` and translation ``−p``).

    Args:
        V_WBo_E: `(..., 6)` ``[ω_WB; v_WBo]`` expressed in E (:class:`SpatialMotion` or raw).
        p_BoBq_E: `(..., 3)` position of Bq from Bo, expressed in E.

    Returns:
        :class:`SpatialMotion` `(..., 6)` ``V_WBq_E`` (frame tag kept)::

            ω unchanged,   v_WBq = v_WBo + ω × p_BoBq

    Source: Drake ``multibody/math/spatial_velocity.h`` (``Shift``); chapter §2.1.
    """
    V = motion_array(V_WBo_E, "V_WBo_E")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    lin = V[..., 3:] + np.cross(V[..., :3], p)
    return SpatialMotion.from_vector(cat(V[..., :3], lin), getattr(V_WBo_E, "frame", None))


def drake_shift_force(F_Bo_E: SpatialForce | ArrayLike, p_BoBq_E: ArrayLike) -> SpatialForce:
    """Drake ``SpatialForce::Shift``: the same force system with its moment taken about Bq.

    Drake's ``SpatialForce`` stores ``[τ; f]`` (torque first) like featherdyn.

    Args:
        F_Bo_E: `(..., 6)` ``[τ_Bo; f]`` expressed in E (:class:`SpatialForce` or raw).
        p_BoBq_E: `(..., 3)` position of Bq from Bo, expressed in E.

    Returns:
        :class:`SpatialForce` `(..., 6)` ``F_Bq_E`` (frame tag kept)::

            f unchanged,   τ_Bq = τ_Bo − p_BoBq × f

    Source: Drake ``multibody/math/spatial_force.h`` (``Shift``); chapter §2.2.
    """
    F = force_array(F_Bo_E, "F_Bo_E")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    tau = F[..., :3] - np.cross(p, F[..., 3:])
    return SpatialForce.from_vector(cat(tau, F[..., 3:]), getattr(F_Bo_E, "frame", None))


def drake_shift_acceleration(A_WBo_E: ArrayLike, p_BoBq_E: ArrayLike, w_WB_E: ArrayLike) -> np.ndarray:
    """Drake ``SpatialAcceleration::Shift``: the classical acceleration of frame Bq, fixed to B.

    Drake's ``SpatialAcceleration`` is the *classical* acceleration
    ``[α; a_WBo]`` (``a_WBo`` the acceleration of the point Bo), not
    Featherstone's spatial one: convert with
    :func:`spatial_to_classical_acceleration` first.

    Args:
        A_WBo_E: `(..., 6)` classical ``[α_WB; a_WBo]`` expressed in E (raw array).
        p_BoBq_E: `(..., 3)` position of Bq from Bo, expressed in E.
        w_WB_E: `(..., 3)` angular velocity of B in W, expressed in E.

    Returns:
        `(..., 6)` classical ``[α_WB; a_WBq]``::

            α unchanged,   a_WBq = a_WBo + α × p + ω × (ω × p)

    Source: Drake ``multibody/math/spatial_acceleration.h`` (``Shift``).
    """
    if isinstance(A_WBo_E, SpatialMotion):
        raise SpatialTypeError(
            "A_WBo_E: got a SpatialMotion; Drake's SpatialAcceleration is the classical acceleration, passed as a "
            "raw (..., 6) array: convert a featherdyn spatial acceleration with spatial_to_classical_acceleration"
        )
    A = foreign_array(A_WBo_E, "A_WBo_E", "Drake classical [α; a]")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    w = as_array(w_WB_E, "w_WB_E", (3,))
    alpha = A[..., :3]
    lin = A[..., 3:] + np.cross(alpha, p) + np.cross(w, np.cross(w, p))
    return cat(alpha, lin)


@overload
def drake_reexpress(R_AE: ArrayLike, V_E: SpatialMotion, *, frame: Frame = None) -> SpatialMotion: ...
@overload
def drake_reexpress(R_AE: ArrayLike, V_E: SpatialForce, *, frame: Frame = None) -> SpatialForce: ...
@overload
def drake_reexpress(R_AE: ArrayLike, V_E: ArrayLike, *, frame: Frame = None) -> np.ndarray: ...


def drake_reexpress(
    R_AE: ArrayLike, V_E: SpatialMotion | SpatialForce | ArrayLike, *, frame: Frame = None
) -> SpatialMotion | SpatialForce | np.ndarray:
    """Drake's re-expression ``R_AE * V_E``: the same spatial vector in another frame's axes.

    The reference point does not move (unlike ``PluckerTransform.apply``,
    which also moves it to the new origin), so both halves rotate. Works for
    motions and forces alike.

    Args:
        R_AE: `(..., 3, 3)` rotation, E's axes expressed in A.
        V_E: `(..., 6)` :class:`SpatialMotion`, :class:`SpatialForce` or raw array, in E.
        frame: optional frame tag (A) for a typed result.

    Returns:
        The same type as ``V_E`` (raw in, raw out), `(..., 6)`::

            V_A = [R_AE ω; R_AE v]

    Source: Drake ``SpatialVector::operator*`` (``R_AE * V_E``, ``spatial_vector.h``).
    """
    R = as_array(R_AE, "R_AE", (3, 3))
    check_rotation(R, "R_AE")
    if isinstance(V_E, SpatialMotion):
        x = V_E.vector
    elif isinstance(V_E, SpatialForce):
        x = V_E.vector
    else:
        x = featherdyn_array(V_E, "V_E", "spatial vector (SpatialMotion, SpatialForce or raw (..., 6))")
    out = cat(matvec(R, x[..., :3]), matvec(R, x[..., 3:]))
    if isinstance(V_E, SpatialMotion):
        return SpatialMotion(out[..., :3], out[..., 3:], frame, body=V_E.body, relative_to=V_E.relative_to)
    if isinstance(V_E, SpatialForce):
        return SpatialForce.from_vector(out, frame)
    return out
