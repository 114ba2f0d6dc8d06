"""Pinocchio: raw 6D arrays, Jacobians, joint layouts and Pinocchio's own objects.

Pinocchio stores 6D quantities linear first (``pin.Motion.vector = [v; ω]``,
``pin.Force.vector = [f; n]``, Jacobian rows ``[v; ω]``, 6×6 matrices
``P M P``); its ``SE3(R, p)`` has the semantics of ``PluckerTransform(R, p)``
(pose of A in B, maps A- to B-coordinates) and its ``Inertia(mass, lever,
inertia)`` the parameters of ``SpatialInertia``. The free-flyer ``q`` is the
same in both libraries; its ``v`` is ``[v; ω]`` in Pinocchio (LOCAL) and
``[ω; v]`` in featherdyn (base frame). A continuous joint is an angle ``θ`` in
featherdyn and ``(cos θ, sin θ)`` in Pinocchio; a planar one ``[x, y, θ]`` /
``[ω, v_x, v_y]`` against ``[x, y, cos θ, sin θ]`` / ``[v_x, v_y, ω]``.

The raw-array converters broadcast over batch axes and need no Pinocchio.
The object converters (``to_pinocchio_*``, ``from_pinocchio_*``,
``transform_*_pinocchio_se3``) take one value at a time and import Pinocchio
on first use; without it they raise :class:`MissingDependencyError`.

Sources: Pinocchio ``MotionTpl``, ``ForceTpl``, ``SE3Tpl``, ``InertiaTpl``,
``JointModelFreeFlyerTpl``, ``JointModelRevoluteUnboundedTpl``,
``JointModelPlanarTpl``; docs/conventions.md; chapter §3, §10.1, §18.3.
"""

from __future__ import annotations

from types import ModuleType
from typing import Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from ..errors import MissingDependencyError, ShapeError, SpatialTypeError
from ..frames import Frame
from ..spatial import PluckerTransform, SpatialForce, SpatialInertia, SpatialMotion
from ..spatial.validation import as_array
from ._common import (
    SWAP,
    as_transform,
    force_array,
    foreign_array,
    is_pinocchio_object,
    motion_array,
    qualified_type_name,
    swap,
)

__all__ = [
    "continuous_q_from_pinocchio",
    "continuous_q_to_pinocchio",
    "force_from_pinocchio",
    "force_to_pinocchio",
    "freeflyer_v_from_pinocchio",
    "freeflyer_v_to_pinocchio",
    "from_pinocchio_force",
    "from_pinocchio_inertia",
    "from_pinocchio_motion",
    "jacobian_from_pinocchio",
    "jacobian_to_pinocchio",
    "matrix6_from_pinocchio",
    "matrix6_to_pinocchio",
    "motion_from_pinocchio",
    "motion_to_pinocchio",
    "planar_q_from_pinocchio",
    "planar_q_to_pinocchio",
    "planar_v_from_pinocchio",
    "planar_v_to_pinocchio",
    "to_pinocchio_force",
    "to_pinocchio_inertia",
    "to_pinocchio_motion",
    "transform_from_pinocchio_se3",
    "transform_to_pinocchio_se3",
]

# Pinocchio ships no type stubs: its objects are typed by name only (``pinocchio.Motion``, ...).
PinMotion: TypeAlias = Any
PinForce: TypeAlias = Any
PinInertia: TypeAlias = Any
PinSE3: TypeAlias = Any


def _pinocchio(function: str) -> ModuleType:
    """Import Pinocchio on first use; a clear error says how to install it."""
    try:
        import pinocchio
    except ImportError as exc:
        raise MissingDependencyError(
            f"{function} needs Pinocchio, which is not installed: pip install pin (or pip install 'featherdyn[verify]')"
        ) from exc
    return pinocchio


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
# raw arrays
# --------------------------------------------------------------------------


def motion_to_pinocchio(m: SpatialMotion | ArrayLike) -> np.ndarray:
    """A featherdyn motion as a Pinocchio-ordered 6-vector (linear first).

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        `(..., 6)` ``[v_O; ω]``, the layout of ``pin.Motion.vector``::

            x_pin = P x = [v_O; ω]

    Source: Pinocchio ``MotionTpl`` (``linear()`` = first three entries); docs/conventions.md.
    """
    return swap(motion_array(m, "m"))


