"""Drake (monogram notation), the classical acceleration, and a ``MultibodyPlant``'s ``q`` / ``v``.

Drake's ``SpatialVelocity`` ``[ω; v]`` and ``SpatialForce`` ``[τ; f]`` are
ordered like featherdyn's, but Drake changes the reference point
(``Shift``) and the axes (``R_AE * V_E``) in two separate steps, and its
``SpatialAcceleration`` is the *classical* acceleration ``[α; a_Bo]`` (of a
body point), not Featherstone's spatial one. The conversion between the two
accelerations is the same for Pinocchio's ``getFrameClassicalAcceleration``::

    a_O(classical) = v̇_O(spatial) + ω × v_O

A plant's state differs from featherdyn's in three ways, converted here by the
whole-model functions ``*_to_drake`` / ``*_from_drake`` (a :class:`DrakeLayout`
says where each featherdyn joint's coordinates sit in Drake's vectors; Drake
orders the coordinates its own way: in Drake 1.51 the floating joints' first)::

    free-flyer q:  featherdyn [x y z, qx qy qz qw]   Drake [qw qx qy qz, x y z]
    free-flyer v:  featherdyn [ω_b; v_b] (base axes)   Drake [ω_WB; v_WBo] (world axes):  v_drake = V v
    gravity:       Drake's CalcGravityGeneralizedForces is τ_g = −g(q) (a force on the tree, featherdyn's
                   g(q) the torque that holds it):  g = −Vᵀ τ_g

with ``V`` the permutation of the coordinates, ``blockdiag(R, R)`` on each free
block (``R`` the base's orientation; ``V`` is orthogonal, so ``τ_drake = V τ``
and ``M_drake = V M Vᵀ``). Drake's ``v̇`` of a floating body is the rate of its
world-frame ``[ω; v_WBo]``, the classical acceleration of the base origin::

    v̇_drake = V a + V̇ v,   free block  [R ω̇_b;  R (v̇_b + ω_b × v_b)]

so Drake's ``CalcBiasTerm`` (``C v`` at ``v̇_drake = 0``) is featherdyn's
``rnea(q, v, a₀) − g(q)`` at ``a₀ = a_from_drake(…, v̇ = 0)``. A Drake Jacobian
``J_V_WF_W`` (``CalcJacobianSpatialVelocity`` with respect to ``v``, measured in
the world, at the frame origin, expressed in the world) is featherdyn's
``LOCAL_WORLD_ALIGNED`` one in Drake's columns: :func:`jacobian_from_drake`.

Sources: Drake ``multibody/math/spatial_{velocity,force,acceleration,vector}.h``,
``multibody/tree/quaternion_floating_joint.h``, ``multibody/plant/multibody_plant.h``
(``CalcGravityGeneralizedForces``, ``CalcBiasTerm``, ``CalcJacobianSpatialVelocity``);
chapter §2.1, §2.2 and §7.2; RBDA (2008) §2.11.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ShapeError, SpatialTypeError
from ..frames import Frame, ReferenceFrame, as_reference_frame, merge_frames
from ..rotation import quat_to_matrix
from ..spatial import PluckerTransform, SpatialForce, SpatialMotion
from ..spatial.ops import matvec
from ..spatial.validation import as_array, check_rotation
from ._common import as_transform, cat, featherdyn_array, force_array, foreign_array, motion_array
from .mujoco import _check_unit_quat

__all__ = [
    "DrakeLayout",
    "a_from_drake",
    "a_to_drake",
    "drake_velocity_map",
    "freeflyer_q_from_drake",
    "freeflyer_q_to_drake",
    "freeflyer_v_from_drake",
    "freeflyer_v_to_drake",
    "generalized_gravity_from_drake",
    "generalized_gravity_to_drake",
    "jacobian_from_drake",
    "jacobian_to_drake",
    "joint_matrix_from_drake",
    "joint_matrix_to_drake",
    "q_from_drake",
    "q_to_drake",
    "tau_from_drake",
    "tau_to_drake",
    "v_from_drake",
    "v_to_drake",
    "velocity_from_drake",
    "velocity_to_drake",
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


# ---------------------------------------------------------------------------
# a MultibodyPlant's q / v / v̇ / generalized forces, and its Jacobians
# ---------------------------------------------------------------------------
#
# The model is read by duck typing (joints[i].kind, joint_names, idx_q, nqs, idx_v, nvs): this layer may not import
# Model. Drake's revolute and prismatic joints have featherdyn's q and v; its QuaternionFloatingJoint is the
# free-flyer above; other joints (Drake's BallRpyJoint, PlanarJoint, ...) are refused.

_DRAKE_KINDS = ("revolute", "prismatic", "free_flyer")


@dataclass(frozen=True, slots=True)
class DrakeLayout:
    """Where each featherdyn joint's coordinates sit in a Drake plant's ``q`` and ``v``.

    Attributes:
        q_start: `(njoints,)` per featherdyn joint (the model's order), Drake's ``Joint.position_start()``.
        v_start: `(njoints,)` per featherdyn joint, Drake's ``Joint.velocity_start()``.

    Drake's vectors have featherdyn's lengths (``nq``, ``nv``): every coordinate of
    the plant belongs to one featherdyn joint (the converters check it)::

        q_drake[q_start[i] : q_start[i] + nq_i]  ↔  q[idx_q[i] : idx_q[i] + nq_i]   (and so for v)

    ``featherdyn.verify.drake`` builds it from a plant, joints matched by name.

    Source: Drake ``Joint::position_start``, ``Joint::velocity_start``.
    """

    q_start: tuple[int, ...]
    v_start: tuple[int, ...]


def _slices(model: Any, layout: DrakeLayout) -> list[tuple[str, int, int, int, int, int, int]]:
    """Per joint: ``(kind, iq, nq, iv, nv, drake_iq, drake_iv)``; a joint Drake's converters do not know refused."""
    if len(layout.q_start) != len(model.joints) or len(layout.v_start) != len(model.joints):
        raise ShapeError(f"layout: expected one q_start and one v_start per joint ({len(model.joints)}), got "
                         f"{len(layout.q_start)} and {len(layout.v_start)}")
    out = []
    for i, joint in enumerate(model.joints):
        if joint.kind not in _DRAKE_KINDS:
            raise ShapeError(f"joint {model.joint_names[i]!r}: the Drake converters take revolute, prismatic and "
                             f"free-flyer joints, not a {joint.kind} joint")
        out.append((joint.kind, model.idx_q[i], model.nqs[i], model.idx_v[i], model.nvs[i],
                    int(layout.q_start[i]), int(layout.v_start[i])))
    nq, nv = sum(model.nqs), sum(model.nvs)
    for what, total, spans in (("q", nq, [(s[5], s[2]) for s in out]), ("v", nv, [(s[6], s[4]) for s in out])):
        covered = np.zeros(total, dtype=int)
        for start, n in spans:
            if start < 0 or start + n > total:
                raise ShapeError(f"layout: a {what} start {start} (+{n}) is outside Drake's {what} of length {total}")
            covered[start:start + n] += 1
        if np.any(covered != 1):
            raise ShapeError(f"layout: the joints' {what} ranges do not tile Drake's {what} (index "
                             f"{int(np.argmax(covered != 1))} is covered {int(covered[np.argmax(covered != 1)])} times)")
    return out


def freeflyer_q_to_drake(q: ArrayLike) -> np.ndarray:
    """A featherdyn free-flyer configuration as Drake's ``QuaternionFloatingJoint`` positions.

    Args:
        q: `(..., 7)` ``[x y z, qx qy qz qw]`` (unit quaternion, checked).

    Returns:
        `(..., 7)`::

            [qw qx qy qz, x y z]

    Source: Drake ``multibody/tree/quaternion_floating_joint.h`` (quaternion first, scalar first).
    """
    qq = as_array(q, "q", (7,))
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    return qq[..., [6, 3, 4, 5, 0, 1, 2]]


def freeflyer_q_from_drake(q_drake: ArrayLike) -> np.ndarray:
    """Drake's ``QuaternionFloatingJoint`` positions as a featherdyn free-flyer configuration.

    Args:
        q_drake: `(..., 7)` ``[qw qx qy qz, x y z]`` (unit quaternion, checked).

    Returns:
        `(..., 7)`::

            [x y z, qx qy qz qw]

    Source: Drake ``multibody/tree/quaternion_floating_joint.h``.
    """
    qq = foreign_array(q_drake, "q_drake", "Drake [qw qx qy qz, x y z]", (7,))
    _check_unit_quat(qq[..., :4], "q_drake[..., 0:4]", "(w, x, y, z)")
    return qq[..., [4, 5, 6, 1, 2, 3, 0]]


def freeflyer_v_to_drake(q: ArrayLike, v: SpatialMotion | ArrayLike) -> np.ndarray:
    """A featherdyn free-flyer velocity as Drake's ``QuaternionFloatingJoint`` velocities.

    featherdyn's ``v = [ω_b; v_b]`` is the base's spatial velocity in base
    coordinates at the base origin; Drake's is ``[ω_WB; v_WBo]``, the same
    vector in world axes.

    Args:
        q: `(..., 7)` featherdyn ``[x y z, qx qy qz qw]`` (for ``R``).
        v: `(..., 6)` featherdyn ``[ω_b; v_b]``.

    Returns:
        `(..., 6)`::

            [R ω_b; R v_b],   R = quat_to_matrix(q[3:7]) (base axes in world)

    Source: Drake ``multibody/tree/quaternion_floating_joint.h`` (``w_FM``, ``v_FM`` expressed in F = world).
    """
    qq = as_array(q, "q", (7,))
    vv = motion_array(v, "v")
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    R = quat_to_matrix(qq[..., 3:], check_norm=False)
    return cat(matvec(R, vv[..., :3]), matvec(R, vv[..., 3:]))


def freeflyer_v_from_drake(q_drake: ArrayLike, v_drake: ArrayLike) -> np.ndarray:
    """Drake's ``QuaternionFloatingJoint`` velocities as a featherdyn free-flyer velocity.

    Args:
        q_drake: `(..., 7)` Drake ``[qw qx qy qz, x y z]`` (for ``R``).
        v_drake: `(..., 6)` ``[ω_WB; v_WBo]`` in world axes.

    Returns:
        `(..., 6)` featherdyn ``[ω_b; v_b]``::

            [Rᵀ ω_WB; Rᵀ v_WBo]

    Source: Drake ``multibody/tree/quaternion_floating_joint.h``.
    """
    q = freeflyer_q_from_drake(q_drake)
    vd = foreign_array(v_drake, "v_drake", "Drake [ω_WB; v_WBo] (world axes)")
    Rt = np.swapaxes(quat_to_matrix(q[..., 3:], check_norm=False), -1, -2)
    return cat(matvec(Rt, vd[..., :3]), matvec(Rt, vd[..., 3:]))


def q_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike) -> np.ndarray:
    """A featherdyn configuration as a Drake plant's positions.

    Args:
        model: the featherdyn model; layout: where its joints sit in the plant.
        q: `(..., nq)`.

    Returns:
        `(..., nq)` Drake's ``q``, per joint at ``layout.q_start``::

            revolute, prismatic: the same;   free-flyer: freeflyer_q_to_drake

    Source: Drake ``Joint::position_start``; ``quaternion_floating_joint.h``.
    """
    slices = _slices(model, layout)
    qq = as_array(q, "q", (sum(model.nqs),))
    out = np.empty_like(qq)
    for kind, iq, nq, _, _, dq, _ in slices:
        part = qq[..., iq:iq + nq]
        out[..., dq:dq + nq] = freeflyer_q_to_drake(part) if kind == "free_flyer" else part
    return out


