"""The second-order derivatives ``fd.rnea_second_derivatives`` and ``fd.aba_second_derivatives`` (issue 30).

Against central differences of the analytical first order (``fd.rnea_derivatives``, ``fd.aba_derivatives``,
``fd.crba``) along ``fd.integrate``'s tangent, ``q̇`` and ``τ``; against complex steps through the core's complex
RNEA (``featherdyn.core.rnea_complex``: exact to rounding where τ's form allows it); the symmetries, and on
floating bases the Lie bracket the asymmetry must equal; core = reference; SymPy on a 2R arm. Their front ends
(batch, float32, Dask, fd.compile), as every declared algorithm's: ``test_declared_front_ends.py``.
Pinocchio 4.1's Python does not bind ``computeRNEASecondOrderDerivatives``: no comparison with it here.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from _models import TREES, library_robot, random_axis, random_inertia, random_placement, random_q, tree

import featherdyn as fd
import featherdyn.core as fdcore
from featherdyn.algorithms import crba as crba_reference
from featherdyn.algorithms import derivatives as first_reference
from featherdyn.algorithms import second_order as reference
from featherdyn.spatial import crm

ROBOTS = [("two_link_arm", False), ("panda", False), ("ur5_robot", False), ("solo12", True),
          ("talos_full_v2", True)]
FIXED = [("two_link_arm", False), ("panda", False), ("ur5_robot", False)]
#: random trees with spherical and planar joints, fixed and floating (tests/_models.py)
TREE_CASES = [("fixed_branch_mixed", False), ("planar_root_branch", False), ("free_branch", True)]


def _robot(name: str, floating: bool) -> fd.Model:
    if name in {t.name for t in TREES}:
        return tree(name)
    model = fd.load_robot(name) if name == "two_link_arm" else library_robot(name, floating)
    assert model is not None
    return model


def _state(model: fd.Model, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng)
    return q, rng.normal(size=model.nv), rng.normal(size=model.nv), rng.normal(size=(model.nbodies, 6))


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


def _central(f: Callable[[float], tuple[np.ndarray, ...]], eps: float = 1e-6) -> tuple[np.ndarray, ...]:
    """``(f(ε) − f(−ε)) / 2ε`` of each of f's arrays."""
    plus, minus = f(eps), f(-eps)
    return tuple((p - m) / (2 * eps) for p, m in zip(plus, minus, strict=True))


def _unit(n: int, k: int, scale: float = 1.0) -> np.ndarray:
    e = np.zeros(n)
    e[k] = scale
    return e


@pytest.mark.parametrize(("name", "floating"), ROBOTS + TREE_CASES)
def test_rnea_against_central_differences_of_the_first_order(name: str, floating: bool) -> None:
    model = _robot(name, floating)
    q, v, a, fx = _state(model, 1)
    s = fd.rnea_second_derivatives(model, q, v, a, fx)
    assert isinstance(s, fd.RneaSecondDerivatives) and all(x.shape == (model.nv,) * 3 for x in s)
    d2q, d2v, dqdv, dM = s  # a tuple as well
    assert d2q is s.d2tau_dq2 and dM is s.dM_dq
    nv = model.nv
    for k in range(nv):
        # along q ⊕ ε e_k: ∂τ/∂q, ∂τ/∂q̇ and M
        fq, fv, fm = _central(lambda e, k=k: fd.rnea_derivatives(model, fd.integrate(model, q, _unit(nv, k, e)), v, a,
                                                                 fx))
        assert _rel(d2q[:, :, k], fq) < 1e-6, (k, _rel(d2q[:, :, k], fq))
        assert _rel(dqdv[:, k, :], fv) < 1e-6, k  # ∂²τ_i/∂q_k∂q̇_j
        assert _rel(dM[:, :, k], fm) < 1e-6, k
        assert _rel(dM[:, :, k], _central(lambda e, k=k: (fd.crba(model, fd.integrate(model, q, _unit(nv, k, e))),))[0]) < 1e-6
        # along q̇ + ε e_k: ∂τ/∂q and ∂τ/∂q̇
        gq, gv, _ = _central(lambda e, k=k: fd.rnea_derivatives(model, q, v + _unit(nv, k, e), a, fx))
        assert _rel(dqdv[:, :, k], gq) < 1e-6, k
        assert _rel(d2v[:, :, k], gv) < 1e-6, k
    assert np.abs(d2q).max() > 1.0 and np.abs(dqdv).max() > 1e-3  # not trivially zero


