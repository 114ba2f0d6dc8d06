"""SymPy proofs of the chapter's identities (``prove_*``), for :mod:`featherdyn.symbolic`.

Each proof builds the chapter's objects with featherdyn's own code on SymPy
object arrays, forms the difference of the two sides of an identity and
returns ``True`` when it reduces to zero *exactly* (:mod:`.reduce`)::

    prove_x() = is_zero(lhs − rhs)      (no random numeric point is ever used)

Sources: chapter §3 (``det X = 1``), §4 (Jacobi, ``crf = −crmᵀ``), §2.3
(power), §5.2 (parallel axis), §5.3 (10 parameters), appendices F and I;
Featherstone, *RBDA* (2008) ch. 2.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np

from ..rotation import quat_to_matrix, rpy_to_matrix
from ..spatial import PluckerTransform, SpatialForce, SpatialInertia, SpatialMotion, crf, crm, skew
from .reduce import Reducer, import_sympy, is_zero, object_array, sympy_matrix

__all__ = [
    "PARAMETRIZATIONS",
    "all_proofs",
    "prove_cross_antisymmetry",
    "prove_cross_equivariance",
    "prove_crf_is_minus_crm_transpose",
    "prove_dynamic_parameters_round_trip",
    "prove_force_cross_duality",
    "prove_gyroscopic_identity",
    "prove_inertia_linear_in_dynamic_parameters",
    "prove_jacobi_identity",
    "prove_kinetic_energy_invariance",
    "prove_parallel_axis",
    "prove_plucker_determinant",
    "prove_power_invariance",
    "prove_pure_rotation_orthogonal",
    "prove_transform_inverse",
]

#: the two ways a symbolic rotation is parametrised in the proofs
PARAMETRIZATIONS = ("quaternion", "rpy")


# --------------------------------------------------------------------------
# symbolic building blocks
# --------------------------------------------------------------------------


def _rotation(parametrization: str) -> tuple[np.ndarray, Reducer]:
    """A general symbolic rotation (featherdyn's own formula) and the reducer that knows its constraint."""
    sp = import_sympy()
    if parametrization == "quaternion":
        quat = sp.symbols("q_x q_y q_z q_w", real=True)
        return quat_to_matrix(object_array(quat)), Reducer(quat)
    if parametrization == "rpy":
        return rpy_to_matrix(object_array(sp.symbols("roll pitch yaw", real=True))), Reducer()
    raise ValueError(f"parametrization: expected one of {PARAMETRIZATIONS}, got {parametrization!r}")


def _transform(parametrization: str) -> tuple[PluckerTransform, Reducer]:
    """``X = (R, p)`` with a general rotation and a symbolic translation ``p``."""
    sp = import_sympy()
    R, red = _rotation(parametrization)
    p = object_array(sp.symbols("p_x p_y p_z", real=True))
    return PluckerTransform(R, p, validate=False), red


def _motion(name: str) -> SpatialMotion:
    sp = import_sympy()
    return SpatialMotion.from_vector(object_array(sp.symbols(f"{name}_0:6", real=True)))


def _force(name: str) -> SpatialForce:
    sp = import_sympy()
    return SpatialForce.from_vector(object_array(sp.symbols(f"{name}_0:6", real=True)))


def _inertia(name: str = "") -> SpatialInertia:
    """A general spatial inertia: symbolic m, c and a symmetric I_c (10 symbols)."""
    sp = import_sympy()
    m = sp.Symbol(f"m{name}", positive=True)
    c = object_array(sp.symbols(f"c{name}_x c{name}_y c{name}_z", real=True))
    xx, xy, yy, xz, yz, zz = sp.symbols(f"I{name}_xx I{name}_xy I{name}_yy I{name}_xz I{name}_yz I{name}_zz", real=True)
    Ic = object_array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    return SpatialInertia(m, c, Ic)


# --------------------------------------------------------------------------
# proofs: Plücker transforms
# --------------------------------------------------------------------------


def prove_plucker_determinant(parametrization: str = "quaternion") -> bool:
    """``det X = 1`` for every Plücker transform (chapter exercise 1, appendix F.1).

    ``X = [[R, 0], [[p]×R, R]]`` with a general rotation ``R`` (unit
    quaternion or rpy angles) and a symbolic ``p``; the 6×6 determinant is
    expanded in full (Berkowitz), not taken from the block formula (the
    exercise's hint, with ``A = D = R``, ``B = 0``, ``C = [p]×R``)::

        det X = det(A) · det(D − C A⁻¹ B) = det(R) · det(R) = 1
    """
    X, red = _transform(parametrization)
    Xm = sympy_matrix(X.matrix()).applyfunc(red.poly)
    return red.is_zero(Xm.det(method="berkowitz") - 1) and red.is_zero(sympy_matrix(X.rotation).det() - 1)


def prove_pure_rotation_orthogonal(parametrization: str = "quaternion") -> bool:
    """A pure rotation ``X_rot = diag(R, R)`` is orthogonal: ``X_rot X_rotᵀ = 1`` (chapter exercise 2).

    (A transform with ``p ≠ 0`` is not: ``X Xᵀ`` has the block ``[p]×[p]×ᵀ + 1``;
    see ``tests/unit/test_symbolic.py``.)
    """
    R, red = _rotation(parametrization)
    Xrot = sympy_matrix(PluckerTransform(R, object_array([0, 0, 0]), validate=False).matrix())
    sp = import_sympy()
    return red.is_zero(Xrot * Xrot.T - sp.eye(6))


def prove_transform_inverse(parametrization: str = "quaternion") -> bool:
    """Inverse and dual (chapter §3.3, appendix F.1, corrected)::

        X⁻¹ = [[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]]      (X.inverse().matrix())
        X*  = X⁻ᵀ = [[R, [p]×R], [0, R]]    (X.dual_matrix())
        X*ᵀ = X⁻¹,    (X*)⁻¹ = (X⁻¹)* = Xᵀ   (F.1 prints X⁻ᵀ here, which is X* itself)
    """
    X, red = _transform(parametrization)
    sp = import_sympy()
    Xm, Xi, Xd = sympy_matrix(X.matrix()), sympy_matrix(X.inverse().matrix()), sympy_matrix(X.dual_matrix())
    Xinv_d = sympy_matrix(X.inverse().dual_matrix())
    one = sp.eye(6)
    return (
        red.is_zero(Xi * Xm - one)
        and red.is_zero(Xd.T * Xm - one)  # X*ᵀ = X⁻¹
        and red.is_zero(Xd * Xm.T - one)  # (X*)⁻¹ = Xᵀ
        and red.is_zero(Xinv_d - Xm.T)  # (X⁻¹)* = Xᵀ
    )


def prove_power_invariance(parametrization: str = "quaternion") -> bool:
    """Power is frame-independent: ``(X m) · (X* f) = m · f`` (chapter §2.3, §3.3).

    ``m``, ``f`` are general (12 symbols), ``X`` general; ``X.apply`` is
    featherdyn's motion and force transform.
    """
    X, red = _transform(parametrization)
    m, f = _motion("m"), _force("f")
    return red.is_zero(X.apply(m).dot(X.apply(f)) - m.dot(f))


def prove_cross_equivariance(parametrization: str = "quaternion") -> bool:
    """The cross products commute with transforms (appendix F.2 row 3)::

        (X v) × (X w) = X (v × w),        (X v) ×* (X* f) = X* (v ×* f)
    """
    X, red = _transform(parametrization)
    v, w, f = _motion("v"), _motion("w"), _force("f")
    lhs_m = X.apply(v).cross(X.apply(w)).vector - X.apply(v.cross(w)).vector
    lhs_f = X.apply(v).cross(X.apply(f)).vector - X.apply(v.cross(f)).vector
    return red.is_zero(lhs_m) and red.is_zero(lhs_f)


# --------------------------------------------------------------------------
# proofs: cross products
# --------------------------------------------------------------------------


def prove_jacobi_identity() -> bool:
    """Jacobi identity of the motion cross product (chapter §4.1, §13.1, exercise 5)::

        v₁ × (v₂ × v₃) + v₂ × (v₃ × v₁) + v₃ × (v₁ × v₂) = 0

    for general ``v₁, v₂, v₃`` (18 symbols), with featherdyn's ``crm``.
    """
    v1, v2, v3 = (_motion(n).vector for n in ("a", "b", "c"))

    def x(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return crm(a) @ b

    return is_zero(x(v1, x(v2, v3)) + x(v2, x(v3, v1)) + x(v3, x(v1, v2)))


def prove_cross_antisymmetry() -> bool:
    """``v₁ × v₂ = −v₂ × v₁`` (the product is anticommutative; the *matrix* ``crm(v)`` is not skew).

    See chapter exercise 3: ``crm(v) + crm(v)ᵀ = [[0, [v_O]×ᵀ], [[v_O]×, 0]] ≠ 0``.
    """
    a, b = _motion("a"), _motion("b")
    return is_zero(a.cross(b).vector + b.cross(a).vector)


def prove_crf_is_minus_crm_transpose() -> bool:
    """``[v]×* = −[v]×ᵀ`` (chapter §4.2, appendix A.2), for a general ``v``::

        crf(v) = [[[ω]×, [v_O]×], [0, [ω]×]] = −crm(v)ᵀ
    """
    v = _motion("v").vector
    return is_zero(crf(v) + crm(v).T)


def prove_force_cross_duality() -> bool:
    """Duality of the two cross products, with the sign the chapter's §10.3 check gets wrong::

        v₂ · (v₁ ×* f) = −(v₁ × v₂) · f          (§10.3 prints "+")
        v · (v ×* f)   = 0                        (exercise 4(c) of the second list)
    """
    v1, v2, f = _motion("a"), _motion("b"), _force("f")
    return is_zero(v2.dot(v1.cross(f)) + v1.cross(v2).dot(f)) and is_zero(v1.dot(v1.cross(f)))


def prove_gyroscopic_identity() -> bool:
    """The bias force of one body, appendix F.2 row 4 with its sign corrected::

        v ×* (I v) = −(v×)ᵀ I v        (F.2 prints  −I(v × v) + (v×)ᵀ I v  =  +(v×)ᵀ I v)

    for a general ``v`` and a general spatial inertia ``I``.
    """
    v = _motion("v")
    inertia = _inertia()
    Iv = inertia @ v
    lhs = v.cross(Iv).vector
    rhs = -(crm(v.vector).T @ (inertia.matrix() @ v.vector))
    return is_zero(lhs - rhs)


# --------------------------------------------------------------------------
# proofs: inertia
# --------------------------------------------------------------------------


def prove_parallel_axis(parametrization: str = "quaternion") -> bool:
    """The spatial parallel-axis theorem (chapter §5.1–§5.2)::

        I_B = X* I_A X⁻¹ = [[Ī, m[c']×], [m[c']×ᵀ, m 1]],
        c' = R c + p,   I_c' = R I_c Rᵀ,   Ī = I_c' − m [c']×[c']×

    checked three ways against each other for a general body and a general
    transform: the 6×6 matrix product, featherdyn's ``X.apply(inertia)`` (which
    moves ``c`` and ``I_c`` directly), and the closed form written out here
    with SymPy matrices.
    """
    sp = import_sympy()
    X, red = _transform(parametrization)
    I_A = _inertia()
    product = sympy_matrix(X.dual_matrix()) * sympy_matrix(I_A.matrix()) * sympy_matrix(X.inverse().matrix())
    applied = sympy_matrix(X.apply(I_A).matrix())
    R, p = sympy_matrix(X.rotation), sympy_matrix(X.translation[:, None])
    c = R * sympy_matrix(I_A.com[:, None]) + p
    Ic = R * sympy_matrix(I_A.inertia_com) * R.T
    cx = sympy_matrix(skew(np.array(list(c), dtype=object)))
    m = I_A.mass[()]
    closed = sp.BlockMatrix([[Ic - m * cx * cx, m * cx], [m * cx.T, m * sp.eye(3)]]).as_explicit()
    return red.is_zero(product - closed) and red.is_zero(applied - closed)


def prove_kinetic_energy_invariance(parametrization: str = "quaternion") -> bool:
    """``½ (X v)ᵀ I_B (X v) = ½ vᵀ I_A v`` with ``I_B = X.apply(I_A)`` (appendix C.2)."""
    X, red = _transform(parametrization)
    I_A, v = _inertia(), _motion("v")
    return red.is_zero(X.apply(I_A).kinetic_energy(X.apply(v)) - I_A.kinetic_energy(v))


def prove_dynamic_parameters_round_trip() -> bool:
    """``(m, c, I_c) → π → (m, c, I_c)`` is the identity (chapter §5.3: 10 parameters)::

        π = [m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]    (I about the origin, Pinocchio's order)
    """
    I_A = _inertia()
    back = SpatialInertia.from_dynamic_parameters(I_A.to_dynamic_parameters())
    sp = import_sympy()
    pi = object_array(sp.symbols("pi_0:10", real=True))
    pi_back = SpatialInertia.from_dynamic_parameters(pi).to_dynamic_parameters()
    return (
        is_zero(back.mass - I_A.mass)
        and is_zero(back.com - I_A.com)
        and is_zero(back.inertia_com - I_A.inertia_com)
        and is_zero(pi_back - pi)
    )


def prove_inertia_linear_in_dynamic_parameters() -> bool:
    """The 6×6 spatial inertia is linear in the 10 dynamic parameters::

        I(π) = Σ_k π_k ∂I/∂π_k     (every second derivative vanishes, I(0) = 0)

    although ``c = h/m`` and ``I_c = I_O + [h]×[h]×/m`` are not: the ``1/m``
    terms cancel. This is what makes ``τ = Y(q, q̇, q̈) π`` (RBDA §2.13).
    """
    sp = import_sympy()
    pi = sp.symbols("pi_0:10", real=True)
    Imat = sympy_matrix(SpatialInertia.from_dynamic_parameters(object_array(pi)).matrix()).applyfunc(lambda e: sp.cancel(sp.together(e)))
    for e in Imat:
        for a, b in itertools.combinations_with_replacement(pi, 2):
            if sp.diff(e, a, b) != 0:
                return False
        if e.subs(dict.fromkeys(pi, 0)) != 0:
            return False
    return True


def all_proofs(parametrizations: Sequence[str] = ("quaternion",)) -> dict[str, bool]:
    """Run every ``prove_*`` (the rotation-dependent ones once per parametrisation); name → result."""
    out: dict[str, bool] = {}
    with_rotation: list[Callable[[str], bool]] = [
        prove_plucker_determinant,
        prove_pure_rotation_orthogonal,
        prove_transform_inverse,
        prove_power_invariance,
        prove_cross_equivariance,
        prove_parallel_axis,
        prove_kinetic_energy_invariance,
    ]
    for fn in with_rotation:
        for par in parametrizations:
            out[f"{fn.__name__}[{par}]"] = fn(par)
    plain: list[Callable[[], bool]] = [
        prove_jacobi_identity,
        prove_cross_antisymmetry,
        prove_crf_is_minus_crm_transpose,
        prove_force_cross_duality,
        prove_gyroscopic_identity,
        prove_dynamic_parameters_round_trip,
        prove_inertia_linear_in_dynamic_parameters,
    ]
    for fn0 in plain:
        out[fn0.__name__] = fn0()
    return out
