"""Converters between featherdyn's conventions and other libraries' (Pinocchio, Lynch–Park, Drake, ROS, MuJoCo).

featherdyn's conventions are fixed (``DESIGN.md``): a motion is ``[ω; v_O]``
and a force ``[n_O; f]`` (angular first, Featherstone); ``PluckerTransform(R, p)``
is the pose of frame A in frame B and maps A- to B-coordinates; the free-flyer
``q`` is ``[x y z, qx qy qz qw]`` and its ``v`` is ``[ω; v]``, the base's spatial
velocity in base coordinates. Everything else converts here, at the boundary,
with a named pair of plain functions ``x_to_y`` / ``y_to_x`` (or
``to_y`` / ``from_y``) that undo each other. Array converters broadcast over
leading batch axes and keep float32 as float32; converters to another library's
*objects* (``pin.Motion``, ``pin.SE3``, ...) take one value at a time.

The 6D swap used for Pinocchio and for flattened ROS messages is the
permutation ``P = [[0, 1], [1, 0]]`` (3×3 blocks), its own inverse::

    x_pin = P x,   M_pin = P M P,   J_pin = P J

=====================================  =====================================  ==========================================================
featherdyn → other                     other → featherdyn                     what changes
=====================================  =====================================  ==========================================================
**Pinocchio** (linear first)
``motion_to_pinocchio``                ``motion_from_pinocchio``              ``[ω; v]`` ↔ ``[v; ω]`` (raw ``(..., 6)``)
``force_to_pinocchio``                 ``force_from_pinocchio``               ``[n; f]`` ↔ ``[f; n]`` (raw ``(..., 6)``)
``matrix6_to_pinocchio``               ``matrix6_from_pinocchio``             ``P M P`` for any 6×6 map (X, X*, crm, inertia)
``jacobian_to_pinocchio``              ``jacobian_from_pinocchio``            rows ``P J`` (and free-flyer columns)
``freeflyer_v_to_pinocchio``           ``freeflyer_v_from_pinocchio``         ``[ω; v]`` ↔ ``[v; ω]`` (both base frame = LOCAL)
``to_pinocchio_motion``                ``from_pinocchio_motion``              ``SpatialMotion`` ↔ ``pin.Motion(linear, angular)``
``to_pinocchio_force``                 ``from_pinocchio_force``               ``SpatialForce`` ↔ ``pin.Force(linear, angular)``
``to_pinocchio_inertia``               ``from_pinocchio_inertia``             ``SpatialInertia`` ↔ ``pin.Inertia(mass, lever, inertia)``
``transform_to_pinocchio_se3``         ``transform_from_pinocchio_se3``       ``PluckerTransform`` ↔ ``pin.SE3`` (same semantics)
(free-flyer ``q``)                     (free-flyer ``q``)                     none: both ``[x y z, qx qy qz qw]``
``continuous_q_to_pinocchio``          ``continuous_q_from_pinocchio``        ``θ`` ↔ ``(cos θ, sin θ)``
``planar_q_to_pinocchio``              ``planar_q_from_pinocchio``            ``[x, y, θ]`` ↔ ``[x, y, cos θ, sin θ]``
``planar_v_to_pinocchio``              ``planar_v_from_pinocchio``            ``[ω, v_x, v_y]`` ↔ ``[v_x, v_y, ω]``
**Lynch–Park / Modern Robotics**
``twist_to_mr``                        ``twist_from_mr``                      none: both ``[ω; v]``
``wrench_to_mr``                       ``wrench_from_mr``                     none: both ``[m; f]``
``body_twist_to_spatial_twist``        ``spatial_twist_to_body_twist``        ``V_s = [Ad_T] V_b``
``adjoint_matrix``                     —                                      ``[Ad_T] = X.matrix()``
``ad_matrix``                          —                                      ``[ad_V] = crm(V)``
``wrench_transform_matrix``            —                                      ``[Ad_T]⁻ᵀ = X.dual_matrix()``
**Drake** (monogram names)
``spatial_to_classical_acceleration``  ``classical_to_spatial_acceleration``  linear part ``± ω × v_O``
``drake_shift_velocity``               (shift by ``−p``)                      ``v_Bq = v_Bo + ω × p``
``drake_shift_force``                  (shift by ``−p``)                      ``τ_Bq = τ_Bo − p × f``
``drake_shift_acceleration``           (shift by ``−p``)                      ``a_Bq = a_Bo + α × p + ω × (ω × p)``
``drake_reexpress``                    (with ``R_AEᵀ``)                       both halves rotated
**ROS** (``geometry_msgs``)
``motion_to_ros_twist``                ``motion_from_ros_twist``              ``{"linear", "angular"}`` mapping
``force_to_ros_wrench``                ``force_from_ros_wrench``              ``{"force", "torque"}`` mapping
``twist_array_to_ros``                 ``twist_array_from_ros``               flattened ``[v; ω]``
``wrench_array_to_ros``                ``wrench_array_from_ros``              flattened ``[f; τ]``
**MuJoCo** (free joint)
``freeflyer_q_to_mujoco``              ``freeflyer_q_from_mujoco``            quaternion ``(x, y, z, w)`` ↔ ``(w, x, y, z)``
``freeflyer_v_to_mujoco``              ``freeflyer_v_from_mujoco``            ``[ω_b; v_b]`` ↔ ``[R v_b; ω_b]``
**Quaternion order**
``quat_xyzw_to_wxyz``                  ``quat_wxyz_to_xyzw``                  component order only
=====================================  =====================================  ==========================================================

Pinocchio is imported lazily, only by the functions that build or read its
objects; without it they raise :class:`MissingDependencyError` (an
``ImportError``). The raw-array Pinocchio converters need no Pinocchio.

Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008) ch. 2;
chapter §2–§3 and §7.2; Lynch & Park, *Modern Robotics* (2017) ch. 3 and 8;
the Pinocchio, Drake, ROS ``geometry_msgs`` and MuJoCo documentation.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ._validation import as_array, check_rotation
from .errors import MissingDependencyError, QuaternionNormError, ShapeError, SpatialTypeError
from .frames import Frame, merge_frames
from .rotation import quat_to_matrix
from .spatial_algebra import PluckerTransform, SpatialForce, SpatialInertia, SpatialMotion, crm
from .tolerances import QUATERNION_NORM, SPATIAL_STRUCTURE

__all__ = [
    "MissingDependencyError",
    "ad_matrix",
    "adjoint_matrix",
    "body_twist_to_spatial_twist",
    "classical_to_spatial_acceleration",
    "continuous_q_from_pinocchio",
    "continuous_q_to_pinocchio",
    "drake_reexpress",
    "drake_shift_acceleration",
    "drake_shift_force",
    "drake_shift_velocity",
    "force_from_pinocchio",
    "force_from_ros_wrench",
    "force_to_pinocchio",
    "force_to_ros_wrench",
    "freeflyer_q_from_mujoco",
    "freeflyer_q_to_mujoco",
    "freeflyer_v_from_mujoco",
    "freeflyer_v_from_pinocchio",
    "freeflyer_v_to_mujoco",
    "freeflyer_v_to_pinocchio",
    "from_pinocchio_force",
    "from_pinocchio_inertia",
    "from_pinocchio_motion",
    "jacobian_from_pinocchio",
    "jacobian_to_pinocchio",
    "matrix6_from_pinocchio",
    "matrix6_to_pinocchio",
    "motion_from_pinocchio",
    "motion_from_ros_twist",
    "motion_to_pinocchio",
    "motion_to_ros_twist",
    "planar_q_from_pinocchio",
    "planar_q_to_pinocchio",
    "planar_v_from_pinocchio",
    "planar_v_to_pinocchio",
    "quat_wxyz_to_xyzw",
    "quat_xyzw_to_wxyz",
    "spatial_to_classical_acceleration",
    "spatial_twist_to_body_twist",
    "to_pinocchio_force",
    "to_pinocchio_inertia",
    "to_pinocchio_motion",
    "transform_from_pinocchio_se3",
    "transform_to_pinocchio_se3",
    "twist_array_from_ros",
    "twist_array_to_ros",
    "twist_from_mr",
    "twist_to_mr",
    "wrench_array_from_ros",
    "wrench_array_to_ros",
    "wrench_from_mr",
    "wrench_to_mr",
    "wrench_transform_matrix",
]



# The half swap [a; b] -> [b; a] of a 6-vector; an involution, so the same
# index array converts in both directions (and for motions and forces alike).
_SWAP = np.array([3, 4, 5, 0, 1, 2])


_SPATIAL_TYPES = (SpatialMotion, SpatialForce, SpatialInertia, PluckerTransform)


# --------------------------------------------------------------------------
# private helpers
# --------------------------------------------------------------------------


def _type_name(x: Any) -> str:
    t = type(x)
    top = t.__module__.split(".")[0]
    return t.__name__ if top == "builtins" else f"{top}.{t.__name__}"


def _is_pinocchio_object(x: Any) -> bool:
    return type(x).__module__.split(".")[0] == "pinocchio"


def _pinocchio(function: str) -> Any:
    """Import Pinocchio on first use; a clear error says how to install it."""
    try:
        import pinocchio
    except ImportError as exc:
        raise MissingDependencyError(
            f"{function} needs Pinocchio, which is not installed: pip install pin (or pip install 'featherdyn[verify]')"
        ) from exc
    return pinocchio


def _motion_array(m: Any, name: str) -> np.ndarray:
    """A featherdyn motion (SpatialMotion or raw ``[ω; v]``) as a ``(..., 6)`` array."""
    if isinstance(m, SpatialMotion):
        return m.vector
    if isinstance(m, SpatialForce):
        raise SpatialTypeError(
            f"{name}: expected a motion vector (SpatialMotion or a raw (..., 6) [ω; v] array), got a SpatialForce; "
            "forces convert with the force_* / *_wrench functions (they are ordered and transformed differently)"
        )
    return _featherdyn_array(m, name, "motion vector (SpatialMotion or a raw (..., 6) [ω; v] array)")


def _force_array(f: Any, name: str) -> np.ndarray:
    """A featherdyn force (SpatialForce or raw ``[n; f]``) as a ``(..., 6)`` array."""
    if isinstance(f, SpatialForce):
        return f.vector
    if isinstance(f, SpatialMotion):
        raise SpatialTypeError(
            f"{name}: expected a force vector (SpatialForce or a raw (..., 6) [n; f] array), got a SpatialMotion; "
            "motions convert with the motion_* / twist_* functions (they are ordered and transformed differently)"
        )
    return _featherdyn_array(m=f, name=name, what="force vector (SpatialForce or a raw (..., 6) [n; f] array)")


def _featherdyn_array(m: Any, name: str, what: str) -> np.ndarray:
    if isinstance(m, _SPATIAL_TYPES):
        raise SpatialTypeError(f"{name}: expected a {what}, got a {_type_name(m)}")
    if _is_pinocchio_object(m):
        raise SpatialTypeError(
            f"{name}: expected a {what}, got a {_type_name(m)}; Pinocchio objects convert with "
            "from_pinocchio_motion / from_pinocchio_force / from_pinocchio_inertia / transform_from_pinocchio_se3"
        )
    return as_array(m, name, (6,))


def _foreign_array(x: Any, name: str, layout: str, trailing: tuple[int, ...] = (6,)) -> np.ndarray:
    """A raw array in another library's layout; featherdyn values (already converted) are refused."""
    if isinstance(x, _SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a raw array in {layout} order, got a {_type_name(x)}, which is a featherdyn value "
            "already (angular first); use it directly, or convert it with the matching *_to_* function"
        )
    if _is_pinocchio_object(x):
        raise SpatialTypeError(
            f"{name}: expected a raw array in {layout} order, got a {_type_name(x)}; Pinocchio objects convert with "
            "from_pinocchio_motion / from_pinocchio_force / from_pinocchio_inertia / transform_from_pinocchio_se3"
        )
    return as_array(x, name, trailing)