def q_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike) -> np.ndarray:
    """A Drake plant's positions as a featherdyn configuration (inverse of :func:`q_to_drake`).

    Args:
        model: the featherdyn model; layout: where its joints sit in the plant.
        q_drake: `(..., nq)`.

    Returns:
        `(..., nq)` featherdyn's ``q``::

            revolute, prismatic: the same;   free-flyer: freeflyer_q_from_drake

    Source: Drake ``Joint::position_start``; ``quaternion_floating_joint.h``.
    """
    slices = _slices(model, layout)
    qd = foreign_array(q_drake, "q_drake", "Drake positions", (sum(model.nqs),))
    out = np.empty_like(qd)
    for kind, iq, nq, _, _, dq, _ in slices:
        part = qd[..., dq:dq + nq]
        out[..., iq:iq + nq] = freeflyer_q_from_drake(part) if kind == "free_flyer" else part
    return out


def drake_velocity_map(model: Any, layout: DrakeLayout, q: ArrayLike) -> np.ndarray:
    """``V`` `(..., nv, nv)` with ``v_drake = V v`` at the featherdyn configuration ``q`` `(..., nq)`.

    A permutation of the coordinates, with ``blockdiag(R, R)`` on each free
    block (``R`` the base's orientation in the world). ``V`` is orthogonal::

        v_drake = V v,   τ_drake = V τ,   M_drake = V M Vᵀ,   J_drake = J Vᵀ

    Source: Drake ``Joint::velocity_start``; ``quaternion_floating_joint.h``.
    """
    slices = _slices(model, layout)
    qq = as_array(q, "q", (sum(model.nqs),))
    nv = sum(model.nvs)
    V = np.zeros(qq.shape[:-1] + (nv, nv), dtype=np.result_type(qq.dtype, np.float64))
    for kind, iq, _, iv, n, _, dv in slices:
        if kind == "free_flyer":
            _check_unit_quat(qq[..., iq + 3:iq + 7], f"q[..., {iq + 3}:{iq + 7}]", "(x, y, z, w)")
            R = quat_to_matrix(qq[..., iq + 3:iq + 7], check_norm=False)
            V[..., dv:dv + 3, iv:iv + 3] = R
            V[..., dv + 3:dv + 6, iv + 3:iv + 6] = R
        else:
            V[..., np.arange(dv, dv + n), np.arange(iv, iv + n)] = 1
    return V