@pytest.mark.parametrize(("name", "floating"), ROBOTS + TREE_CASES)
def test_aba_against_central_differences_of_the_first_order(name: str, floating: bool) -> None:
    model = _robot(name, floating)
    q, v, tau, fx = _state(model, 2)
    s = fd.aba_second_derivatives(model, q, v, tau, fx)
    assert isinstance(s, fd.AbaSecondDerivatives) and all(x.shape == (model.nv,) * 3 for x in s)
    nv = model.nv
    scale = max(1.0, max(np.abs(x).max() for x in s))

    def close(x: np.ndarray, y: np.ndarray) -> bool:
        return float(np.abs(x - y).max()) < 1e-6 * scale

    # ε = 1e-4: talos' M⁻¹ reaches 1.2e5 (its light finger links), and the differences of the first order lose
    # |M⁻¹| · 1e-16 / ε to rounding (measured: the error falls from 5e-2 at ε = 1e-6 to 5e-4 at 1e-4, scale 1.3e4)
    eps = 1e-4

    for k in range(nv):
        fq, fv, fminv = _central(lambda e, k=k: fd.aba_derivatives(model, fd.integrate(model, q, _unit(nv, k, e)), v,
                                                                   tau, fx), eps)
        assert close(s.d2ddq_dq2[:, :, k], fq), k
        assert close(s.d2ddq_dqdv[:, k, :], fv), k
        assert close(s.d2ddq_dqdtau[:, k, :], fminv), k  # ∂(M⁻¹)_ij/∂q_k
        gq, gv, _ = _central(lambda e, k=k: fd.aba_derivatives(model, q, v + _unit(nv, k, e), tau, fx), eps)
        assert close(s.d2ddq_dqdv[:, :, k], gq), k
        assert close(s.d2ddq_dv2[:, :, k], gv), k
        tq, _, _ = _central(lambda e, k=k: fd.aba_derivatives(model, q, v, tau + _unit(nv, k, e), fx), eps)
        assert close(s.d2ddq_dqdtau[:, :, k], tq), k


def _coordinate_columns(model: fd.Model) -> list[tuple[int, int]]:
    """``(v column, q index)`` of the revolute and prismatic joints: there ``q ⊕ ε e_k`` is ``q + ε e_iq``."""
    return [(model.idx_v[i], model.idx_q[i]) for i, j in enumerate(model.joints)
            if isinstance(j, (fd.joints.RevoluteJoint, fd.joints.PrismaticJoint))]


@pytest.mark.parametrize(("name", "floating"), [*FIXED, ("solo12", True)])
def test_complex_step_through_the_core(name: str, floating: bool) -> None:
    """τ is linear in q̈ and quadratic in q̇: a complex step in q (or q̇) of τ, or of its exact q̇-differences, is
    exact to rounding (h = 1e-30)."""
    model = _robot(name, floating)
    q, v, a, _ = _state(model, 3)
    s = fd.rnea_second_derivatives(model, q, v, a)
    nv, h = model.nv, 1e-30
    cols = _coordinate_columns(model)
    assert len(cols) >= 2

    def tau(qc: np.ndarray, vc: np.ndarray, ac: np.ndarray, gravity: bool = True) -> np.ndarray:
        return fdcore.rnea_complex(model, qc, vc, ac, gravity=gravity)

    worst = 0.0
    for k, iq in cols:
        qk = q + 1j * h * _unit(model.nq, iq)
        for j in range(nv):
            # ∂M e_j/∂q_k = Im τ(q + i h e_k, 0, e_j) / h  (no gravity)
            dm = tau(qk, np.zeros(nv), _unit(nv, j), gravity=False).imag / h
            # ∂²τ/∂q_k∂q̇_j: the q̇-difference ±e_j of τ is exactly 2 ∂τ/∂q̇_j
            dqv = (tau(qk, v + _unit(nv, j), a) - tau(qk, v - _unit(nv, j), a)).imag / (2 * h)
            worst = max(worst, _rel(s.dM_dq[:, j, k], dm), _rel(s.d2tau_dqdv[:, k, j], dqv))
    for k in range(nv):  # ∂²τ/∂q̇_j∂q̇_k on every column (q stays real)
        vk = v + 1j * h * _unit(nv, k)
        for j in range(nv):
            dvv = (tau(q.astype(complex), vk + _unit(nv, j), a) - tau(q.astype(complex), vk - _unit(nv, j), a)).imag / (2 * h)
            worst = max(worst, _rel(s.d2tau_dv2[:, j, k], dvv))
    assert worst < 1e-11, worst