def motion_from_pinocchio(v6: ArrayLike, frame: Frame = None) -> SpatialMotion:
    """A Pinocchio-ordered 6-vector (linear first) as a featherdyn motion.

    Args:
        v6: `(..., 6)` ``[v_O; ω]`` (e.g. ``pin.Motion.vector``, ``data.v[i].vector``).
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            x = P x_pin = [ω; v_O]

    Source: Pinocchio ``MotionTpl``; docs/conventions.md.
    """
    return SpatialMotion.from_vector(swap(foreign_array(v6, "v6", "Pinocchio [linear; angular]")), frame)


def force_to_pinocchio(f: SpatialForce | ArrayLike) -> np.ndarray:
    """A featherdyn force as a Pinocchio-ordered 6-vector (force first).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        `(..., 6)` ``[f; n_O]``, the layout of ``pin.Force.vector``::

            f_pin = P f = [f; n_O]

    Source: Pinocchio ``ForceTpl``; docs/conventions.md.
    """
    return swap(force_array(f, "f"))


def force_from_pinocchio(f6: ArrayLike, frame: Frame = None) -> SpatialForce:
    """A Pinocchio-ordered 6-vector (force first) as a featherdyn force.

    Args:
        f6: `(..., 6)` ``[f; n_O]`` (e.g. ``pin.Force.vector``, ``data.f[i].vector``).
        frame: optional frame tag of the result.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = P f_pin = [n_O; f]

    Source: Pinocchio ``ForceTpl``; docs/conventions.md.
    """
    return SpatialForce.from_vector(swap(foreign_array(f6, "f6", "Pinocchio [linear; angular]")), frame)


def matrix6_to_pinocchio(M: ArrayLike) -> np.ndarray:
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

    Source: Pinocchio ``SE3Tpl::toActionMatrix``, ``InertiaTpl::matrix``; docs/conventions.md.
    """
    mat = as_array(M, "M", (6, 6))
    return mat[..., SWAP[:, None], SWAP]


def matrix6_from_pinocchio(M: ArrayLike) -> np.ndarray:
    """A 6×6 matrix in Pinocchio's order (linear first), rewritten for featherdyn's.

    Args:
        M: `(..., 6, 6)` (e.g. ``pin.SE3.toActionMatrix()``, ``pin.Inertia.matrix()``).

    Returns:
        `(..., 6, 6)` with both axes permuted::

            M = P M_pin P

    Source: see :func:`matrix6_to_pinocchio`.
    """
    mat = foreign_array(M, "M", "Pinocchio [linear; angular]", (6, 6))
    return mat[..., SWAP[:, None], SWAP]


def _jacobian(J: ArrayLike, name: str, floating_base: bool, foreign: bool) -> np.ndarray:
    if foreign:
        arr = foreign_array(J, name, "Pinocchio [linear; angular]", ())
    else:
        arr = as_array(J, name)
    if arr.ndim < 2 or arr.shape[-2] != 6:
        raise ShapeError(f"{name}: expected shape (..., 6, n), got shape {tuple(arr.shape)}")
    out = arr[..., SWAP, :]
    if floating_base:
        if arr.shape[-1] < 6:
            raise ShapeError(
                f"{name}: floating_base=True needs at least 6 columns (the free-flyer block), got shape {tuple(arr.shape)}"
            )
        out[..., :6] = out[..., :6][..., SWAP]
    return out


def jacobian_to_pinocchio(J: ArrayLike, *, floating_base: bool = False) -> np.ndarray:
    """A featherdyn Jacobian (rows ``[ω; v]``) rewritten for Pinocchio (rows ``[v; ω]``).

    Args:
        J: `(..., 6, n)`, mapping ``q̇`` to a featherdyn motion.
        floating_base: the first six columns are a free-flyer block (featherdyn
            ``v = [ω; v]``, Pinocchio ``v = [v; ω]``): swap those columns too.

    Returns:
        `(..., 6, n)`::

            J_pin = P J                       (fixed base)
            J_pin = P J diag(P, 1)            (floating_base=True)

    Source: Pinocchio ``getFrameJacobian`` (rows ``[linear; angular]``); docs/conventions.md.
    """
    return _jacobian(J, "J", floating_base, foreign=False)


def jacobian_from_pinocchio(J: ArrayLike, *, floating_base: bool = False) -> np.ndarray:
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


def freeflyer_v_to_pinocchio(v: SpatialMotion | ArrayLike) -> np.ndarray:
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

    Source: Pinocchio ``JointModelFreeFlyerTpl`` documentation; docs/conventions.md.
    """
    return swap(motion_array(v, "v"))


