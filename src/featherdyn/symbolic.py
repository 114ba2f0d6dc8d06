"""SymPy proofs of the chapter's identities, and closed-form dynamics of small robots.

Two kinds of functions live here.

**Proofs** (``prove_*``). Each builds the chapter's objects with featherdyn's
own code (:class:`~featherdyn.PluckerTransform`, :func:`~featherdyn.crm`,
:class:`~featherdyn.SpatialInertia`, ...) on SymPy object arrays, forms the
difference of the two sides of an identity and returns ``True`` when it
reduces to zero *exactly*. No random numeric point is ever used. The
reduction is polynomial and therefore canonical:

* a rotation is parametrised either by a unit quaternion ``(x, y, z, w)``
  (``w²`` is eliminated with ``x² + y² + z² + w² = 1``) or by roll-pitch-yaw
  angles (``sin θ``, ``cos θ`` become symbols ``s``, ``c`` and ``s²`` is
  eliminated with ``s² + c² = 1``);
* floats coming from constant model data (``1.0`` in a motion subspace) are
  replaced by the rationals they print as;
* the result is expanded. ``{s² + c² − 1}`` and ``{|q|² − 1}`` are Gröbner
  bases with coprime leading terms, so the remainder is zero iff the
  expression vanishes on the constraint set.

**Closed-form dynamics.** :func:`mass_matrix`, :func:`coriolis` and
:func:`gravity` run the reference algorithms (:func:`featherdyn.crba`,
:func:`featherdyn.coriolis_matrix`, :func:`featherdyn.generalized_gravity`) on
object arrays of symbols and reduce the result the same way;
:func:`symbolic_model` puts symbolic masses, lengths and gravity into a model.
:func:`lagrangian_two_link` derives ``M``, ``C``, ``g`` of the chapter's
appendix-D arm from its Lagrangian, independently of the spatial algebra, and
:func:`check_two_link` proves the two derivations equal.

SymPy is optional (a test dependency); it is imported on first use and its
absence raises :class:`~featherdyn.errors.MissingDependencyError`.

Sources: chapter §3 (``det X = 1``), §4 (Jacobi, ``crf = −crmᵀ``), §2.3
(power), §5.2 (parallel axis), §5.3 (10 parameters), appendices F and I;
Featherstone, *RBDA* (2008) ch. 2.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

from .errors import MissingDependencyError, ShapeError

__all__ = [
    "PARAMETRIZATIONS",
    "APPENDIX_D",
    "TwoLinkDynamics",
    "all_proofs",
    "canonical",
    "check_two_link",
    "coriolis",
    "gravity",
    "is_zero",
    "lagrangian_two_link",
    "mass_matrix",
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
    "symbolic_model",
    "two_link_arm",
    "two_link_symbols",
]

#: the two ways a symbolic rotation is parametrised in the proofs
PARAMETRIZATIONS = ("quaternion", "rpy")

#: the chapter's appendix-D arm (D.1): lengths, masses, CoM distances from the joint, I_zz about the CoM
APPENDIX_D: dict[str, float] = {
    "l1": 1.0, "m1": 3.0, "c1": 0.5, "I1": 0.25,
    "l2": 0.8, "m2": 2.0, "c2": 0.4, "I2": 0.11,
    "g": 9.81,
}


def _sympy() -> Any:
    try:
        import sympy
    except ImportError:
        raise MissingDependencyError(
            "featherdyn.symbolic needs SymPy, which is not installed: pip install sympy"
        ) from None
    return sympy


def _obj(values: Iterable[Any]) -> np.ndarray:
    """An object array (SymPy entries) from a nested sequence."""
    return np.array(list(values) if not isinstance(values, np.ndarray) else values, dtype=object)


# --------------------------------------------------------------------------
# exact reduction
# --------------------------------------------------------------------------


class _Reducer:
    """Canonical form of polynomial expressions in sin/cos of symbols and in a unit quaternion.

    ``sin(a)``, ``cos(a)`` of each symbol ``a`` become symbols ``s_a``, ``c_a``;
    after expansion ``s_a^k → s_a^(k mod 2) (1 − c_a²)^(k div 2)`` (and the same
    for ``w`` of a unit quaternion), then expansion again. Arguments that are
    sums or integer multiples of symbols are expanded first (``expand_trig``);
    other arguments (``sin(q/2)``) are treated as independent angles, so an
    identity relating them to ``sin(q)`` is reported as not proved (never the
    other way round). Rational functions are cancelled and their numerator
    and denominator reduced.
    """

    def __init__(self, quaternion: Sequence[Any] | None = None) -> None:
        self.sp = _sympy()
        self.quaternion = tuple(quaternion) if quaternion is not None else None
        self._sc: dict[Any, tuple[Any, Any]] = {}

    def _pair(self, arg: Any) -> tuple[Any, Any]:
        if arg not in self._sc:
            name = str(arg)
            self._sc[arg] = (self.sp.Symbol(f"_s[{name}]", real=True), self.sp.Symbol(f"_c[{name}]", real=True))
        return self._sc[arg]

    def poly(self, expr: Any) -> Any:
        """``expr`` with floats made rational and sin/cos of symbols replaced by ``s``/``c`` symbols."""
        sp = self.sp
        expr = sp.sympify(expr)
        floats = expr.atoms(sp.Float)
        if floats:
            expr = expr.xreplace({f: sp.Rational(repr(float(f))) for f in floats})
        trig = expr.atoms(sp.sin, sp.cos)
        if any(not t.args[0].is_Symbol for t in trig):
            expr = sp.expand_trig(expr)
            trig = expr.atoms(sp.sin, sp.cos)
        mapping = {}
        for t in trig:
            s, c = self._pair(t.args[0])
            mapping[t] = s if isinstance(t, sp.sin) else c
        return expr.xreplace(mapping) if mapping else expr

    def reduce(self, expr: Any) -> Any:
        """The canonical form of ``expr``: a reduced, expanded polynomial (or a quotient of two, cancelled)."""
        sp = self.sp
        e = self.poly(expr)
        if any(a.exp.is_negative and a.base.free_symbols for a in e.atoms(sp.Pow)):
            # a rational function (e.g. the CoM (m₁c₁ + m₂c₂)/(m₁ + m₂) of a composite body)
            num, den = sp.fraction(sp.cancel(sp.together(e)))
            num, den = self._reduce_poly(num), self._reduce_poly(den)
            return sp.cancel(num / den) if num != 0 else sp.Integer(0)
        return self._reduce_poly(e)

    def _reduce_poly(self, e: Any) -> Any:
        sp = self.sp
        e = sp.expand(e)
        rules: dict[Any, Any] = {s: 1 - c**2 for s, c in self._sc.values()}
        if self.quaternion is not None:
            x, y, z, w = self.quaternion
            rules[w] = 1 - x**2 - y**2 - z**2
        if not rules:
            return e

        def high_power(a: Any) -> bool:
            return bool(a.is_Pow and a.base in rules and a.exp.is_Integer and a.exp >= 2)

        def lower(a: Any) -> Any:
            k = int(a.exp)
            return a.base ** (k % 2) * rules[a.base] ** (k // 2)

        return sp.expand(e.replace(high_power, lower))

    def back(self, expr: Any) -> Any:
        """Replace the ``s``/``c`` symbols by ``sin``/``cos`` again."""
        sp = self.sp
        mapping = {}
        for arg, (s, c) in self._sc.items():
            mapping[s] = sp.sin(arg)
            mapping[c] = sp.cos(arg)
        return expr.xreplace(mapping) if mapping else expr

    def is_zero(self, expr: Any) -> bool:
        sp = self.sp
        if isinstance(expr, np.ndarray):
            return all(self.is_zero(e) for e in expr.ravel())
        if isinstance(expr, sp.MatrixBase):
            return all(self.is_zero(e) for e in expr)
        return bool(self.reduce(expr) == 0)


def canonical(expr: Any, *, unit_quaternion: Sequence[Any] | None = None) -> Any:
    """The canonical expanded form of a trigonometric (and/or unit-quaternion) polynomial.

    ``sin``/``cos`` of symbols are reduced with ``sin² = 1 − cos²`` (compound
    arguments are expanded first), ``w²`` of ``unit_quaternion = (x, y, z, w)``
    with ``w² = 1 − x² − y² − z²``; floats are made rational. Two expressions
    are equal on the constraint set iff their canonical forms are equal.
    Matrices and object arrays are reduced entry by entry.
    """
    sp = _sympy()
    red = _Reducer(unit_quaternion)
    if isinstance(expr, np.ndarray):
        out = np.empty(expr.shape, dtype=object)
        for idx in np.ndindex(*expr.shape):
            out[idx] = red.back(red.reduce(expr[idx]))
        return out
    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(lambda e: red.back(red.reduce(e)))
    return red.back(red.reduce(expr))


def is_zero(expr: Any, *, unit_quaternion: Sequence[Any] | None = None) -> bool:
    """Whether ``expr`` (scalar, matrix or object array) reduces to exactly zero (see :func:`canonical`)."""
    return _Reducer(unit_quaternion).is_zero(expr)


def _pretty(expr: Any) -> Any:
    """A readable form of a canonical expression: collect, then recombine cos(a ± b) where it shortens."""
    sp = _sympy()
    if expr == 0:
        return expr
    out = sp.factor_terms(expr)
    if out.has(sp.sin, sp.cos) and sp.count_ops(out) < 120:
        short = sp.trigsimp(out)
        if sp.count_ops(short) <= sp.count_ops(out):
            out = short
    return out


# --------------------------------------------------------------------------
# symbolic building blocks
# --------------------------------------------------------------------------


def _rotation(parametrization: str) -> tuple[np.ndarray, _Reducer]:
    """A general symbolic rotation (featherdyn's own formula) and the reducer that knows its constraint."""
    from .rotation import quat_to_matrix, rpy_to_matrix

    sp = _sympy()
    if parametrization == "quaternion":
        quat = sp.symbols("q_x q_y q_z q_w", real=True)
        return quat_to_matrix(_obj(quat)), _Reducer(quat)
    if parametrization == "rpy":
        return rpy_to_matrix(_obj(sp.symbols("roll pitch yaw", real=True))), _Reducer()
    raise ValueError(f"parametrization: expected one of {PARAMETRIZATIONS}, got {parametrization!r}")


def _transform(parametrization: str) -> tuple[Any, _Reducer]:
    """``X = (R, p)`` with a general rotation and a symbolic translation ``p``."""
    from .spatial_algebra import PluckerTransform

    sp = _sympy()
    R, red = _rotation(parametrization)
    p = _obj(sp.symbols("p_x p_y p_z", real=True))
    return PluckerTransform(R, p, validate=False), red


def _motion(name: str) -> Any:
    from .spatial_algebra import SpatialMotion

    sp = _sympy()
    return SpatialMotion.from_vector(_obj(sp.symbols(f"{name}_0:6", real=True)))


def _force(name: str) -> Any:
    from .spatial_algebra import SpatialForce

    sp = _sympy()
    return SpatialForce.from_vector(_obj(sp.symbols(f"{name}_0:6", real=True)))


def _inertia(name: str = "") -> Any:
    """A general spatial inertia: symbolic m, c and a symmetric I_c (10 symbols)."""
    from .spatial_algebra import SpatialInertia

    sp = _sympy()
    m = sp.Symbol(f"m{name}", positive=True)
    c = _obj(sp.symbols(f"c{name}_x c{name}_y c{name}_z", real=True))
    xx, xy, yy, xz, yz, zz = sp.symbols(f"I{name}_xx I{name}_xy I{name}_yy I{name}_xz I{name}_yz I{name}_zz", real=True)
    Ic = _obj([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    return SpatialInertia(m, c, Ic)


def _mat(a: Any) -> Any:
    return _sympy().Matrix(np.asarray(a, dtype=object).tolist())


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
    Xm = _mat(X.matrix()).applyfunc(red.poly)
    return red.is_zero(Xm.det(method="berkowitz") - 1) and red.is_zero(_mat(X.rotation).det() - 1)


def prove_pure_rotation_orthogonal(parametrization: str = "quaternion") -> bool:
    """A pure rotation ``X_rot = diag(R, R)`` is orthogonal: ``X_rot X_rotᵀ = 1`` (chapter exercise 2).

    (A transform with ``p ≠ 0`` is not: ``X Xᵀ`` has the block ``[p]×[p]×ᵀ + 1``;
    see ``tests/unit/test_symbolic.py``.)
    """
    from .spatial_algebra import PluckerTransform

    R, red = _rotation(parametrization)
    Xrot = _mat(PluckerTransform(R, _obj([0, 0, 0]), validate=False).matrix())
    sp = _sympy()
    return red.is_zero(Xrot * Xrot.T - sp.eye(6))


def prove_transform_inverse(parametrization: str = "quaternion") -> bool:
    """Inverse and dual (chapter §3.3, appendix F.1, corrected)::

        X⁻¹ = [[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]]      (X.inverse().matrix())
        X*  = X⁻ᵀ = [[R, [p]×R], [0, R]]    (X.dual_matrix())
        X*ᵀ = X⁻¹,    (X*)⁻¹ = (X⁻¹)* = Xᵀ   (F.1 prints X⁻ᵀ here, which is X* itself)
    """
    X, red = _transform(parametrization)
    sp = _sympy()
    Xm, Xi, Xd = _mat(X.matrix()), _mat(X.inverse().matrix()), _mat(X.dual_matrix())
    Xinv_d = _mat(X.inverse().dual_matrix())
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
    from .spatial_algebra import crm

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
    from .spatial_algebra import crf, crm

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
    from .spatial_algebra import crm

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
    from .spatial_algebra import skew

    sp = _sympy()
    X, red = _transform(parametrization)
    I_A = _inertia()
    product = _mat(X.dual_matrix()) * _mat(I_A.matrix()) * _mat(X.inverse().matrix())
    applied = _mat(X.apply(I_A).matrix())
    R, p = _mat(X.rotation), _mat(X.translation[:, None])
    c = R * _mat(I_A.com[:, None]) + p
    Ic = R * _mat(I_A.inertia_com) * R.T
    cx = _mat(skew(np.array(list(c), dtype=object)))
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
    from .spatial_algebra import SpatialInertia

    I_A = _inertia()
    back = SpatialInertia.from_dynamic_parameters(I_A.to_dynamic_parameters())
    sp = _sympy()
    pi = _obj(sp.symbols("pi_0:10", real=True))
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
    from .spatial_algebra import SpatialInertia

    sp = _sympy()
    pi = sp.symbols("pi_0:10", real=True)
    Imat = _mat(SpatialInertia.from_dynamic_parameters(_obj(pi)).matrix()).applyfunc(lambda e: sp.cancel(sp.together(e)))
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


# --------------------------------------------------------------------------
# closed-form dynamics
# --------------------------------------------------------------------------


def symbolic_model(model: Any, *, inertias: Any = None, placements: Any = None, gravity: Any = None) -> Any:
    """A copy of ``model`` whose inertias, joint placements or gravity hold SymPy expressions.

    :class:`~featherdyn.ModelBuilder` accepts floating-point data only; this
    swaps in object arrays afterwards, for the reference algorithms (which are
    dtype-generic) to run on. The tree, joints and frames are unchanged.

    Args:
        model: a built :class:`~featherdyn.Model`.
        inertias: a :class:`~featherdyn.SpatialInertia` with batch shape `(nb,)`.
        placements: a :class:`~featherdyn.PluckerTransform` with batch shape `(nb,)`.
        gravity: `(3,)` gravity in world coordinates.
    """
    from .spatial_algebra import PluckerTransform, SpatialInertia

    nb = model.nbodies
    changes: dict[str, Any] = {}
    if inertias is not None:
        if not isinstance(inertias, SpatialInertia) or inertias.shape != (nb,):
            raise ShapeError(f"inertias: expected a SpatialInertia of batch shape ({nb},)")
        changes["inertias"] = SpatialInertia._wrap(
            inertias.mass.astype(object), inertias.com.astype(object), inertias.inertia_com.astype(object), None
        )
    if placements is not None:
        if not isinstance(placements, PluckerTransform) or placements.shape != (nb,):
            raise ShapeError(f"placements: expected a PluckerTransform of batch shape ({nb},)")
        changes["joint_placements"] = PluckerTransform._wrap(
            placements.rotation.astype(object), placements.translation.astype(object), None, None
        )
    if gravity is not None:
        g = np.asarray(gravity, dtype=object)
        if g.shape != (3,):
            raise ShapeError(f"gravity: expected shape (3,), got {g.shape}")
        changes["gravity"] = g
    return dataclasses.replace(model, **changes)


def _exact(x: Any) -> Any:
    """A float as the rational it prints as (``0.1 → 1/10``); anything else through ``sympify``."""
    sp = _sympy()
    if isinstance(x, (float, np.floating)):
        return sp.Rational(repr(float(x)))
    return sp.sympify(x)


def _placeholders(a: np.ndarray, table: dict[Any, Any]) -> np.ndarray:
    """``a`` as an object array in which every entry other than an integer or a plain symbol is a
    placeholder symbol (see :func:`_exact_model`); ``table`` maps each value to its placeholder."""
    sp = _sympy()
    out = np.empty(a.shape, dtype=object)
    for idx in np.ndindex(*a.shape):
        x = a[idx]
        x = _exact(x.item() if isinstance(x, np.generic) else x)
        if x.is_Integer or x.is_Symbol:
            out[idx] = x
        else:
            if x not in table:
                table[x] = sp.Dummy(f"k{len(table)}")
            out[idx] = table[x]
    return out


def _exact_model(model: Any) -> tuple[Any, dict[Any, Any]]:
    """``model`` with every model constant that is not an integer or a plain symbol (inertias, placements,
    gravity) replaced by a placeholder symbol, and the map from each placeholder to its exact value.

    The reference algorithms multiply model data with the joints' own float
    constants (``1.0`` in ``S``); in SymPy ``1.0 * (m l²/12)`` becomes
    ``0.0833…·m l²``, a rounded coefficient. Placeholders keep every product
    symbolic until the end, where the exact values (floats as the rationals
    they print as) are substituted.
    """
    from .spatial_algebra import PluckerTransform, SpatialInertia

    table: dict[Any, Any] = {}
    I, X = model.inertias, model.joint_placements
    sym = symbolic_model(
        model,
        inertias=SpatialInertia._wrap(_placeholders(I.mass, table), _placeholders(I.com, table),
                                      _placeholders(I.inertia_com, table), None),
        placements=PluckerTransform._wrap(_placeholders(X.rotation, table), _placeholders(X.translation, table),
                                          None, None),
        gravity=_placeholders(np.asarray(model.gravity), table),
    )
    return sym, {d: x for x, d in table.items()}


def _vector(x: Any, n: int, name: str) -> np.ndarray:
    arr = np.asarray(list(x) if not isinstance(x, np.ndarray) else x, dtype=object)
    if arr.shape != (n,):
        raise ShapeError(f"{name}: expected {n} entries, got shape {arr.shape}")
    return arr


def _finish(M: np.ndarray, pretty: bool, values: Mapping[Any, Any]) -> Any:
    red = _Reducer()

    def one(e: Any) -> Any:
        r = red.reduce(e)
        if values:
            r = red.reduce(r.xreplace(dict(values)))
        return red.back(r)

    out = _mat(M).applyfunc(one)
    return out.applyfunc(_pretty) if pretty else out


def mass_matrix(model: Any, q: Any, *, pretty: bool = True) -> Any:
    """The joint-space mass matrix ``M(q)`` as a SymPy matrix, from :func:`featherdyn.crba` on symbols.

    Args:
        model: a featherdyn model (numeric, or from :func:`symbolic_model`).
        q: `(nq,)` symbols (or expressions).
        pretty: collect terms and recombine ``cos(a ± b)`` where that is shorter
            (otherwise the canonical expanded form of :func:`canonical`).

    ::

        M_ij = S_iᵀ ⁱX_j^* I^C_j S_j      (CRBA, chapter §5.3)
    """
    from .api import crba

    sym, values = _exact_model(model)
    return _finish(crba(sym, _vector(q, model.nq, "q")), pretty, values)


def coriolis(model: Any, q: Any, v: Any, *, pretty: bool = True) -> Any:
    """The Coriolis matrix ``C(q, q̇)`` (Pinocchio's factorisation, ``Ṁ − 2C`` skew) from :func:`featherdyn.coriolis_matrix`.

    ``C(q, q̇) q̇ = RNEA(q, q̇, 0) − g(q)``; for the 2R arm it equals the
    Christoffel-symbol matrix of the Lagrangian derivation.
    """
    from .api import coriolis_matrix

    sym, values = _exact_model(model)
    return _finish(coriolis_matrix(sym, _vector(q, model.nq, "q"), _vector(v, model.nv, "v")), pretty, values)


def gravity(model: Any, q: Any, *, pretty: bool = True) -> Any:
    """The generalised gravity ``g(q) = RNEA(q, 0, 0)`` as an `(nv, 1)` SymPy matrix."""
    from .api import generalized_gravity

    sym, values = _exact_model(model)
    return _finish(generalized_gravity(sym, _vector(q, model.nq, "q"))[:, None], pretty, values)


# --------------------------------------------------------------------------
# the chapter's 2R arm
# --------------------------------------------------------------------------


class TwoLinkDynamics(NamedTuple):
    """``M(q) q̈ + C(q, q̇) q̇ + g(q) = τ`` of a planar 2R arm, as SymPy objects."""

    q: tuple[Any, Any]
    v: tuple[Any, Any]
    M: Any
    C: Any
    g: Any
    kinetic: Any
    potential: Any


def two_link_symbols() -> dict[str, Any]:
    """The arm's parameters as positive SymPy symbols ``l1 m1 c1 I1 l2 m2 c2 I2 g``."""
    sp = _sympy()
    return {name: sp.Symbol(name, positive=True) for name in APPENDIX_D}


def two_link_arm(params: Mapping[str, Any] | None = None) -> Any:
    """The chapter's planar 2R arm (appendix D.1) as a featherdyn model.

    Both joints turn about z; the arm moves in the vertical x–y plane with
    gravity ``(0, −g, 0)``. Body frames sit at the joints (Featherstone's
    placement, frame i on joint i's axis): joint 2 at ``(l1, 0, 0)`` in link 1,
    the CoMs at ``(c_i, 0, 0)``, ``I_i`` the moment of inertia about the CoM
    about z (the x and y moments are set to ``I_i`` as well; they do not enter
    planar motion). A frame ``"tip"`` sits at ``(l2, 0, 0)`` on link 2.

    Args:
        params: values for ``l1 m1 c1 I1 l2 m2 c2 I2 g`` (numbers or SymPy
            expressions); missing names are symbols. Numbers only → a float
            model, anything symbolic → a :func:`symbolic_model`.
    """
    from .joints import RevoluteJoint
    from .model import ModelBuilder
    from .spatial_algebra import PluckerTransform, SpatialInertia

    sp = _sympy()
    values: dict[str, Any] = two_link_symbols()
    values.update(params or {})
    numeric = {k: v for k, v in values.items() if isinstance(v, (int, float, np.floating, np.integer))}
    f = {k: float(numeric.get(k, APPENDIX_D[k])) for k in APPENDIX_D}
    b = ModelBuilder("two_link_arm", gravity=(0.0, -f["g"], 0.0))
    z = np.array([0.0, 0.0, 1.0])
    l1 = b.add_body("link1", -1, RevoluteJoint(z), joint_name="joint1",
                    inertia=SpatialInertia(f["m1"], [f["c1"], 0.0, 0.0], f["I1"] * np.eye(3)))
    l2 = b.add_body("link2", l1, RevoluteJoint(z), joint_name="joint2",
                    placement=PluckerTransform(np.eye(3), [f["l1"], 0.0, 0.0]),
                    inertia=SpatialInertia(f["m2"], [f["c2"], 0.0, 0.0], f["I2"] * np.eye(3)))
    b.add_frame("tip", l2, PluckerTransform(np.eye(3), [f["l2"], 0.0, 0.0]))
    model = b.build()
    if len(numeric) == len(values):
        return model
    v = {k: _exact(val) for k, val in values.items()}
    zero = sp.Integer(0)
    eye = np.eye(3, dtype=int).astype(object)
    inertias = SpatialInertia._wrap(
        _obj([v["m1"], v["m2"]]),
        _obj([[v["c1"], zero, zero], [v["c2"], zero, zero]]),
        np.stack([v["I1"] * eye, v["I2"] * eye]),
        None,
    )
    rot = np.stack([eye, eye])
    placements = PluckerTransform._wrap(rot, _obj([[zero, zero, zero], [v["l1"], zero, zero]]), None, None)
    return symbolic_model(model, inertias=inertias, placements=placements, gravity=_obj([zero, -v["g"], zero]))


def lagrangian_two_link(params: Mapping[str, Any] | None = None) -> TwoLinkDynamics:
    """``M``, ``C``, ``g`` of the 2R arm from its Lagrangian, with no spatial algebra (appendix I, exercise 5).

    With ``θ₁ = q₁``, ``θ₂ = q₁ + q₂`` and the CoMs at
    ``p₁ = c₁ (cos θ₁, sin θ₁)``, ``p₂ = l₁ (cos θ₁, sin θ₁) + c₂ (cos θ₂, sin θ₂)``::

        T = ½ Σ_i (m_i |ṗ_i|² + I_i θ̇_i²),      V = g Σ_i m_i y_i
        M = ∂²T/∂q̇²,
        C_kj = Σ_i ½ (∂M_kj/∂q_i + ∂M_ki/∂q_j − ∂M_ij/∂q_k) q̇_i     (Christoffel symbols)
        g = ∂V/∂q

    giving the textbook closed form ``M₁₁ = I₁ + I₂ + m₁c₁² + m₂(l₁² + c₂² + 2 l₁c₂ cos q₂)``,
    ``M₁₂ = I₂ + m₂(c₂² + l₁c₂ cos q₂)``, ``M₂₂ = I₂ + m₂c₂²``.

    Args:
        params: values for some of ``l1 m1 c1 I1 m2 c2 I2 g``; the rest stay symbols.
    """
    sp = _sympy()
    p: dict[str, Any] = two_link_symbols()
    p.update({k: _exact(val) for k, val in (params or {}).items()})
    q1, q2 = sp.symbols("q1 q2", real=True)
    v1, v2 = sp.symbols("v1 v2", real=True)
    q, v = (q1, q2), (v1, v2)
    t = sp.Symbol("t")
    Q = [sp.Function("Q1")(t), sp.Function("Q2")(t)]
    th1, th2 = Q[0], Q[0] + Q[1]
    x1, y1 = p["c1"] * sp.cos(th1), p["c1"] * sp.sin(th1)
    x2 = p["l1"] * sp.cos(th1) + p["c2"] * sp.cos(th2)
    y2 = p["l1"] * sp.sin(th1) + p["c2"] * sp.sin(th2)
    kinetic = (
        p["m1"] * (sp.diff(x1, t) ** 2 + sp.diff(y1, t) ** 2) / 2
        + p["m2"] * (sp.diff(x2, t) ** 2 + sp.diff(y2, t) ** 2) / 2
        + p["I1"] * sp.diff(th1, t) ** 2 / 2
        + p["I2"] * sp.diff(th2, t) ** 2 / 2
    )
    potential = p["g"] * (p["m1"] * y1 + p["m2"] * y2)
    subs = {sp.diff(Q[0], t): v1, sp.diff(Q[1], t): v2}
    kinetic = kinetic.subs(subs).subs({Q[0]: q1, Q[1]: q2})
    potential = potential.subs({Q[0]: q1, Q[1]: q2})
    M = sp.Matrix(2, 2, lambda i, j: sp.diff(kinetic, v[i], v[j])).applyfunc(lambda e: canonical(e))
    C = sp.zeros(2, 2)
    for k, j in itertools.product(range(2), range(2)):
        C[k, j] = sum(
            (sp.diff(M[k, j], q[i]) + sp.diff(M[k, i], q[j]) - sp.diff(M[i, j], q[k])) * v[i] / 2 for i in range(2)
        )
    g = sp.Matrix([sp.diff(potential, qi) for qi in q])
    return TwoLinkDynamics(
        q, v, M.applyfunc(_pretty), canonical(C).applyfunc(_pretty), canonical(g).applyfunc(_pretty),
        canonical(kinetic), canonical(potential),
    )


def check_two_link(params: Mapping[str, Any] | None = None) -> bool:
    """The Lagrangian ``M``, ``C``, ``g`` of the 2R arm equal the spatial-algebra ones, exactly.

    The spatial side is :func:`mass_matrix`, :func:`coriolis` and
    :func:`gravity` of :func:`two_link_arm` (CRBA, the Coriolis-matrix
    algorithm and RNEA run on symbols); the Lagrangian side is
    :func:`lagrangian_two_link`. Returns ``True`` when every entry of the
    three differences reduces to zero.
    """
    lag = lagrangian_two_link(params)
    model = two_link_arm(params)
    M = mass_matrix(model, lag.q, pretty=False)
    C = coriolis(model, lag.q, lag.v, pretty=False)
    g = gravity(model, lag.q, pretty=False)
    return is_zero(M - lag.M) and is_zero(C - lag.C) and is_zero(g - lag.g)