@pytest.mark.parametrize(("name", "floating"), ROBOTS)
def test_symmetries(name: str, floating: bool) -> None:
    model = _robot(name, floating)
    q, v, a, fx = _state(model, 4)
    s = fd.rnea_second_derivatives(model, q, v, a, fx)
    assert _rel(s.d2tau_dv2, s.d2tau_dv2.swapaxes(1, 2)) < 1e-12
    assert _rel(s.dM_dq, s.dM_dq.swapaxes(0, 1)) < 1e-12  # M symmetric
    # ∂²τ/∂q̇² does not depend on q̇ or q̈ (τ quadratic in q̇), nor on gravity or the external forces
    other = fd.rnea_second_derivatives(model, q, 2 * v + 1, -a, gravity=False)
    assert _rel(other.d2tau_dv2, s.d2tau_dv2) < 1e-12 and _rel(other.dM_dq, s.dM_dq) < 1e-12
    a2 = fd.aba_second_derivatives(model, q, v, a, fx)
    assert _rel(a2.d2ddq_dv2, a2.d2ddq_dv2.swapaxes(1, 2)) < 1e-12
    if not floating:  # revolute and prismatic coordinates: the second derivatives in q commute
        assert _rel(s.d2tau_dq2, s.d2tau_dq2.swapaxes(1, 2)) < 1e-12
        assert _rel(a2.d2ddq_dq2, a2.d2ddq_dq2.swapaxes(1, 2)) < 1e-11


def _bracket_part(model: fd.Model, dtau_dq: np.ndarray) -> np.ndarray:
    """``([X_k, X_j] τ)_i`` at ``[i, j, k]``: for two columns of one joint ``Σ_c ∂τ_i/∂q_c S_cᵀ (S_k × S_j)`` (motion
    cross product in the joint's body; the joint's S has orthonormal columns), zero otherwise."""
    out = np.zeros((model.nv,) * 3)
    for b, joint in enumerate(model.joints):
        S, o, n = joint.S, model.idx_v[b], model.nvs[b]
        for j in range(n):
            for k in range(n):
                out[:, o + j, o + k] = dtau_dq[:, o:o + n] @ (S.T @ (crm(S[:, k]) @ S[:, j]))
    return out