def freeflyer_v_from_pinocchio(v: ArrayLike) -> np.ndarray:
    """A Pinocchio free-flyer velocity ``[v; ω]`` (LOCAL) as featherdyn's ``[ω; v]`` (base frame).

    Args:
        v: `(..., 6)` Pinocchio ``[v; ω]``.

    Returns:
        `(..., 6)` featherdyn ``[ω; v]``::

            v = P v_pin

    Source: see :func:`freeflyer_v_to_pinocchio`.
    """
    return swap(foreign_array(v, "v", "Pinocchio free-flyer [linear; angular]"))


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


def continuous_q_to_pinocchio(theta: ArrayLike) -> np.ndarray:
    """A continuous joint's angle as Pinocchio's configuration ``(cos θ, sin θ)``.

    featherdyn stores a continuous joint like a revolute one (``nq = nv = 1``,
    an angle); Pinocchio's ``JointModelRUB*`` stores a unit complex number
    (``nq = 2``, ``nv = 1``; the velocity ``θ̇`` is the same in both).

    Args:
        theta: `(...)` angle.

    Returns:
        `(..., 2)`::

            q_pin = (cos θ, sin θ)

    Source: Pinocchio ``JointModelRevoluteUnboundedTpl``; docs/conventions.md.
    """
    t = as_array(theta, "theta")
    c, s = _cos_sin(t)
    return np.stack([c, s], axis=-1)


def continuous_q_from_pinocchio(q: ArrayLike) -> np.ndarray:
    """Pinocchio's continuous-joint configuration ``(cos θ, sin θ)`` as the angle ``θ ∈ (−π, π]``.

    The pair's norm is not checked (``atan2`` ignores a common scale).

    Args:
        q: `(..., 2)` ``(cos θ, sin θ)``.

    Returns:
        `(...)`::

            θ = atan2(sin θ, cos θ)

    Source: Pinocchio ``JointModelRevoluteUnboundedTpl``; docs/conventions.md.
    """
    cs = foreign_array(q, "q", "Pinocchio (cos θ, sin θ)", (2,))
    return _atan2(cs[..., 1], cs[..., 0])


def planar_q_to_pinocchio(q: ArrayLike) -> np.ndarray:
    """A planar joint's configuration ``[x, y, θ]`` as Pinocchio's ``[x, y, cos θ, sin θ]``.

    Args:
        q: `(..., 3)` featherdyn ``[x, y, θ]``.

    Returns:
        `(..., 4)`::

            q_pin = [x, y, cos θ, sin θ]

    Source: Pinocchio ``JointModelPlanarTpl``; docs/conventions.md.
    """
    qq = as_array(q, "q", (3,))
    c, s = _cos_sin(qq[..., 2])
    return np.concatenate([qq[..., :2], np.stack([c, s], axis=-1)], axis=-1)


def planar_q_from_pinocchio(q: ArrayLike) -> np.ndarray:
    """Pinocchio's planar configuration ``[x, y, cos θ, sin θ]`` as featherdyn's ``[x, y, θ]``.

    Args:
        q: `(..., 4)` Pinocchio ``[x, y, cos θ, sin θ]``.

    Returns:
        `(..., 3)`::

            [x, y, atan2(sin θ, cos θ)]

    Source: Pinocchio ``JointModelPlanarTpl``; docs/conventions.md.
    """
    qq = foreign_array(q, "q", "Pinocchio planar [x, y, cos θ, sin θ]", (4,))
    theta = _atan2(qq[..., 3], qq[..., 2])
    return np.concatenate([qq[..., :2], theta[..., None].astype(qq.dtype)], axis=-1)