def _transpose(x: np.ndarray) -> np.ndarray:
    return np.swapaxes(x, -1, -2)


def v_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, v: ArrayLike) -> np.ndarray:
    """A featherdyn velocity as a Drake plant's velocities.

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`; v: `(..., nv)`.

    Returns:
        `(..., nv)`::

            v_drake = V v       (V = drake_velocity_map(model, layout, q))

    Source: Drake ``Joint::velocity_start``; ``quaternion_floating_joint.h``.
    """
    vv = as_array(v, "v", (sum(model.nvs),))
    return matvec(drake_velocity_map(model, layout, q), vv)


def v_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike, v_drake: ArrayLike) -> np.ndarray:
    """A Drake plant's velocities as a featherdyn velocity (inverse of :func:`v_to_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q_drake: `(..., nq)`; v_drake: `(..., nv)`.

    Returns:
        `(..., nv)`::

            v = Vᵀ v_drake

    Source: Drake ``Joint::velocity_start``; ``quaternion_floating_joint.h``.
    """
    q = q_from_drake(model, layout, q_drake)
    vd = foreign_array(v_drake, "v_drake", "Drake velocities", (sum(model.nvs),))
    return matvec(_transpose(drake_velocity_map(model, layout, q)), vd)


def _free_omega_cross_v(slices: Sequence[tuple[str, int, int, int, int, int, int]], v: np.ndarray) -> np.ndarray:
    """``V̇ v`` pulled back by ``Vᵀ``: ``[0; ω_b × v_b]`` on each free block, zero elsewhere, `(..., nv)`."""
    out = np.zeros_like(v)
    for kind, _, _, iv, _, _, _ in slices:
        if kind == "free_flyer":
            out[..., iv + 3:iv + 6] = np.cross(v[..., iv:iv + 3], v[..., iv + 3:iv + 6])
    return out