@pytest.mark.parametrize("name", ["solo12", *[t.name for t in TREES]])
def test_bracket_on_floating_bases(name: str) -> None:
    """d2tau_dq2[i, j, k] − d2tau_dq2[i, k, j] = ([X_k, X_j] τ)_i: the tangent fields of a free-flyer, spherical
    or planar joint do not commute; revolute and prismatic ones do."""
    model = _robot(name, True) if name == "solo12" else tree(name)
    rng = np.random.default_rng(5)
    q = random_q(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    s = fd.rnea_second_derivatives(model, q, v, a)
    dtau_dq = fd.rnea_derivatives(model, q, v, a)[0]
    antisymmetric = s.d2tau_dq2 - s.d2tau_dq2.swapaxes(1, 2)
    assert _rel(antisymmetric, _bracket_part(model, dtau_dq)) < 1e-12
    kinds = {type(j).__name__ for j in model.joints}
    if kinds & {"FreeFlyerJoint", "SphericalJoint"}:
        assert np.abs(antisymmetric).max() > 1e-2 * np.abs(s.d2tau_dq2).max()  # really not symmetric


@pytest.mark.parametrize("name", [t.name for t in TREES])
def test_core_equals_reference(name: str) -> None:
    model = tree(name)
    rng = np.random.default_rng(6)
    q = random_q(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    fx = rng.normal(size=(model.nbodies, 6))
    for kwargs in ({}, {"gravity": False}):
        core = fd.rnea_second_derivatives(model, q, v, a, fx, **kwargs)
        ref = fd.rnea_second_derivatives(model, q, v, a, fx, backend="reference", **kwargs)
        assert max(_rel(x, y) for x, y in zip(core, ref, strict=True)) < 1e-11
        core = fd.aba_second_derivatives(model, q, v, a, fx, **kwargs)
        ref = fd.aba_second_derivatives(model, q, v, a, fx, backend="reference", **kwargs)
        assert max(_rel(x, y) for x, y in zip(core, ref, strict=True)) < 1e-10
    # the external forces change the result (they are not dropped on the way)
    with_forces = fd.rnea_second_derivatives(model, q, v, a, fx).d2tau_dq2
    assert _rel(fd.rnea_second_derivatives(model, q, v, a).d2tau_dq2, with_forces) > 1e-6


def _branched_model(parents: list[int], seed: int) -> fd.Model:
    """A tree of revolute, spherical and prismatic joints hung from ``parents`` (only ``parent[i] < i``)."""
    rng = np.random.default_rng(seed)
    kinds = [fd.RevoluteJoint, fd.SphericalJoint, fd.PrismaticJoint]
    b = fd.ModelBuilder("branched")
    for i, p in enumerate(parents):
        kind = kinds[i % 3]
        joint = kind() if kind is fd.SphericalJoint else kind(random_axis(rng))
        b.add_body(f"b{i}", p, joint, placement=random_placement(rng), inertia=random_inertia(rng))
    return b.build()


@pytest.mark.parametrize("parents", [[-1, 0, 1, 1, 0, 4, 4, 6], [-1, 0, 0, 1, 2, 1, 3]],
                         ids=["depth-first", "not depth-first"])
def test_aba_core_equals_reference_on_branched_trees(parents: list[int]) -> None:
    """The core solves only the entries of ``−M⁻¹ T`` that the tree lets be nonzero in its first sweep (where the
    numbering is depth-first; every entry otherwise): on trees with several branches, numbered depth-first and
    not (``d`` after its uncle), it equals the reference, which solves densely."""
    model = _branched_model(parents, len(parents))
    rng = np.random.default_rng(9)
    q = random_q(model, rng)
    v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
    core = fd.aba_second_derivatives(model, q, v, tau)
    ref = fd.aba_second_derivatives(model, q, v, tau, backend="reference")
    assert max(_rel(x, y) for x, y in zip(core, ref, strict=True)) < 1e-10
    assert min(np.abs(x).max() for x in core) > 1e-3  # none of the four is trivially zero


def test_large_states_are_computed_and_overflow_is_an_error() -> None:
    """The core vouches for its tensors' finiteness while its factors stay under bounds (velocity components
    under 2^170 ≈ 1.5e51); past them it scans the tensors: a large but finite result is returned, equal to the
    reference, and an overflowing one (q̇ ~ 1e160, q̇² beyond float64) is an error naming the overflow, in one
    state and in the row of a batch."""
    model = fd.load_robot("panda")
    rng = np.random.default_rng(8)
    q, a = fd.random_configuration(model, rng), rng.normal(size=model.nv)
    v = rng.normal(size=model.nv) * 1e60
    core = fd.rnea_second_derivatives(model, q, v, a)
    ref = fd.rnea_second_derivatives(model, q, v, a, backend="reference")
    assert np.abs(core.d2tau_dq2).max() > 1e110  # q̇² terms: past the bounds, still finite
    for x, y in zip(core, ref, strict=True):
        assert np.isfinite(x).all()
        assert np.abs(x - y).max() <= 1e-11 * np.abs(y).max()
    huge = v * 1e100
    with pytest.raises(fd.errors.NonFiniteError, match="overflowed"):
        fd.rnea_second_derivatives(model, q, huge, a)
    with pytest.raises(fd.errors.NonFiniteError, match=r"\(state \(1,\) of the batch\): the result overflowed"):
        fd.rnea_second_derivatives(model, np.stack([q, q]), np.stack([v, huge]), a)


def test_batch_equals_loop() -> None:
    model = _robot("solo12", True)
    rng = np.random.default_rng(7)
    Q = fd.random_configuration(model, rng, size=(4,))
    V, T = rng.normal(size=(4, model.nv)), rng.normal(size=model.nv)  # τ broadcast
    batch = fd.aba_second_derivatives(model, Q, V, T)
    for n in range(4):
        one = fd.aba_second_derivatives(model, Q[n], V[n], T)
        assert all(np.array_equal(x[n], y) for x, y in zip(batch, one, strict=True))
    # out=: the core's kernel writes into given arrays, the same numbers bit for bit; fd.* too, and returns the
    # record of them
    outs = tuple(np.full((4,) + (model.nv,) * 3, np.nan) for _ in range(4))
    assert fdcore.aba_second_derivatives(model, Q, V, np.broadcast_to(T, V.shape), None, out=outs) is outs
    assert all(np.array_equal(x, y) for x, y in zip(outs, batch, strict=True))
    outs2 = tuple(np.full_like(x, np.nan) for x in outs)
    r = fd.aba_second_derivatives(model, Q, V, T, out=outs2)
    assert type(r) is fd.AbaSecondDerivatives and all(x is y for x, y in zip(r, outs2, strict=True))
    assert all(np.array_equal(x, y) for x, y in zip(outs2, batch, strict=True))
    ref = fd.rnea_second_derivatives(model, Q[:2], V[:2], T, backend="reference")  # the reference batches too
    core = fd.rnea_second_derivatives(model, Q[:2], V[:2], T)
    assert max(_rel(x, y) for x, y in zip(core, ref, strict=True)) < 1e-11


def test_sympy_two_link_arm() -> None:
    """The reference on SymPy symbols equals ``sympy.diff`` of the symbolic first order (2R arm)."""
    sympy = pytest.importorskip("sympy")
    model = fd.load_robot("two_link_arm")
    qs, vs = sympy.symbols("q1 q2"), sympy.symbols("v1 v2")
    q = np.array(qs, dtype=object)
    v = np.array(vs, dtype=object)
    a = np.array([sympy.Rational(1, 3), sympy.Rational(-2, 5)], dtype=object)
    dq, dv = first_reference.rnea_partials(model, q, v, a)
    M = crba_reference.crba(model, q)
    d2q, d2v, dqdv, dM = reference.rnea_second_derivatives(model, q, v, a)
    point = {qs[0]: 0.3, qs[1]: -1.1, vs[0]: 0.7, vs[1]: 0.2}

    def value(x: object) -> float:
        return float(sympy.sympify(x).subs(point))

    worst = 0.0
    for i in range(2):
        for j in range(2):
            for k in range(2):
                worst = max(worst, abs(value(d2q[i, j, k] - sympy.diff(dq[i, j], qs[k]))),
                            abs(value(d2v[i, j, k] - sympy.diff(dv[i, j], vs[k]))),
                            abs(value(dqdv[i, j, k] - sympy.diff(dq[i, j], vs[k]))),
                            abs(value(dM[i, j, k] - sympy.diff(M[i, j], qs[k]))))
    assert worst < 1e-12
    # and the symbolic numbers are the core's
    num = fd.rnea_second_derivatives(model, np.array([0.3, -1.1]), np.array([0.7, 0.2]), np.array([1 / 3, -0.4]))
    sym = np.array([[[value(x) for x in row] for row in m] for m in d2q], dtype=float)
    assert _rel(num.d2tau_dq2, sym) < 1e-12
    assert np.abs(sym).max() > 0.1