def planar_v_to_pinocchio(v: ArrayLike) -> np.ndarray:
    """A planar joint's velocity ``[ω, v_x, v_y]`` (angular first) as Pinocchio's ``[v_x, v_y, ω]``.

    Both are in the moving (LOCAL) frame; only the order differs.

    Args:
        v: `(..., 3)` featherdyn ``[ω, v_x, v_y]``.

    Returns:
        `(..., 3)`::

            v_pin = [v_x, v_y, ω]

    Source: Pinocchio ``JointModelPlanarTpl``; docs/conventions.md.
    """
    return as_array(v, "v", (3,))[..., [1, 2, 0]]


def planar_v_from_pinocchio(v: ArrayLike) -> np.ndarray:
    """Pinocchio's planar velocity ``[v_x, v_y, ω]`` as featherdyn's ``[ω, v_x, v_y]``.

    Args:
        v: `(..., 3)` Pinocchio ``[v_x, v_y, ω]``.

    Returns:
        `(..., 3)`::

            v = [ω, v_x, v_y]

    Source: Pinocchio ``JointModelPlanarTpl``; docs/conventions.md.
    """
    return foreign_array(v, "v", "Pinocchio planar [v_x, v_y, ω]", (3,))[..., [2, 0, 1]]


# --------------------------------------------------------------------------
# objects (one value each; Pinocchio imported lazily)
# --------------------------------------------------------------------------


def to_pinocchio_motion(m: SpatialMotion | ArrayLike) -> PinMotion:
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
    vec = _single(motion_array(m, "m"), "m", "motion", "motion_to_pinocchio")
    return pin.Motion(vec[3:], vec[:3])


def from_pinocchio_motion(motion: PinMotion, frame: Frame = None) -> SpatialMotion:
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
            f"motion: expected a pinocchio.Motion, got a {qualified_type_name(motion)}"
            + (
                "; raw [linear; angular] arrays convert with motion_from_pinocchio"
                if not is_pinocchio_object(motion)
                else ""
            )
        )
    return SpatialMotion(np.array(motion.angular), np.array(motion.linear), frame)


def to_pinocchio_force(f: SpatialForce | ArrayLike) -> PinForce:
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
    vec = _single(force_array(f, "f"), "f", "force", "force_to_pinocchio")
    return pin.Force(vec[3:], vec[:3])


def from_pinocchio_force(force: PinForce, frame: Frame = None) -> SpatialForce:
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
            f"force: expected a pinocchio.Force, got a {qualified_type_name(force)}"
            + (
                "; raw [linear; angular] arrays convert with force_from_pinocchio"
                if not is_pinocchio_object(force)
                else ""
            )
        )
    return SpatialForce(np.array(force.angular), np.array(force.linear), frame)


def to_pinocchio_inertia(inertia: SpatialInertia) -> PinInertia:
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
            f"inertia: expected a SpatialInertia, got a {qualified_type_name(inertia)}; a 6×6 matrix converts with "
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


def from_pinocchio_inertia(inertia: PinInertia, frame: Frame = None) -> SpatialInertia:
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
        raise SpatialTypeError(f"inertia: expected a pinocchio.Inertia, got a {qualified_type_name(inertia)}")
    return SpatialInertia(float(inertia.mass), np.array(inertia.lever), np.array(inertia.inertia), frame)


def transform_to_pinocchio_se3(X: PluckerTransform | ArrayLike) -> PinSE3:
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
    xf = as_transform(X, "X")
    if xf.shape:
        raise ShapeError(
            f"X: expected a single transform (batch shape ()), got batch shape {xf.shape}; "
            "Pinocchio objects hold one value each"
        )
    if xf.dtype.kind == "O":
        raise SpatialTypeError("X: Pinocchio objects hold numbers; got an object (SymPy) transform")
    return pin.SE3(np.array(xf.rotation, dtype=np.float64), np.array(xf.translation, dtype=np.float64))


def transform_from_pinocchio_se3(se3: PinSE3, source: Frame = None, target: Frame = None) -> PluckerTransform:
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
            f"se3: expected a pinocchio.SE3, got a {qualified_type_name(se3)}; a (4, 4) homogeneous matrix converts with "
            "PluckerTransform.from_homogeneous"
        )
    return PluckerTransform(np.array(se3.rotation), np.array(se3.translation), source, target)