def a_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> np.ndarray:
    """A featherdyn acceleration ``a = v̇`` as a Drake plant's ``v̇``.

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`; v, a: `(..., nv)`.

    Returns:
        `(..., nv)` ``v̇_drake = V a + V̇ v``; on a free block::

            [R ω̇_b;  R (v̇_b + ω_b × v_b)]

    Source: the derivative of ``v_drake = V v`` (``Ṙ = R [ω_b]×``).
    """
    slices = _slices(model, layout)
    vv = as_array(v, "v", (sum(model.nvs),))
    aa = as_array(a, "a", (sum(model.nvs),))
    aa, vv = np.broadcast_arrays(aa, vv)
    aa = aa.astype(np.result_type(aa.dtype, np.float64)) + _free_omega_cross_v(slices, vv)
    return matvec(drake_velocity_map(model, layout, q), aa)


def a_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike, v_drake: ArrayLike,
                 vdot_drake: ArrayLike) -> np.ndarray:
    """A Drake plant's ``v̇`` as a featherdyn acceleration (inverse of :func:`a_to_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q_drake: `(..., nq)`; v_drake, vdot_drake: `(..., nv)`.

    Returns:
        `(..., nv)`; on a free block (``v_b = Rᵀ v_WBo``)::

            a = Vᵀ v̇_drake − [0; ω_b × v_b]

    Source: the derivative of ``v_drake = V v``.
    """
    slices = _slices(model, layout)
    q = q_from_drake(model, layout, q_drake)
    Vt = _transpose(drake_velocity_map(model, layout, q))
    vd = foreign_array(v_drake, "v_drake", "Drake velocities", (sum(model.nvs),))
    ad = foreign_array(vdot_drake, "vdot_drake", "Drake accelerations", (sum(model.nvs),))
    v = matvec(Vt, vd)
    return matvec(Vt, ad) - _free_omega_cross_v(slices, v)


