"""Configuration space of a model: neutral and random configurations, integrate, difference.

A configuration ``q`` `(..., nq)` and a velocity ``v`` `(..., nv)` are the
joints' pieces laid end to end: body ``i``'s joint owns ``q[idx_q[i] :
idx_q[i] + nqs[i]]`` and ``v[idx_v[i] : idx_v[i] + nvs[i]]``. Every function
here works joint by joint with the joint models' own maps, so a quaternion
(spherical and free-flyer joints) is moved on the Lie group, never added to::

    revolute, prismatic:  q' = q + v
    spherical:            R(q') = R(q) exp([ω]×)        (ω in the child frame)
    free-flyer:           T(q') = T(q) exp(v)           (v = [ω; v] in the base frame)
    planar:               T(q') = T(q) exp(v)           (SE(2))

``difference`` is the inverse map, ``integrate(q0, difference(q0, q1)) = q1``:
the same as Pinocchio's ``integrate`` / ``difference`` once Pinocchio's
layouts are converted (free-flyer ``v = [v; ω]``, planar ``q = [x, y, cos θ,
sin θ]``, ``v = [v_x, v_y, ω]``).

Inputs are checked: a wrong trailing length raises :class:`ShapeError`
("q: expected trailing dimension nq=9, got shape (8,)"), NaN or infinity
:class:`NonFiniteError`, and a quaternion off unit norm by more than 1e-6
(float64; 1e-4 for float32) :class:`QuaternionNormError` naming the joint.
Batch axes lead and broadcast; float32 stays float32.

Source: Pinocchio ``algorithm/joint-configuration.hpp`` and its Lie groups;
Solà, Deray & Atchuthan (2018), "A micro Lie theory for state estimation in
robotics"; docs/architecture.md ("Conventions").
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _dask
from ._state_checks import check_state
from .errors import QuaternionNormError, ShapeError
from .model import Model
from .spatial.validation import as_array, result_dtype

__all__ = [
    "integrate_derivatives",
    "difference_derivatives",
    "neutral",
    "random_configuration",
    "integrate",
    "difference",
    "interpolate",
    "normalize",
    "is_normalized",
]

# --------------------------------------------------------------------------
# private helpers
# --------------------------------------------------------------------------


def _check_model(model: Any) -> Model:
    if not isinstance(model, Model):
        raise TypeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    return model


def _vector(x: Any, name: str, size_name: str, n: int) -> np.ndarray:
    """``x`` as an array `(..., n)`; :class:`ShapeError` naming ``size_name`` otherwise."""
    arr = as_array(x, name, (), check_finite=False)
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise ShapeError(f"{name}: expected trailing dimension {size_name}={n}, got shape {tuple(arr.shape)}")
    return as_array(arr, name, (n,))  # finiteness, with the index of the first bad value


def _broadcast_batch(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[int, ...]]:
    """``a`` and ``b`` (checked: their batch shapes broadcast) broadcast to their common batch shape."""
    batch = np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    return np.broadcast_to(a, batch + a.shape[-1:]), np.broadcast_to(b, batch + b.shape[-1:]), batch


def _slices(model: Model, i: int) -> tuple[slice, slice]:
    iq, iv = model.idx_q[i], model.idx_v[i]
    return slice(iq, iq + model.nqs[i]), slice(iv, iv + model.nvs[i])


# --------------------------------------------------------------------------
# public functions
# --------------------------------------------------------------------------


def neutral(model: Model) -> np.ndarray:
    """The neutral configuration `(nq,)`: zero angles and displacements, identity quaternions.

    Equals Pinocchio's ``pin.neutral(model)`` (planar joints converted:
    Pinocchio's ``[0, 0, 1, 0]`` is featherdyn's ``[0, 0, 0]``).

    Args:
        model: the kinematic tree.

    Returns:
        `(nq,)` float64 array.
    """
    model = _check_model(model)
    q = np.zeros(model.nq)
    for i, joint in enumerate(model.joints):
        sq, _ = _slices(model, i)
        q[sq] = joint.neutral()
    return q


def random_configuration(model: Model, rng: np.random.Generator | int | None = None, size: int | tuple[int, ...] | None = None) -> np.ndarray:
    """Random configurations within the position limits.

    Each coordinate is uniform between ``model.lower`` and ``model.upper``
    where those are finite; otherwise revolute angles and the planar angle
    are uniform in ``[−π, π]``, prismatic and free-flyer positions in
    ``[−1, 1]``. Quaternions (spherical, free-flyer) are uniform on SO(3)
    (Shoemake's method), with ``w >= 0``.

    Args:
        model: the kinematic tree.
        rng: a :class:`numpy.random.Generator`, an integer seed, or ``None``
            (a fresh ``numpy.random.default_rng()``).
        size: batch shape: ``None`` (one configuration), an int or a tuple.

    Returns:
        `(*size, nq)` float64 array.
    """
    model = _check_model(model)
    if isinstance(rng, np.random.RandomState):
        raise TypeError("rng: expected a numpy Generator, an int seed or None, got a legacy RandomState")
    try:
        gen = np.random.default_rng(rng)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"rng: expected a numpy Generator, an int seed or None, got {rng!r} ({exc})") from None
    try:
        shape = () if size is None else ((int(size),) if isinstance(size, (int, np.integer)) else tuple(int(s) for s in size))
    except (TypeError, ValueError):
        raise ShapeError(f"size: expected None, an int or a tuple of ints, got {size!r}") from None
    if any(s < 0 for s in shape):
        raise ShapeError(f"size: expected non-negative sizes, got {shape}")
    q = np.empty(shape + (model.nq,))
    for i, joint in enumerate(model.joints):
        sq, _ = _slices(model, i)
        q[..., sq] = joint.random(gen, model.lower[sq], model.upper[sq], shape)
    return q


def integrate(model: Model, q: ArrayLike, v: ArrayLike) -> np.ndarray:
    """The configuration reached from ``q`` moving with velocity ``v`` for unit time.

    Joint by joint, on each joint's Lie group (velocities in the moving
    frame, Pinocchio's convention)::

        q' = q ⊕ v:   q + v (revolute, prismatic),  R(q) exp(ω) (spherical),
                      T(q') = T(q) exp(v) (free-flyer, planar)

    Args:
        model: the kinematic tree.
        q: `(..., nq)` configuration (quaternions unit within 1e-6).
        v: `(..., nv)` velocity; batch axes broadcast with ``q``'s.

    Returns:
        `(..., nq)` configuration, dtype of ``q`` and ``v`` combined.

    Raises:
        ShapeError, NonFiniteError, QuaternionNormError.
    """
    if _dask.lazy(q, v):
        return _dask.call(integrate, model, {"q": q, "v": v})
    st = check_state(_check_model(model), q, v=v)
    qq, vv, batch = _broadcast_batch(st.q, st.arrays["v"])
    out = np.empty(batch + (model.nq,), dtype=result_dtype(qq, vv))
    for i, joint in enumerate(model.joints):
        sq, sv = _slices(model, i)
        out[..., sq] = joint.integrate(qq[..., sq], vv[..., sv])
    return out


def difference(model: Model, q0: ArrayLike, q1: ArrayLike) -> np.ndarray:
    """The velocity that takes ``q0`` to ``q1`` in unit time: the inverse of :func:`integrate`.

    ::

        v = q1 ⊖ q0   with   integrate(q0, v) = q1
          = q1 − q0 (revolute, prismatic),  log(R(q0)ᵀ R(q1)) (spherical),
            log(T(q0)⁻¹ T(q1)) (free-flyer, planar)

    Rotation parts take the shorter way (angle in ``[0, π]``).

    Args:
        model: the kinematic tree.
        q0: `(..., nq)` start configuration.
        q1: `(..., nq)` end configuration; batch axes broadcast with ``q0``'s.

    Returns:
        `(..., nv)` velocity in the moving frames of ``q0``.

    Raises:
        ShapeError, NonFiniteError, QuaternionNormError.
    """
    if _dask.lazy(q0, q1):
        return _dask.call(difference, model, {"q0": q0, "q1": q1})
    st = check_state(_check_model(model), q0, name="q0", q1=q1)
    a0, a1, batch = _broadcast_batch(st.q, st.arrays["q1"])
    out = np.empty(batch + (model.nv,), dtype=result_dtype(a0, a1))
    for i, joint in enumerate(model.joints):
        sq, sv = _slices(model, i)
        out[..., sv] = joint.difference(a0[..., sq], a1[..., sq])
    return out


def _joint_blocks(model: Model, kind: str, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The two block-diagonal tangent maps of integrate (kind "integrate": a = q, b = v) or difference
    (kind "difference": a = q0, b = q1), one block per joint."""
    from .joints import FreeFlyerJoint, PlanarJoint, SphericalJoint
    from .spatial import lie

    a, b, batch = _broadcast_batch(a.astype(np.float64), b.astype(np.float64))
    nv = model.nv
    A = np.zeros(batch + (nv, nv))
    B = np.zeros(batch + (nv, nv))
    for i, joint in enumerate(model.joints):
        sq, sv = _slices(model, i)
        if kind == "integrate":
            xi = b[..., sv]
        else:
            xi = joint.difference(a[..., sq], b[..., sq])
        if isinstance(joint, FreeFlyerJoint):
            Ad_inv, Jr = lie.se3_inverse_adjoint_of_exp(xi), lie.se3_right_jacobian(xi)
        elif isinstance(joint, SphericalJoint):
            Jr = lie.so3_right_jacobian(xi)  # Ad(exp(ω))⁻¹ = exp(ω)ᵀ: SE(3)'s rotation block with v = 0
            Ad_inv = lie.se3_inverse_adjoint_of_exp(np.concatenate([xi, np.zeros_like(xi)], -1))[..., :3, :3]
        elif isinstance(joint, PlanarJoint):
            Ad_inv, Jr = lie.se2_inverse_adjoint_of_exp(xi), lie.se2_right_jacobian(xi)
        else:  # revolute, prismatic: a vector space
            n = model.nvs[i]
            Ad_inv = Jr = np.broadcast_to(np.eye(n), batch + (n, n))
        if kind == "integrate":
            A[..., sv, sv], B[..., sv, sv] = Ad_inv, Jr
        else:
            Jr_inv = np.linalg.inv(Jr)
            A[..., sv, sv], B[..., sv, sv] = -(Jr_inv @ Ad_inv), Jr_inv
    return A, B


def integrate_derivatives(model: Model, q: ArrayLike, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``(J_q, J_v)`` `(..., nv, nv)`: the tangent maps of ``q' = integrate(q, v)``, block-diagonal by joint.

    With tangents in ``v``'s layout at ``q`` and at ``q'`` (Pinocchio's ``dIntegrate``, up to the
    free-flyer's ``[v; ω]`` order)::

        integrate(q ⊕ δ, v) = q' ⊕ J_q δ,    integrate(q, v + δ) = q' ⊕ J_v δ    (to first order)
        J_q = Ad(exp(v))⁻¹,   J_v = Jr(v)   (the group's right Jacobian; identities for revolute, prismatic)

    Raises:
        ShapeError, NonFiniteError, QuaternionNormError.
    """
    if _dask.lazy(q, v):
        return _dask.call(integrate_derivatives, model, {"q": q, "v": v})
    st = check_state(_check_model(model), q, v=v)
    return _joint_blocks(model, "integrate", st.q, st.arrays["v"])


def difference_derivatives(model: Model, q0: ArrayLike, q1: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``(J_0, J_1)`` `(..., nv, nv)`: the tangent maps of ``v = difference(q0, q1)``, block-diagonal by joint.

    ::

        difference(q0 ⊕ δ, q1) = v + J_0 δ,    difference(q0, q1 ⊕ δ) = v + J_1 δ    (to first order)
        J_1 = Jr(v)⁻¹,   J_0 = −Jr(v)⁻¹ Ad(exp(v))⁻¹   (Pinocchio's ``dDifference``, ARG0 and ARG1)

    Raises:
        ShapeError, NonFiniteError, QuaternionNormError.
    """
    if _dask.lazy(q0, q1):
        return _dask.call(difference_derivatives, model, {"q0": q0, "q1": q1})
    st = check_state(_check_model(model), q0, name="q0", q1=q1)
    return _joint_blocks(model, "difference", st.q, st.arrays["q1"])


def interpolate(model: Model, q0: ArrayLike, q1: ArrayLike, t: ArrayLike) -> np.ndarray:
    """The configuration a fraction ``t`` of the way from ``q0`` to ``q1`` (geodesic per joint).

    ::

        q(t) = integrate(q0, t · difference(q0, q1)),    q(0) = q0,  q(1) = q1

    (Pinocchio's ``interpolate``.)

    Args:
        model: the kinematic tree.
        q0, q1: `(..., nq)` configurations.
        t: `(...)` fractions (any real numbers; 0 and 1 give the ends).

    Returns:
        `(..., nq)` configuration.
    """
    model = _check_model(model)
    tt = as_array(t, "t", ())
    dv = difference(model, q0, q1)
    if tt.dtype.kind == "f" and dv.dtype.kind == "f":
        tt = tt.astype(dv.dtype)  # a Python float t keeps float32 configurations float32
    return integrate(model, q0, tt[..., None] * dv)


def normalize(model: Model, q: ArrayLike) -> np.ndarray:
    """The nearest valid configuration: every quaternion scaled to unit norm, the rest unchanged.

    ::

        quat ← quat / |quat|

    Args:
        model: the kinematic tree.
        q: `(..., nq)` configuration (quaternions non-zero).

    Returns:
        `(..., nq)` a new array.

    Raises:
        ShapeError, NonFiniteError, QuaternionNormError (a zero quaternion).
    """
    model = _check_model(model)
    qq = _vector(q, "q", "nq", model.nq)
    out = np.array(qq)
    for i, joint in enumerate(model.joints):
        sq, _ = _slices(model, i)
        try:
            out[..., sq] = joint.normalize(qq[..., sq])
        except QuaternionNormError:
            raise QuaternionNormError(
                f"q: joint {model.joint_names[i]!r} ({joint.kind}, q[{sq.start}:{sq.stop}]): "
                "a zero quaternion cannot be normalised"
            ) from None
    return out


def is_normalized(model: Model, q: ArrayLike, tol: float = 1e-10) -> np.ndarray | bool:
    """Whether every quaternion of ``q`` has unit norm within ``tol``.

    ::

        | |quat| − 1 | <= tol   for every spherical and free-flyer joint

    Args:
        model: the kinematic tree.
        q: `(..., nq)` configuration.
        tol: the allowed deviation of each quaternion's norm from 1.

    Returns:
        `(...)` bool array; a plain ``bool`` for a single configuration.
    """
    model = _check_model(model)
    qq = _vector(q, "q", "nq", model.nq)
    ok = np.ones(qq.shape[:-1], dtype=bool)
    for i, joint in enumerate(model.joints):
        sq, _ = _slices(model, i)
        ok &= joint.is_normalized(qq[..., sq], tol)
    return bool(ok) if ok.ndim == 0 else ok
