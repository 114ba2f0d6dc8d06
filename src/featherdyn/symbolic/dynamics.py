"""Closed-form dynamics on symbols, and the chapter's 2R arm derived twice, for :mod:`featherdyn.symbolic`.

:func:`mass_matrix`, :func:`coriolis` and :func:`gravity` run the reference
algorithms on object arrays of SymPy symbols and reduce the result exactly;
:func:`lagrangian_two_link` derives the appendix-D arm's ``M``, ``C``, ``g``
from its Lagrangian with no spatial algebra, and :func:`check_two_link` proves
the two equal::

    M(q) q̈ + C(q, q̇) q̇ + g(q) = τ

Sources: chapter §5.3, appendix D and appendix I (exercise 5); RBDA (2008) §6.2.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

from ..api import coriolis_matrix, crba, generalized_gravity
from ..errors import ShapeError
from ..joints import RevoluteJoint
from ..model import Model, ModelBuilder
from ..spatial import PluckerTransform, SpatialInertia
from .reduce import (
    Reducer,
    SymExpr,
    SymMatrix,
    canonical,
    import_sympy,
    is_zero,
    object_array,
    pretty_form,
    sympy_matrix,
)

#: the chapter's appendix-D arm (D.1): lengths, masses, CoM distances from the joint, I_zz about the CoM
APPENDIX_D: dict[str, float] = {
    "l1": 1.0, "m1": 3.0, "c1": 0.5, "I1": 0.25,
    "l2": 0.8, "m2": 2.0, "c2": 0.4, "I2": 0.11,
    "g": 9.81,
}


def symbolic_model(
    model: Model,
    *,
    inertias: SpatialInertia | None = None,
    placements: PluckerTransform | None = None,
    gravity: Sequence[SymExpr] | np.ndarray | None = None,
) -> Model:
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


def _exact(x: object) -> SymExpr:
    """A float as the rational it prints as (``0.1 → 1/10``); anything else through ``sympify``."""
    sp = import_sympy()
    if isinstance(x, (float, np.floating)):
        return sp.Rational(repr(float(x)))
    return sp.sympify(x)


def _placeholders(a: np.ndarray, table: dict[SymExpr, SymExpr]) -> np.ndarray:
    """``a`` as an object array in which every entry other than an integer or a plain symbol is a
    placeholder symbol (see :func:`_exact_model`); ``table`` maps each value to its placeholder."""
    sp = import_sympy()
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


def _exact_model(model: Model) -> tuple[Model, dict[SymExpr, SymExpr]]:
    """``model`` with every model constant that is not an integer or a plain symbol (inertias, placements,
    gravity) replaced by a placeholder symbol, and the map from each placeholder to its exact value.

    The reference algorithms multiply model data with the joints' own float
    constants (``1.0`` in ``S``); in SymPy ``1.0 * (m l²/12)`` becomes
    ``0.0833…·m l²``, a rounded coefficient. Placeholders keep every product
    symbolic until the end, where the exact values (floats as the rationals
    they print as) are substituted.
    """
    table: dict[SymExpr, SymExpr] = {}
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


def _vector(x: Sequence[SymExpr] | np.ndarray, n: int, name: str) -> np.ndarray:
    arr = np.asarray(list(x) if not isinstance(x, np.ndarray) else x, dtype=object)
    if arr.shape != (n,):
        raise ShapeError(f"{name}: expected {n} entries, got shape {arr.shape}")
    return arr


def _finish(M: np.ndarray, pretty: bool, values: Mapping[SymExpr, SymExpr]) -> SymMatrix:
    red = Reducer()

    def one(e: SymExpr) -> SymExpr:
        r = red.reduce(e)
        if values:
            r = red.reduce(r.xreplace(dict(values)))
        return red.back(r)

    out = sympy_matrix(M).applyfunc(one)
    return out.applyfunc(pretty_form) if pretty else out


def mass_matrix(model: Model, q: Sequence[SymExpr] | np.ndarray, *, pretty: bool = True) -> SymMatrix:
    """The joint-space mass matrix ``M(q)`` as a SymPy matrix, from :func:`featherdyn.crba` on symbols.

    Args:
        model: a featherdyn model (numeric, or from :func:`symbolic_model`).
        q: `(nq,)` symbols (or expressions).
        pretty: collect terms and recombine ``cos(a ± b)`` where that is shorter
            (otherwise the canonical expanded form of :func:`canonical`).

    ::

        M_ij = S_iᵀ ⁱX_j^* I^C_j S_j      (CRBA, chapter §5.3)
    """
    sym, values = _exact_model(model)
    return _finish(crba(sym, _vector(q, model.nq, "q")), pretty, values)


def coriolis(
    model: Model, q: Sequence[SymExpr] | np.ndarray, v: Sequence[SymExpr] | np.ndarray, *, pretty: bool = True
) -> SymMatrix:
    """The Coriolis matrix ``C(q, q̇)`` (Pinocchio's factorisation, ``Ṁ − 2C`` skew) from :func:`featherdyn.coriolis_matrix`.

    ``C(q, q̇) q̇ = RNEA(q, q̇, 0) − g(q)``; for the 2R arm it equals the
    Christoffel-symbol matrix of the Lagrangian derivation.
    """
    sym, values = _exact_model(model)
    return _finish(coriolis_matrix(sym, _vector(q, model.nq, "q"), _vector(v, model.nv, "v")), pretty, values)


def gravity(model: Model, q: Sequence[SymExpr] | np.ndarray, *, pretty: bool = True) -> SymMatrix:
    """The generalised gravity ``g(q) = RNEA(q, 0, 0)`` as an `(nv, 1)` SymPy matrix."""
    sym, values = _exact_model(model)
    return _finish(generalized_gravity(sym, _vector(q, model.nq, "q"))[:, None], pretty, values)


# --------------------------------------------------------------------------
# the chapter's 2R arm
# --------------------------------------------------------------------------


class TwoLinkDynamics(NamedTuple):
    """``M(q) q̈ + C(q, q̇) q̇ + g(q) = τ`` of a planar 2R arm, as SymPy objects."""

    q: tuple[SymExpr, SymExpr]
    v: tuple[SymExpr, SymExpr]
    M: SymMatrix
    C: SymMatrix
    g: SymMatrix
    kinetic: SymExpr
    potential: SymExpr


def two_link_symbols() -> dict[str, SymExpr]:
    """The arm's parameters as positive SymPy symbols ``l1 m1 c1 I1 l2 m2 c2 I2 g``."""
    sp = import_sympy()
    return {name: sp.Symbol(name, positive=True) for name in APPENDIX_D}


def two_link_arm(params: Mapping[str, float | SymExpr] | None = None) -> Model:
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
    sp = import_sympy()
    values: dict[str, SymExpr] = two_link_symbols()
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
        object_array([v["m1"], v["m2"]]),
        object_array([[v["c1"], zero, zero], [v["c2"], zero, zero]]),
        np.stack([v["I1"] * eye, v["I2"] * eye]),
        None,
    )
    rot = np.stack([eye, eye])
    placements = PluckerTransform._wrap(rot, object_array([[zero, zero, zero], [v["l1"], zero, zero]]), None, None)
    return symbolic_model(model, inertias=inertias, placements=placements, gravity=object_array([zero, -v["g"], zero]))


def lagrangian_two_link(params: Mapping[str, float | SymExpr] | None = None) -> TwoLinkDynamics:
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
    sp = import_sympy()
    p: dict[str, SymExpr] = two_link_symbols()
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
        q, v, M.applyfunc(pretty_form), canonical(C).applyfunc(pretty_form), canonical(g).applyfunc(pretty_form),
        canonical(kinetic), canonical(potential),
    )


def check_two_link(params: Mapping[str, float | SymExpr] | None = None) -> bool:
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