def tau_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, tau: ArrayLike) -> np.ndarray:
    """Joint forces ``τ`` as a Drake plant's generalized forces (``CalcInverseDynamics``'s output).

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`; tau: `(..., nv)`.

    Returns:
        `(..., nv)`; on a free block ``[n_b; f_b] -> [R n_b; R f_b]`` (moment about the base origin)::

            τ_drake = V τ       (power τ·v = τ_drake·v_drake, V orthogonal)

    Source: Drake ``MultibodyPlant::CalcInverseDynamics``; ``quaternion_floating_joint.h``.
    """
    tt = as_array(tau, "tau", (sum(model.nvs),))
    return matvec(drake_velocity_map(model, layout, q), tt)


def tau_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike, tau_drake: ArrayLike) -> np.ndarray:
    """A Drake plant's generalized forces as featherdyn joint forces (inverse of :func:`tau_to_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q_drake: `(..., nq)`; tau_drake: `(..., nv)`.

    Returns:
        `(..., nv)`::

            τ = Vᵀ τ_drake

    Source: Drake ``MultibodyPlant::CalcInverseDynamics``.
    """
    q = q_from_drake(model, layout, q_drake)
    td = foreign_array(tau_drake, "tau_drake", "Drake generalized forces", (sum(model.nvs),))
    return matvec(_transpose(drake_velocity_map(model, layout, q)), td)


def generalized_gravity_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, g: ArrayLike) -> np.ndarray:
    """featherdyn's gravity torques ``g(q)`` as Drake's ``CalcGravityGeneralizedForces``.

    featherdyn's ``g(q)`` is what the joints apply to hold the robot still
    (``rnea(q, 0, 0)``); Drake's ``τ_g`` is the force gravity applies to the
    tree, on the right-hand side of ``M v̇ + C v = τ_g + τ``: the opposite sign.

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`; g: `(..., nv)`.

    Returns:
        `(..., nv)`::

            τ_g = −V g

    Source: Drake ``MultibodyPlant::CalcGravityGeneralizedForces`` (measured: ``τ_g = −V g`` to 4e-15 on solo12).
    """
    return -tau_to_drake(model, layout, q, g)


def generalized_gravity_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike,
                                   tau_g: ArrayLike) -> np.ndarray:
    """Drake's ``CalcGravityGeneralizedForces`` as featherdyn's ``g(q)`` (inverse of
    :func:`generalized_gravity_to_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q_drake: `(..., nq)`; tau_g: `(..., nv)`.

    Returns:
        `(..., nv)`::

            g = −Vᵀ τ_g

    Source: Drake ``MultibodyPlant::CalcGravityGeneralizedForces``.
    """
    return -tau_from_drake(model, layout, q_drake, tau_g)