def _swap(x: np.ndarray) -> np.ndarray:
    """``[a; b] -> [b; a]`` over the last axis (a fresh array, dtype kept)."""
    return x[..., _SWAP]


def _cat(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Concatenate two ``(..., 3)`` halves after broadcasting their batch shapes."""
    a, b = np.broadcast_arrays(a, b)
    return np.concatenate([a, b], axis=-1)


def _matvec(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    return (m @ x[..., None])[..., 0]


def _as_transform(T: Any, name: str) -> PluckerTransform:
    """A :class:`PluckerTransform`, or one built from a ``(..., 4, 4)`` homogeneous matrix."""
    if isinstance(T, PluckerTransform):
        return T
    if isinstance(T, _SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a PluckerTransform or a (..., 4, 4) homogeneous matrix, got a {_type_name(T)}"
        )
    if _is_pinocchio_object(T):
        raise SpatialTypeError(
            f"{name}: expected a PluckerTransform or a (..., 4, 4) homogeneous matrix, got a {_type_name(T)}; "
            "convert a pin.SE3 with transform_from_pinocchio_se3"
        )
    t = as_array(T, name, (4, 4))
    if t.dtype.kind != "O":
        bottom = t[..., 3, :]
        expected = np.array([0, 0, 0, 1], dtype=t.dtype)
        if not np.allclose(bottom, expected, atol=SPATIAL_STRUCTURE.of(t.dtype), rtol=0):
            raise ShapeError(
                f"{name}: expected a homogeneous transform with last row [0, 0, 0, 1], "
                f"got {np.asarray(bottom).reshape(-1, 4)[0].tolist()}"
            )
    check_rotation(t[..., :3, :3], f"{name}[..., :3, :3]")
    return PluckerTransform(t[..., :3, :3], t[..., :3, 3], validate=False)


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


def _single(x: np.ndarray, name: str, what: str, batch_function: str) -> np.ndarray:
    """One value (no batch axes) as float64, for building one Pinocchio object."""
    if x.dtype.kind == "O":
        raise SpatialTypeError(f"{name}: Pinocchio objects hold numbers; got an object (SymPy) array")
    batch = x.shape[:-1]
    if batch:
        raise ShapeError(
            f"{name}: expected a single {what} (batch shape ()), got batch shape {batch}; "
            f"Pinocchio objects hold one value each: loop, or convert the arrays with {batch_function}"
        )
    return np.array(x, dtype=np.float64)


# --------------------------------------------------------------------------
# Pinocchio: raw arrays
# --------------------------------------------------------------------------


def motion_to_pinocchio(m: Any) -> np.ndarray:
    """A featherdyn motion as a Pinocchio-ordered 6-vector (linear first).

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        `(..., 6)` ``[v_O; ω]``, the layout of ``pin.Motion.vector``::

            x_pin = P x = [v_O; ω]

    Source: Pinocchio ``MotionTpl`` (``linear()`` = first three entries); DESIGN.md.
    """
    return _swap(_motion_array(m, "m"))


def motion_from_pinocchio(v6: Any, frame: Frame = None) -> SpatialMotion:
    """A Pinocchio-ordered 6-vector (linear first) as a featherdyn motion.

    Args:
        v6: `(..., 6)` ``[v_O; ω]`` (e.g. ``pin.Motion.vector``, ``data.v[i].vector``).
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            x = P x_pin = [ω; v_O]

    Source: Pinocchio ``MotionTpl``; DESIGN.md.
    """
    return SpatialMotion.from_vector(_swap(_foreign_array(v6, "v6", "Pinocchio [linear; angular]")), frame)


def force_to_pinocchio(f: Any) -> np.ndarray:
    """A featherdyn force as a Pinocchio-ordered 6-vector (force first).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        `(..., 6)` ``[f; n_O]``, the layout of ``pin.Force.vector``::

            f_pin = P f = [f; n_O]

    Source: Pinocchio ``ForceTpl``; DESIGN.md.
    """
    return _swap(_force_array(f, "f"))


def force_from_pinocchio(f6: Any, frame: Frame = None) -> SpatialForce:
    """A Pinocchio-ordered 6-vector (force first) as a featherdyn force.

    Args:
        f6: `(..., 6)` ``[f; n_O]`` (e.g. ``pin.Force.vector``, ``data.f[i].vector``).
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = P f_pin = [n_O; f]

    Source: Pinocchio ``ForceTpl``; DESIGN.md.
    """
    return SpatialForce.from_vector(_swap(_foreign_array(f6, "f6", "Pinocchio [linear; angular]")), frame)


def matrix6_to_pinocchio(M: Any) -> np.ndarray:
    """A 6×6 matrix acting on featherdyn 6-vectors, rewritten for Pinocchio's order.

    Works for any linear map between motion and force spaces, because motions
    and forces use the same swap: the motion transform ``X``
    (``SE3.toActionMatrix``), the force transform ``X*``
    (``toDualActionMatrix``), ``crm`` / ``crf`` (``Motion.action`` /
    ``dualAction``), a spatial inertia (``Inertia.matrix``) and its inverse.

    Args:
        M: `(..., 6, 6)`.

    Returns:
        `(..., 6, 6)` with both axes permuted::

            M_pin = P M P        (P = Pᵀ = P⁻¹)

    Source: Pinocchio ``SE3Tpl::toActionMatrix``, ``InertiaTpl::matrix``; DESIGN.md.
    """
    mat = as_array(M, "M", (6, 6))
    return mat[..., _SWAP[:, None], _SWAP]


def matrix6_from_pinocchio(M: Any) -> np.ndarray:
    """A 6×6 matrix in Pinocchio's order (linear first), rewritten for featherdyn's.

    Args:
        M: `(..., 6, 6)` (e.g. ``pin.SE3.toActionMatrix()``, ``pin.Inertia.matrix()``).

    Returns:
        `(..., 6, 6)` with both axes permuted::

            M = P M_pin P

    Source: see :func:`matrix6_to_pinocchio`.
    """
    mat = _foreign_array(M, "M", "Pinocchio [linear; angular]", (6, 6))
    return mat[..., _SWAP[:, None], _SWAP]


def _jacobian(J: Any, name: str, floating_base: bool, foreign: bool) -> np.ndarray:
    if foreign:
        arr = _foreign_array(J, name, "Pinocchio [linear; angular]", ())
    else:
        arr = as_array(J, name)
    if arr.ndim < 2 or arr.shape[-2] != 6:
        raise ShapeError(f"{name}: expected shape (..., 6, n), got shape {tuple(arr.shape)}")
    out = arr[..., _SWAP, :]
    if floating_base:
        if arr.shape[-1] < 6:
            raise ShapeError(
                f"{name}: floating_base=True needs at least 6 columns (the free-flyer block), got shape {tuple(arr.shape)}"
            )
        out[..., :6] = out[..., :6][..., _SWAP]
    return out


def jacobian_to_pinocchio(J: Any, *, floating_base: bool = False) -> np.ndarray:
    """A featherdyn Jacobian (rows ``[ω; v]``) rewritten for Pinocchio (rows ``[v; ω]``).

    Args:
        J: `(..., 6, n)`, mapping ``q̇`` to a featherdyn motion.
        floating_base: the first six columns are a free-flyer block (featherdyn
            ``v = [ω; v]``, Pinocchio ``v = [v; ω]``): swap those columns too.

    Returns:
        `(..., 6, n)`::

            J_pin = P J                       (fixed base)
            J_pin = P J diag(P, 1)            (floating_base=True)

    Source: Pinocchio ``getFrameJacobian`` (rows ``[linear; angular]``); DESIGN.md.
    """
    return _jacobian(J, "J", floating_base, foreign=False)


def jacobian_from_pinocchio(J: Any, *, floating_base: bool = False) -> np.ndarray:
    """A Pinocchio Jacobian (rows ``[v; ω]``) rewritten for featherdyn (rows ``[ω; v]``).

    Args:
        J: `(..., 6, n)` (e.g. ``pin.getFrameJacobian(...)``).
        floating_base: also swap the first six (free-flyer) columns, see
            :func:`jacobian_to_pinocchio`.

    Returns:
        `(..., 6, n)`::

            J = P J_pin                       (fixed base)
            J = P J_pin diag(P, 1)            (floating_base=True)

    Source: see :func:`jacobian_to_pinocchio`.
    """
    return _jacobian(J, "J", floating_base, foreign=True)


def freeflyer_v_to_pinocchio(v: Any) -> np.ndarray:
    """A featherdyn free-flyer velocity as Pinocchio's (the half swap).

    Both are the base's spatial velocity in base coordinates (Pinocchio's
    LOCAL frame: ``v`` is the velocity of the base origin, in base axes); only
    the order differs. The configuration ``q = [x y z, qx qy qz qw]`` is the
    same in both and needs no conversion. For a whole model's ``v``, convert
    the free-flyer block ``v[..., :6]`` (other joints have their own layouts).

    Args:
        v: `(..., 6)` featherdyn ``[ω; v]``.

    Returns:
        `(..., 6)` Pinocchio ``[v; ω]``::

            v_pin = P v

    Source: Pinocchio ``JointModelFreeFlyerTpl`` documentation; DESIGN.md.
    """
    return _swap(_motion_array(v, "v"))


def freeflyer_v_from_pinocchio(v: Any) -> np.ndarray:
    """A Pinocchio free-flyer velocity ``[v; ω]`` (LOCAL) as featherdyn's ``[ω; v]`` (base frame).

    Args:
        v: `(..., 6)` Pinocchio ``[v; ω]``.

    Returns:
        `(..., 6)` featherdyn ``[ω; v]``::

            v = P v_pin

    Source: see :func:`freeflyer_v_to_pinocchio`.
    """
    return _swap(_foreign_array(v, "v", "Pinocchio free-flyer [linear; angular]"))


def _cos_sin(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if theta.dtype.kind == "O":
        import sympy

        return np.vectorize(sympy.cos, otypes=[object])(theta), np.vectorize(sympy.sin, otypes=[object])(theta)
    return np.cos(theta), np.sin(theta)


def _atan2(s: np.ndarray, c: np.ndarray) -> np.ndarray:
    if s.dtype.kind == "O" or c.dtype.kind == "O":
        import sympy

        return np.asarray(np.vectorize(sympy.atan2, otypes=[object])(s, c))
    return np.asarray(np.arctan2(s, c))


def continuous_q_to_pinocchio(theta: Any) -> np.ndarray:
    """A continuous joint's angle as Pinocchio's configuration ``(cos θ, sin θ)``.

    featherdyn stores a continuous joint like a revolute one (``nq = nv = 1``,
    an angle); Pinocchio's ``JointModelRUB*`` stores a unit complex number
    (``nq = 2``, ``nv = 1``; the velocity ``θ̇`` is the same in both).

    Args:
        theta: `(...)` angle.

    Returns:
        `(..., 2)`::

            q_pin = (cos θ, sin θ)

    Source: Pinocchio ``JointModelRevoluteUnboundedTpl``; DESIGN.md.
    """
    t = as_array(theta, "theta")
    c, s = _cos_sin(t)
    return np.stack([c, s], axis=-1)


def continuous_q_from_pinocchio(q: Any) -> np.ndarray:
    """Pinocchio's continuous-joint configuration ``(cos θ, sin θ)`` as the angle ``θ ∈ (−π, π]``.

    The pair's norm is not checked (``atan2`` ignores a common scale).

    Args:
        q: `(..., 2)` ``(cos θ, sin θ)``.

    Returns:
        `(...)`::

            θ = atan2(sin θ, cos θ)

    Source: Pinocchio ``JointModelRevoluteUnboundedTpl``; DESIGN.md.
    """
    cs = _foreign_array(q, "q", "Pinocchio (cos θ, sin θ)", (2,))
    return _atan2(cs[..., 1], cs[..., 0])


def planar_q_to_pinocchio(q: Any) -> np.ndarray:
    """A planar joint's configuration ``[x, y, θ]`` as Pinocchio's ``[x, y, cos θ, sin θ]``.

    Args:
        q: `(..., 3)` featherdyn ``[x, y, θ]``.

    Returns:
        `(..., 4)`::

            q_pin = [x, y, cos θ, sin θ]

    Source: Pinocchio ``JointModelPlanarTpl``; DESIGN.md.
    """
    qq = as_array(q, "q", (3,))
    c, s = _cos_sin(qq[..., 2])
    return np.concatenate([qq[..., :2], np.stack([c, s], axis=-1)], axis=-1)


def planar_q_from_pinocchio(q: Any) -> np.ndarray:
    """Pinocchio's planar configuration ``[x, y, cos θ, sin θ]`` as featherdyn's ``[x, y, θ]``.

    Args:
        q: `(..., 4)` Pinocchio ``[x, y, cos θ, sin θ]``.

    Returns:
        `(..., 3)`::

            [x, y, atan2(sin θ, cos θ)]

    Source: Pinocchio ``JointModelPlanarTpl``; DESIGN.md.
    """
    qq = _foreign_array(q, "q", "Pinocchio planar [x, y, cos θ, sin θ]", (4,))
    theta = _atan2(qq[..., 3], qq[..., 2])
    return np.concatenate([qq[..., :2], theta[..., None].astype(qq.dtype)], axis=-1)


def planar_v_to_pinocchio(v: Any) -> np.ndarray:
    """A planar joint's velocity ``[ω, v_x, v_y]`` (angular first) as Pinocchio's ``[v_x, v_y, ω]``.

    Both are in the moving (LOCAL) frame; only the order differs.

    Args:
        v: `(..., 3)` featherdyn ``[ω, v_x, v_y]``.

    Returns:
        `(..., 3)`::

            v_pin = [v_x, v_y, ω]

    Source: Pinocchio ``JointModelPlanarTpl``; DESIGN.md.
    """
    return as_array(v, "v", (3,))[..., [1, 2, 0]]


def planar_v_from_pinocchio(v: Any) -> np.ndarray:
    """Pinocchio's planar velocity ``[v_x, v_y, ω]`` as featherdyn's ``[ω, v_x, v_y]``.

    Args:
        v: `(..., 3)` Pinocchio ``[v_x, v_y, ω]``.

    Returns:
        `(..., 3)`::

            v = [ω, v_x, v_y]

    Source: Pinocchio ``JointModelPlanarTpl``; DESIGN.md.
    """
    return _foreign_array(v, "v", "Pinocchio planar [v_x, v_y, ω]", (3,))[..., [2, 0, 1]]


# --------------------------------------------------------------------------
# Pinocchio: objects (one value each; Pinocchio imported lazily)
# --------------------------------------------------------------------------


def to_pinocchio_motion(m: Any) -> Any:
    """A featherdyn motion as a ``pin.Motion``.

    Args:
        m: :class:`SpatialMotion` or raw `(6,)` ``[ω; v_O]`` (one value).

    Returns:
        ``pin.Motion``; note its constructor takes ``(linear, angular)``::

            pin.Motion(linear=v_O, angular=ω)

    Raises:
        MissingDependencyError: Pinocchio is not installed.
        ShapeError: ``m`` has batch axes.

    Source: Pinocchio ``MotionTpl``.
    """
    pin = _pinocchio("to_pinocchio_motion")
    vec = _single(_motion_array(m, "m"), "m", "motion", "motion_to_pinocchio")
    return pin.Motion(vec[3:], vec[:3])


def from_pinocchio_motion(motion: Any, frame: Frame = None) -> SpatialMotion:
    """A ``pin.Motion`` as a featherdyn motion.

    Args:
        motion: ``pin.Motion``.
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialMotion` `(6,)`::

            [ω; v_O] = [motion.angular; motion.linear]

    Source: Pinocchio ``MotionTpl``.
    """
    pin = _pinocchio("from_pinocchio_motion")
    if not isinstance(motion, pin.Motion):
        raise SpatialTypeError(
            f"motion: expected a pinocchio.Motion, got a {_type_name(motion)}"
            + (
                "; raw [linear; angular] arrays convert with motion_from_pinocchio"
                if not _is_pinocchio_object(motion)
                else ""
            )
        )
    return SpatialMotion(np.array(motion.angular), np.array(motion.linear), frame)


def to_pinocchio_force(f: Any) -> Any:
    """A featherdyn force as a ``pin.Force``.

    Args:
        f: :class:`SpatialForce` or raw `(6,)` ``[n_O; f]`` (one value).

    Returns:
        ``pin.Force``; its constructor takes ``(linear, angular)``::

            pin.Force(linear=f, angular=n_O)

    Raises:
        MissingDependencyError: Pinocchio is not installed.
        ShapeError: ``f`` has batch axes.

    Source: Pinocchio ``ForceTpl``.
    """
    pin = _pinocchio("to_pinocchio_force")
    vec = _single(_force_array(f, "f"), "f", "force", "force_to_pinocchio")
    return pin.Force(vec[3:], vec[:3])


def from_pinocchio_force(force: Any, frame: Frame = None) -> SpatialForce:
    """A ``pin.Force`` as a featherdyn force.

    Args:
        force: ``pin.Force``.
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialForce` `(6,)`::

            [n_O; f] = [force.angular; force.linear]

    Source: Pinocchio ``ForceTpl``.
    """
    pin = _pinocchio("from_pinocchio_force")
    if not isinstance(force, pin.Force):
        raise SpatialTypeError(
            f"force: expected a pinocchio.Force, got a {_type_name(force)}"
            + (
                "; raw [linear; angular] arrays convert with force_from_pinocchio"
                if not _is_pinocchio_object(force)
                else ""
            )
        )
    return SpatialForce(np.array(force.angular), np.array(force.linear), frame)


def to_pinocchio_inertia(inertia: SpatialInertia) -> Any:
    """A featherdyn spatial inertia as a ``pin.Inertia``.

    Both are parametrised the same way (mass, centre of mass from the frame
    origin, rotational inertia about the centre of mass); only the 6×6 matrix
    is ordered differently (``Inertia.matrix() = P I P``).

    Args:
        inertia: :class:`SpatialInertia` with batch shape `()`.

    Returns:
        ``pin.Inertia``::

            pin.Inertia(mass=m, lever=c, inertia=I_c)

    Source: Pinocchio ``InertiaTpl(mass, lever, inertia)``.
    """
    pin = _pinocchio("to_pinocchio_inertia")
    if not isinstance(inertia, SpatialInertia):
        raise SpatialTypeError(
            f"inertia: expected a SpatialInertia, got a {_type_name(inertia)}; a 6×6 matrix converts with "
            "SpatialInertia.from_matrix(M) first (or matrix6_to_pinocchio for the bare matrix)"
        )
    if inertia.shape:
        raise ShapeError(
            f"inertia: expected a single inertia (batch shape ()), got batch shape {inertia.shape}; "
            "Pinocchio objects hold one value each"
        )
    if inertia.dtype.kind == "O":
        raise SpatialTypeError("inertia: Pinocchio objects hold numbers; got an object (SymPy) inertia")
    return pin.Inertia(
        float(inertia.mass),
        np.array(inertia.com, dtype=np.float64),
        np.array(inertia.inertia_com, dtype=np.float64),
    )


def from_pinocchio_inertia(inertia: Any, frame: Frame = None) -> SpatialInertia:
    """A ``pin.Inertia`` as a featherdyn spatial inertia.

    Args:
        inertia: ``pin.Inertia``.
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialInertia` with batch shape `()` (``com`` `(3,)`, ``inertia_com`` `(3, 3)`)::

            SpatialInertia(mass=inertia.mass, com=inertia.lever, inertia_com=inertia.inertia)

    Source: Pinocchio ``InertiaTpl``.
    """
    pin = _pinocchio("from_pinocchio_inertia")
    if not isinstance(inertia, pin.Inertia):
        raise SpatialTypeError(f"inertia: expected a pinocchio.Inertia, got a {_type_name(inertia)}")
    return SpatialInertia(float(inertia.mass), np.array(inertia.lever), np.array(inertia.inertia), frame)


def transform_to_pinocchio_se3(X: Any) -> Any:
    """A featherdyn transform as a ``pin.SE3`` (the same pose, the same action).

    ``PluckerTransform(R, p)`` and ``pin.SE3(R, p)`` both hold the pose of
    frame A in frame B and both map A-coordinates to B-coordinates
    (``X.apply`` = ``SE3.act``, ``X.apply_inverse`` = ``SE3.actInv``); only the
    6×6 matrices are ordered differently.

    Args:
        X: :class:`PluckerTransform` or `(4, 4)` homogeneous matrix, one value.

    Returns:
        ``pin.SE3``::

            pin.SE3(R, p),   toActionMatrix() = P X.matrix() P

    Source: Pinocchio ``SE3Tpl``; chapter §3.
    """
    pin = _pinocchio("transform_to_pinocchio_se3")
    xf = _as_transform(X, "X")
    if xf.shape:
        raise ShapeError(
            f"X: expected a single transform (batch shape ()), got batch shape {xf.shape}; "
            "Pinocchio objects hold one value each"
        )
    if xf.dtype.kind == "O":
        raise SpatialTypeError("X: Pinocchio objects hold numbers; got an object (SymPy) transform")
    return pin.SE3(np.array(xf.rotation, dtype=np.float64), np.array(xf.translation, dtype=np.float64))


def transform_from_pinocchio_se3(se3: Any, source: Frame = None, target: Frame = None) -> PluckerTransform:
    """A ``pin.SE3`` as a featherdyn transform (same pose, same action).

    Args:
        se3: ``pin.SE3`` (e.g. ``data.oMi[i]``: ``source`` = body i, ``target`` = world).
        source: optional tag of frame A.
        target: optional tag of frame B.

    Returns:
        :class:`PluckerTransform` with batch shape `()` (``rotation`` `(3, 3)`, ``translation`` `(3,)`)::

            PluckerTransform(se3.rotation, se3.translation)

    Source: Pinocchio ``SE3Tpl``; chapter §3.
    """
    pin = _pinocchio("transform_from_pinocchio_se3")
    if not isinstance(se3, pin.SE3):
        raise SpatialTypeError(
            f"se3: expected a pinocchio.SE3, got a {_type_name(se3)}; a (4, 4) homogeneous matrix converts with "
            "PluckerTransform.from_homogeneous"
        )
    return PluckerTransform(np.array(se3.rotation), np.array(se3.translation), source, target)


# --------------------------------------------------------------------------
# Lynch–Park / Modern Robotics
# --------------------------------------------------------------------------


def twist_to_mr(m: Any) -> np.ndarray:
    """A featherdyn motion as a Modern Robotics twist: the numbers do not change.

    Modern Robotics writes twists ``V = [ω; v]``, angular first like
    Featherstone, and its ``v`` is the velocity of the body point at the
    origin of the frame of expression. So a featherdyn motion expressed in
    the world frame *is* MR's spatial twist ``V_s`` (reference point the
    space origin), and one expressed in the body frame is MR's body twist
    ``V_b``.

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)`.

    Returns:
        `(..., 6)` (a copy)::

            V = [ω; v] = m

    Source: Lynch & Park (2017) §3.3.2, eqs. (3.70) and (3.72).
    """
    return np.array(_motion_array(m, "m"))


def twist_from_mr(V: Any, frame: Frame = None) -> SpatialMotion:
    """A Modern Robotics twist ``[ω; v]`` as a featherdyn motion (same numbers, see :func:`twist_to_mr`).

    Args:
        V: `(..., 6)` MR twist ``[ω; v]``.
        frame: optional frame tag (``V_s``: the space frame; ``V_b``: the body frame).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            m = V

    Source: Lynch & Park (2017) §3.3.2.
    """
    return SpatialMotion.from_vector(_foreign_array(V, "V", "Modern Robotics [ω; v]"), frame)


def wrench_to_mr(f: Any) -> np.ndarray:
    """A featherdyn force as a Modern Robotics wrench: the numbers do not change.

    MR writes a wrench ``F = [m; f]``, moment first, the moment taken about
    the origin of the frame of expression, exactly featherdyn's ``[n_O; f]``.

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)`.

    Returns:
        `(..., 6)` (a copy)::

            F = [m; f] = [n_O; f]

    Source: Lynch & Park (2017) §3.4, eq. (3.95).
    """
    return np.array(_force_array(f, "f"))


def wrench_from_mr(F: Any, frame: Frame = None) -> SpatialForce:
    """A Modern Robotics wrench ``[m; f]`` as a featherdyn force (same numbers, see :func:`wrench_to_mr`).

    Args:
        F: `(..., 6)` MR wrench ``[m; f]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = F

    Source: Lynch & Park (2017) §3.4.
    """
    return SpatialForce.from_vector(_foreign_array(F, "F", "Modern Robotics [m; f]"), frame)


def adjoint_matrix(T: Any) -> np.ndarray:
    """Modern Robotics ``[Ad_T]``: featherdyn's motion transform ``X.matrix()``.

    ``T`` = ``[[R, p], [0, 1]]`` is the pose of frame b in frame a (``T_ab``);
    as a :class:`PluckerTransform` it is ``PluckerTransform(R, p)``, and
    ``[Ad_T]`` maps twists in b-coordinates to a-coordinates.

    Args:
        T: :class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix.

    Returns:
        `(..., 6, 6)`::

            [Ad_T] = [[ R,     0 ],   = X
                      [ [p]R,  R ]]

    Source: Lynch & Park (2017) Definition 3.20, eq. (3.83); RBDA (2008) eq. 2.24.
    """
    return _as_transform(T, "T").matrix()


def ad_matrix(V: Any) -> np.ndarray:
    """Modern Robotics ``[ad_V]`` (the Lie bracket ``[ad_V1] V2``): featherdyn's ``crm(V)``.

    Args:
        V: :class:`SpatialMotion` or raw `(..., 6)` twist ``[ω; v]``.

    Returns:
        `(..., 6, 6)`::

            [ad_V] = [[ [ω],  0   ],   = crm(V) = [V]×
                      [ [v],  [ω] ]]

    Source: Lynch & Park (2017) Definition 8.2, eq. (8.38); RBDA (2008) eq. 2.31.
    """
    return crm(_motion_array(V, "V"))


def wrench_transform_matrix(T: Any) -> np.ndarray:
    """The wrench map of a pose: featherdyn's force transform ``X.dual_matrix()``.

    With ``T = T_ab`` (pose of b in a), Modern Robotics writes
    ``F_b = [Ad_{T_ab}]ᵀ F_a``, so ``F_a = [Ad_{T_ab}]⁻ᵀ F_b`` — featherdyn's
    ``X* = X⁻ᵀ`` of the same pose. It preserves power:
    ``(X V)ᵀ (X* F) = Vᵀ F``.

    Args:
        T: :class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix.

    Returns:
        `(..., 6, 6)`::

            [Ad_T]⁻ᵀ = [[ R,  [p]R ],   = X*
                        [ 0,  R    ]]

    Source: Lynch & Park (2017) §3.4, eq. (3.98); RBDA (2008) eq. 2.25.
    """
    return _as_transform(T, "T").dual_matrix()


def body_twist_to_spatial_twist(T: Any, V_b: Any) -> SpatialMotion:
    """Modern Robotics: a body twist ``V_b`` to the spatial twist ``V_s`` of the same motion.

    Args:
        T: the pose ``T_sb`` of the body in the space frame
            (:class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix).
        V_b: `(..., 6)` body twist ``[ω_b; v_b]`` (:class:`SpatialMotion` or raw).

    Returns:
        :class:`SpatialMotion` `(..., 6)`, the spatial twist::

            V_s = [Ad_{T_sb}] V_b        ([V_s] = Ṫ T⁻¹,  [V_b] = T⁻¹ Ṫ)

    Source: Lynch & Park (2017) eq. (3.84).
    """
    X = _as_transform(T, "T")
    vb = V_b if isinstance(V_b, SpatialMotion) else SpatialMotion.from_vector(_motion_array(V_b, "V_b"))
    result: SpatialMotion = X.apply(vb)
    return result


def spatial_twist_to_body_twist(T: Any, V_s: Any) -> SpatialMotion:
    """Modern Robotics: a spatial twist ``V_s`` to the body twist ``V_b`` (inverse of :func:`body_twist_to_spatial_twist`).

    Args:
        T: the pose ``T_sb`` (:class:`PluckerTransform` or `(..., 4, 4)`).
        V_s: `(..., 6)` spatial twist (:class:`SpatialMotion` or raw).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            V_b = [Ad_{T_sb}]⁻¹ V_s = [Ad_{T_bs}] V_s

    Source: Lynch & Park (2017) eq. (3.84).
    """
    X = _as_transform(T, "T")
    vs = V_s if isinstance(V_s, SpatialMotion) else SpatialMotion.from_vector(_motion_array(V_s, "V_s"))
    result: SpatialMotion = X.apply_inverse(vs)
    return result


# --------------------------------------------------------------------------
# Drake and classical acceleration
# --------------------------------------------------------------------------


def spatial_to_classical_acceleration(a_spatial: Any, v: Any) -> np.ndarray:
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
    a = _motion_array(a_spatial, "a_spatial")
    vv = _motion_array(v, "v")
    merge_frames(
        getattr(a_spatial, "frame", None), getattr(v, "frame", None), "spatial_to_classical_acceleration(a_spatial, v)"
    )
    lin = a[..., 3:] + np.cross(vv[..., :3], vv[..., 3:])
    return _cat(a[..., :3], lin)


def classical_to_spatial_acceleration(a_classical: Any, v: Any, frame: Frame = None) -> SpatialMotion:
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
    a = _foreign_array(a_classical, "a_classical", "classical [ω̇; a_O]")
    vv = _motion_array(v, "v")
    tag = merge_frames(frame, getattr(v, "frame", None), "classical_to_spatial_acceleration(frame, v)")
    lin = a[..., 3:] - np.cross(vv[..., :3], vv[..., 3:])
    return SpatialMotion.from_vector(_cat(a[..., :3], lin), tag)


def drake_shift_velocity(V_WBo_E: Any, p_BoBq_E: Any) -> SpatialMotion:
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
    V = _motion_array(V_WBo_E, "V_WBo_E")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    lin = V[..., 3:] + np.cross(V[..., :3], p)
    return SpatialMotion.from_vector(_cat(V[..., :3], lin), getattr(V_WBo_E, "frame", None))


def drake_shift_force(F_Bo_E: Any, p_BoBq_E: Any) -> SpatialForce:
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
    F = _force_array(F_Bo_E, "F_Bo_E")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    tau = F[..., :3] - np.cross(p, F[..., 3:])
    return SpatialForce.from_vector(_cat(tau, F[..., 3:]), getattr(F_Bo_E, "frame", None))


def drake_shift_acceleration(A_WBo_E: Any, p_BoBq_E: Any, w_WB_E: Any) -> np.ndarray:
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
    A = _foreign_array(A_WBo_E, "A_WBo_E", "Drake classical [α; a]")
    p = as_array(p_BoBq_E, "p_BoBq_E", (3,))
    w = as_array(w_WB_E, "w_WB_E", (3,))
    alpha = A[..., :3]
    lin = A[..., 3:] + np.cross(alpha, p) + np.cross(w, np.cross(w, p))
    return _cat(alpha, lin)


def drake_reexpress(R_AE: Any, V_E: Any, *, frame: Frame = None) -> Any:
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
        x = _featherdyn_array(V_E, "V_E", "spatial vector (SpatialMotion, SpatialForce or raw (..., 6))")
    out = _cat(_matvec(R, x[..., :3]), _matvec(R, x[..., 3:]))
    if isinstance(V_E, SpatialMotion):
        return SpatialMotion(out[..., :3], out[..., 3:], frame, body=V_E.body, relative_to=V_E.relative_to)
    if isinstance(V_E, SpatialForce):
        return SpatialForce.from_vector(out, frame)
    return out


# --------------------------------------------------------------------------
# ROS geometry_msgs
# --------------------------------------------------------------------------


def _ros_out(vec: np.ndarray, first: tuple[str, np.ndarray], second: tuple[str, np.ndarray]) -> dict[str, Any]:
    if vec.ndim == 1:
        return {first[0]: tuple(first[1].tolist()), second[0]: tuple(second[1].tolist())}
    return {first[0]: np.array(first[1]), second[0]: np.array(second[1])}


def _ros_field(msg: Any, key: str, name: str, keys: tuple[str, str], message: str, flat_function: str) -> Any:
    if isinstance(msg, _SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a {message} (a mapping with keys {keys[0]!r} and {keys[1]!r}), got a "
            f"{_type_name(msg)}, which is a featherdyn value already"
        )
    if isinstance(msg, Mapping):
        if key not in msg:
            raise ShapeError(
                f"{name}: missing key {key!r}; expected a {message} mapping with keys {keys[0]!r} and {keys[1]!r}, "
                f"got keys {[str(k) for k in msg]}"
            )
        return msg[key]
    if isinstance(msg, (np.ndarray, list, tuple, str, bytes)) or not hasattr(msg, key):
        raise ShapeError(
            f"{name}: expected a {message} (a mapping with keys {keys[0]!r} and {keys[1]!r}, or a message object "
            f"with those fields), got a {_type_name(msg)} without field {key!r}; flattened 6-arrays convert with "
            f"{flat_function}"
        )
    return getattr(msg, key)


def _ros_vector3(value: Any, name: str) -> np.ndarray:
    if isinstance(value, Mapping):
        for k in "xyz":
            if k not in value:
                raise ShapeError(
                    f"{name}: missing key {k!r}; expected a 3-sequence or a mapping with keys 'x', 'y', 'z', "
                    f"got keys {[str(key) for key in value]}"
                )
        comps = [as_array(value[k], f"{name}[{k!r}]") for k in "xyz"]
    elif not isinstance(value, (np.ndarray, list, tuple)) and all(hasattr(value, k) for k in "xyz"):
        comps = [as_array(getattr(value, k), f"{name}.{k}") for k in "xyz"]
    else:
        return as_array(value, name, (3,))
    return np.stack(np.broadcast_arrays(*comps), axis=-1)


def motion_to_ros_twist(m: Any) -> dict[str, Any]:
    """A featherdyn motion as the fields of a ROS ``geometry_msgs/Twist``.

    ROS's ``linear`` is the velocity of the point at the origin of the
    message's frame (the ``v_O`` of featherdyn), expressed in that frame.

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        ``{"linear": v_O, "angular": ω}``: tuples of 3 floats for one motion,
        `(..., 3)` arrays for a batch::

            Twist(linear=Vector3(*d["linear"]), angular=Vector3(*d["angular"]))

    Source: ROS ``geometry_msgs/msg/Twist``.
    """
    vec = _motion_array(m, "m")
    return _ros_out(vec, ("linear", vec[..., 3:]), ("angular", vec[..., :3]))


def motion_from_ros_twist(twist: Any, frame: Frame = None) -> SpatialMotion:
    """A ROS ``Twist`` (message, or mapping) as a featherdyn motion.

    Args:
        twist: a mapping with keys ``"linear"`` and ``"angular"`` (or an object
            with those attributes, e.g. a ``geometry_msgs/Twist``), each a
            3-sequence / `(..., 3)` array, a mapping with keys ``x, y, z`` or a
            ``Vector3``-like object.
        frame: optional frame tag (the message's ``header.frame_id``).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            [ω; v_O] = [twist.angular; twist.linear]

    Raises:
        ShapeError: a key or field is missing (the message names it) or a
            vector is not 3 long.

    Source: ROS ``geometry_msgs/msg/Twist``.
    """
    keys = ("linear", "angular")
    lin = _ros_vector3(_ros_field(twist, "linear", "twist", keys, "Twist", "twist_array_from_ros"), "twist['linear']")
    ang = _ros_vector3(_ros_field(twist, "angular", "twist", keys, "Twist", "twist_array_from_ros"), "twist['angular']")
    return SpatialMotion(ang, lin, frame)


def force_to_ros_wrench(f: Any) -> dict[str, Any]:
    """A featherdyn force as the fields of a ROS ``geometry_msgs/Wrench``.

    ROS's ``torque`` is the moment about the origin of the message's frame
    (featherdyn's ``n_O``).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        ``{"force": f, "torque": n_O}``: tuples of 3 floats for one force,
        `(..., 3)` arrays for a batch::

            Wrench(force=Vector3(*d["force"]), torque=Vector3(*d["torque"]))

    Source: ROS ``geometry_msgs/msg/Wrench``.
    """
    vec = _force_array(f, "f")
    return _ros_out(vec, ("force", vec[..., 3:]), ("torque", vec[..., :3]))


def force_from_ros_wrench(wrench: Any, frame: Frame = None) -> SpatialForce:
    """A ROS ``Wrench`` (message, or mapping) as a featherdyn force.

    Args:
        wrench: a mapping with keys ``"force"`` and ``"torque"`` (or an object
            with those attributes), each a 3-sequence / `(..., 3)` array, a
            mapping with keys ``x, y, z`` or a ``Vector3``-like object.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            [n_O; f] = [wrench.torque; wrench.force]

    Raises:
        ShapeError: a key or field is missing (the message names it) or a
            vector is not 3 long.

    Source: ROS ``geometry_msgs/msg/Wrench``.
    """
    keys = ("force", "torque")
    force = _ros_vector3(
        _ros_field(wrench, "force", "wrench", keys, "Wrench", "wrench_array_from_ros"), "wrench['force']"
    )
    torque = _ros_vector3(
        _ros_field(wrench, "torque", "wrench", keys, "Wrench", "wrench_array_from_ros"), "wrench['torque']"
    )
    return SpatialForce(torque, force, frame)


def twist_array_to_ros(m: Any) -> np.ndarray:
    """A featherdyn motion as a flattened ROS twist, linear first (message field order).

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        `(..., 6)`::

            [linear; angular] = [v_O; ω] = P m

    Source: ROS ``geometry_msgs/msg/Twist`` field order.
    """
    return _swap(_motion_array(m, "m"))


def twist_array_from_ros(twist: Any, frame: Frame = None) -> SpatialMotion:
    """A flattened ROS twist ``[linear; angular]`` as a featherdyn motion.

    Args:
        twist: `(..., 6)` ``[v_O; ω]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            m = P [v_O; ω] = [ω; v_O]

    Source: ROS ``geometry_msgs/msg/Twist`` field order.
    """
    return SpatialMotion.from_vector(_swap(_foreign_array(twist, "twist", "ROS [linear; angular]")), frame)


def wrench_array_to_ros(f: Any) -> np.ndarray:
    """A featherdyn force as a flattened ROS wrench, force first (message field order).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        `(..., 6)`::

            [force; torque] = [f; n_O] = P f

    Source: ROS ``geometry_msgs/msg/Wrench`` field order.
    """
    return _swap(_force_array(f, "f"))


def wrench_array_from_ros(wrench: Any, frame: Frame = None) -> SpatialForce:
    """A flattened ROS wrench ``[force; torque]`` as a featherdyn force.

    Args:
        wrench: `(..., 6)` ``[f; n_O]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = P [f; n_O] = [n_O; f]

    Source: ROS ``geometry_msgs/msg/Wrench`` field order.
    """
    return SpatialForce.from_vector(_swap(_foreign_array(wrench, "wrench", "ROS [force; torque]")), frame)


# --------------------------------------------------------------------------
# MuJoCo free joint and quaternion order
# --------------------------------------------------------------------------


def quat_xyzw_to_wxyz(quat: Any) -> np.ndarray:
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


def quat_wxyz_to_xyzw(quat: Any) -> np.ndarray:
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


def freeflyer_q_to_mujoco(q: Any) -> np.ndarray:
    """A featherdyn free-flyer configuration as a MuJoCo free joint's ``qpos``.

    Args:
        q: `(..., 7)` ``[x y z, qx qy qz qw]`` (unit quaternion, checked).

    Returns:
        `(..., 7)` ``qpos``::

            [x y z, qw qx qy qz]

    Raises:
        QuaternionNormError: the quaternion is off unit norm by more than 1e-6.

    Source: MuJoCo documentation, free joint (``qpos`` = position, then a
    (w, x, y, z) unit quaternion).
    """
    qq = as_array(q, "q", (7,))
    _check_unit_quat(qq[..., 3:], "q[..., 3:7]", "(x, y, z, w)")
    return qq[..., [0, 1, 2, 6, 3, 4, 5]]


def freeflyer_q_from_mujoco(qpos: Any) -> np.ndarray:
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


def freeflyer_v_to_mujoco(q: Any, v: Any) -> np.ndarray:
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


def freeflyer_v_from_mujoco(qpos: Any, qvel: Any) -> np.ndarray:
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