def joint_matrix_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, M: ArrayLike) -> np.ndarray:
    """A joint-space matrix (``M``, ``∂τ/∂a``) in a Drake plant's coordinates (``CalcMassMatrix``).

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`; M: `(..., nv, nv)`.

    Returns:
        `(..., nv, nv)`::

            M_drake = V M Vᵀ       (kinetic energy ½ vᵀ M v = ½ v_drakeᵀ M_drake v_drake)

    Source: Drake ``MultibodyPlant::CalcMassMatrix``.
    """
    n = sum(model.nvs)
    mm = as_array(M, "M", (n, n))
    V = drake_velocity_map(model, layout, q)
    return V @ mm @ _transpose(V)


def joint_matrix_from_drake(model: Any, layout: DrakeLayout, q_drake: ArrayLike, M_drake: ArrayLike) -> np.ndarray:
    """A joint-space matrix from a Drake plant's coordinates (inverse of :func:`joint_matrix_to_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q_drake: `(..., nq)`; M_drake: `(..., nv, nv)`.

    Returns:
        `(..., nv, nv)`::

            M = Vᵀ M_drake V

    Source: Drake ``MultibodyPlant::CalcMassMatrix``.
    """
    n = sum(model.nvs)
    q = q_from_drake(model, layout, q_drake)
    md = foreign_array(M_drake, "M_drake", "Drake joint-space", (n, n))
    V = drake_velocity_map(model, layout, q)
    return _transpose(V) @ md @ V


def _reference_map(placement: PluckerTransform | ArrayLike, ref: ReferenceFrame | str) -> np.ndarray:
    """``W`` `(..., 6, 6)`: featherdyn's ``[ω; v]`` in ``ref`` = ``W`` · Drake's ``V_WF_W`` (at the frame origin Fo,
    world axes), for the frame F at ``placement`` (its pose in the world)."""
    X = as_transform(placement, "placement")
    R, p = X.rotation, X.translation
    W = np.zeros(R.shape[:-2] + (6, 6), dtype=np.result_type(R.dtype, np.float64))
    reference = as_reference_frame(ref)
    if reference is ReferenceFrame.LOCAL_WORLD_ALIGNED:
        W[..., np.arange(6), np.arange(6)] = 1
    elif reference is ReferenceFrame.LOCAL:
        W[..., :3, :3] = _transpose(R)
        W[..., 3:, 3:] = _transpose(R)
    else:  # WORLD: the body point at the world origin, v_O = v_Fo + ω × (0 − p) = v_Fo + [p]× ω
        W[..., np.arange(6), np.arange(6)] = 1
        px, py, pz = p[..., 0], p[..., 1], p[..., 2]
        W[..., 3, 1], W[..., 3, 2] = -pz, py
        W[..., 4, 0], W[..., 4, 2] = pz, -px
        W[..., 5, 0], W[..., 5, 1] = -py, px
    return W


def velocity_from_drake(V_WF_W: ArrayLike, placement: PluckerTransform | ArrayLike,
                        ref: ReferenceFrame | str) -> np.ndarray:
    """A Drake spatial velocity ``V_WF_W`` (of frame F in the world, at Fo, in world axes) in a featherdyn reference.

    Drake's ``SpatialVelocity`` is ``[ω; v]`` like featherdyn's; what differs
    is the point and the axes. ``V_WF_W`` is featherdyn's
    ``LOCAL_WORLD_ALIGNED``; with F's pose ``(R, p)`` in the world::

        LOCAL_WORLD_ALIGNED:  [ω; v_Fo]
        LOCAL:                [Rᵀ ω; Rᵀ v_Fo]
        WORLD:                [ω; v_Fo + p × ω]       (the body point at the world origin)

    Args:
        V_WF_W: `(..., 6)` raw ``[ω_WF; v_WFo]`` (Drake ``SpatialVelocity.get_coeffs()``).
        placement: `(..., 4, 4)` or :class:`PluckerTransform`, F's pose in the world (``X_WF``).
        ref: ``fd.LOCAL``, ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED``.

    Returns:
        `(..., 6)` featherdyn ``[ω; v]`` in ``ref`` (what ``fd.frame_velocity`` returns).

    Source: Drake ``multibody/math/spatial_velocity.h`` (``Shift``, ``R_AE * V_E``); chapter §2.1.
    """
    Vd = foreign_array(V_WF_W, "V_WF_W", "Drake [ω; v] at the frame origin, world axes")
    return matvec(_reference_map(placement, ref), Vd)


def velocity_to_drake(velocity: SpatialMotion | ArrayLike, placement: PluckerTransform | ArrayLike,
                      ref: ReferenceFrame | str) -> np.ndarray:
    """A featherdyn frame velocity in ``ref`` as Drake's ``V_WF_W`` (inverse of :func:`velocity_from_drake`).

    Args:
        velocity: `(..., 6)` featherdyn ``[ω; v]`` of the frame in ``ref``.
        placement: `(..., 4, 4)` or :class:`PluckerTransform`, the frame's pose in the world.
        ref: the reference ``velocity`` is in.

    Returns:
        `(..., 6)` ``[ω_WF; v_WFo]`` in world axes::

            V_WF_W = W⁻¹ v,   W the map of velocity_from_drake

    Source: Drake ``multibody/math/spatial_velocity.h``.
    """
    vv = motion_array(velocity, "velocity")
    return np.linalg.solve(_reference_map(placement, ref), vv[..., None])[..., 0]


def jacobian_from_drake(model: Any, layout: DrakeLayout, q: ArrayLike, J_V_WF_W: ArrayLike,
                        placement: PluckerTransform | ArrayLike, ref: ReferenceFrame | str) -> np.ndarray:
    """Drake's ``CalcJacobianSpatialVelocity`` (with respect to ``v``, measured in the world, at the frame
    origin, expressed in the world) as featherdyn's ``frame_jacobian(model, q, frame, ref)``.

    Rows convert as :func:`velocity_from_drake`, columns as ``v_drake = V v``::

        J = W J_drake V

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)` featherdyn configuration.
        J_V_WF_W: `(..., 6, nv)` Drake's Jacobian (rows ``[ω; v]``, Drake's columns).
        placement: `(..., 4, 4)` or :class:`PluckerTransform`, the frame's pose in the world.
        ref: ``fd.LOCAL``, ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED``.

    Returns:
        `(..., 6, nv)` featherdyn's Jacobian (rows ``[ω; v]`` in ``ref``, featherdyn's columns).

    Source: Drake ``MultibodyPlant::CalcJacobianSpatialVelocity`` (``JacobianWrtVariable.kV``).
    """
    n = sum(model.nvs)
    Jd = foreign_array(J_V_WF_W, "J_V_WF_W", "Drake rows [ω; v] (world axes, frame origin)", (6, n))
    return _reference_map(placement, ref) @ Jd @ drake_velocity_map(model, layout, q)


def jacobian_to_drake(model: Any, layout: DrakeLayout, q: ArrayLike, J: ArrayLike,
                      placement: PluckerTransform | ArrayLike, ref: ReferenceFrame | str) -> np.ndarray:
    """featherdyn's ``frame_jacobian`` in ``ref`` as Drake's ``J_V_WF_W`` (inverse of :func:`jacobian_from_drake`).

    Args:
        model, layout: as :func:`q_to_drake`; q: `(..., nq)`.
        J: `(..., 6, nv)` featherdyn's Jacobian in ``ref``.
        placement: `(..., 4, 4)` or :class:`PluckerTransform`, the frame's pose in the world.
        ref: the reference ``J`` is in.

    Returns:
        `(..., 6, nv)`::

            J_drake = W⁻¹ J Vᵀ

    Source: Drake ``MultibodyPlant::CalcJacobianSpatialVelocity``.
    """
    n = sum(model.nvs)
    JJ = as_array(J, "J", (6, n))
    return np.linalg.solve(_reference_map(placement, ref), JJ) @ _transpose(drake_velocity_map(model, layout, q))
