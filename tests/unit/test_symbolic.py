"""featherdyn.symbolic: every proof returns True, false identities are caught, and the 2R closed form is right.

The proofs are exact (polynomial reduction, see the module docstring); the
closed-form 2R dynamics are checked numerically against the float
algorithms (fd.crba, fd.rnea, fd.coriolis_matrix) at several states.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import MissingDependencyError

sp = pytest.importorskip("sympy")
from featherdyn import symbolic  # noqa: E402  (after the importorskip)

ROTATION_PROOFS = [
    symbolic.prove_plucker_determinant,
    symbolic.prove_pure_rotation_orthogonal,
    symbolic.prove_transform_inverse,
    symbolic.prove_power_invariance,
    symbolic.prove_cross_equivariance,
    symbolic.prove_parallel_axis,
    symbolic.prove_kinetic_energy_invariance,
]
PLAIN_PROOFS = [
    symbolic.prove_jacobi_identity,
    symbolic.prove_cross_antisymmetry,
    symbolic.prove_crf_is_minus_crm_transpose,
    symbolic.prove_force_cross_duality,
    symbolic.prove_gyroscopic_identity,
    symbolic.prove_dynamic_parameters_round_trip,
    symbolic.prove_inertia_linear_in_dynamic_parameters,
]


@pytest.mark.parametrize("parametrization", symbolic.PARAMETRIZATIONS)
@pytest.mark.parametrize("proof", ROTATION_PROOFS, ids=lambda f: f.__name__)
def test_rotation_proofs(proof, parametrization):
    assert proof(parametrization) is True


@pytest.mark.parametrize("proof", PLAIN_PROOFS, ids=lambda f: f.__name__)
def test_plain_proofs(proof):
    assert proof() is True


def test_every_proof_is_listed():
    names = {n for n in symbolic.__all__ if n.startswith("prove_")}
    assert names == {f.__name__ for f in ROTATION_PROOFS + PLAIN_PROOFS}


def test_unknown_parametrization():
    with pytest.raises(ValueError, match="parametrization"):
        symbolic.prove_plucker_determinant("euler")


# --------------------------------------------------------------------------
# the reduction can say "no": false identities are not proved
# --------------------------------------------------------------------------


def test_is_zero_rejects_nonzero():
    q, x = sp.symbols("q x", real=True)
    assert symbolic.is_zero(sp.sin(q) ** 2 + sp.cos(q) ** 2 - 1)
    assert not symbolic.is_zero(sp.sin(q) ** 2 - sp.cos(q) ** 2 - 1)
    assert symbolic.is_zero(sp.cos(2 * q) - 2 * sp.cos(q) ** 2 + 1)  # compound arguments are expanded
    assert not symbolic.is_zero(x * sp.sin(q))
    assert symbolic.is_zero(sp.Float(0.5) * x - x / 2)  # floats become the rationals they print as


def test_unit_quaternion_constraint_is_needed():
    x, y, z, w = sp.symbols("x y z w", real=True)
    expr = x**2 + y**2 + z**2 + w**2 - 1
    assert symbolic.is_zero(expr, unit_quaternion=(x, y, z, w))
    assert not symbolic.is_zero(expr)


def test_chapter_f2_sign_is_not_an_identity():
    """Appendix F.2 prints v ×* (I v) = −I(v × v) + (v×)ᵀ I v; only the opposite sign holds."""
    v = np.array(sp.symbols("v0:6", real=True), dtype=object)
    I = fd.SpatialInertia(sp.Symbol("m", positive=True), np.array(sp.symbols("cx cy cz", real=True), dtype=object),
                          np.diag(np.array(sp.symbols("a b c", positive=True), dtype=object)))
    Iv = I.matrix() @ v
    printed = -I.matrix() @ (fd.crm(v) @ v) + fd.crm(v).T @ Iv
    assert not symbolic.is_zero(fd.crf(v) @ Iv - printed)
    assert symbolic.is_zero(fd.crf(v) @ Iv + fd.crm(v).T @ Iv)


def test_power_with_the_inverse_force_transform_is_not_invariant():
    """The troubleshooting table's 'force uses actInv' fails symbolically too."""
    th = sp.Symbol("theta", real=True)
    R = np.array([[sp.cos(th), -sp.sin(th), 0], [sp.sin(th), sp.cos(th), 0], [0, 0, 1]], dtype=object)
    X = fd.PluckerTransform(R, np.array(sp.symbols("px py pz", real=True), dtype=object), validate=False)
    m = fd.SpatialMotion.from_vector(np.array(sp.symbols("m0:6", real=True), dtype=object))
    f = fd.SpatialForce.from_vector(np.array(sp.symbols("f0:6", real=True), dtype=object))
    assert symbolic.is_zero(X.apply(m).dot(X.apply(f)) - m.dot(f))
    assert not symbolic.is_zero(X.apply(m).dot(X.apply_inverse(f)) - m.dot(f))


def test_general_transform_is_not_orthogonal():
    """Exercise 2: only the pure rotation is orthogonal."""
    p = np.array(sp.symbols("px py pz", real=True), dtype=object)
    X = sp.Matrix(fd.PluckerTransform(np.eye(3, dtype=int).astype(object), p, validate=False).matrix().tolist())
    assert not symbolic.is_zero(X * X.T - sp.eye(6))


# --------------------------------------------------------------------------
# closed-form dynamics
# --------------------------------------------------------------------------

STATES = [
    (np.array([0.0, 0.0]), np.array([0.0, 0.0]), np.array([0.0, 0.0])),
    (np.deg2rad([30.0, 45.0]), np.array([2.0, -1.0]), np.array([0.5, -0.3])),  # appendix D
    (np.array([-1.3, 2.2]), np.array([0.7, 1.9]), np.array([-2.0, 0.4])),
    (np.array([2.9, -0.4]), np.array([-3.0, 0.2]), np.array([1.1, 1.5])),
]


@pytest.fixture(scope="module")
def closed_form():
    """The 2R arm's M, C, g with symbolic parameters, from the spatial algebra, lambdified."""
    params = symbolic.two_link_symbols()
    arm = symbolic.two_link_arm()
    q = sp.symbols("q1 q2", real=True)
    v = sp.symbols("v1 v2", real=True)
    M, C, g = symbolic.mass_matrix(arm, q), symbolic.coriolis(arm, q, v), symbolic.gravity(arm, q)
    args = [*q, *v, *params.values()]
    return {name: sp.lambdify(args, expr, "numpy") for name, expr in (("M", M), ("C", C), ("g", g))}, params


@pytest.mark.parametrize("state", range(len(STATES)))
def test_two_link_closed_form_matches_float_algorithms(closed_form, state):
    fns, params = closed_form
    numbers = dict(symbolic.APPENDIX_D, l1=1.3, c2=0.35, I2=0.07)
    model = symbolic.two_link_arm(numbers)
    q, v, a = STATES[state]
    args = [*q, *v, *(numbers[k] for k in params)]
    M = np.array(fns["M"](*args), dtype=float)
    C = np.array(fns["C"](*args), dtype=float)
    g = np.array(fns["g"](*args), dtype=float)[:, 0]
    np.testing.assert_allclose(M, fd.crba(model, q), atol=1e-12)
    np.testing.assert_allclose(C, fd.coriolis_matrix(model, q, v), atol=1e-12)
    np.testing.assert_allclose(g, fd.generalized_gravity(model, q), atol=1e-12)
    np.testing.assert_allclose(M @ a + C @ v + g, fd.rnea(model, q, v, a), atol=1e-12)


def test_two_link_lagrangian_equals_spatial_algebra():
    assert symbolic.check_two_link() is True
    assert symbolic.check_two_link(symbolic.APPENDIX_D) is True


def test_two_link_textbook_form():
    lag = symbolic.lagrangian_two_link()
    p = symbolic.two_link_symbols()
    q2 = lag.q[1]
    M11 = p["I1"] + p["I2"] + p["m1"] * p["c1"] ** 2 + p["m2"] * (p["l1"] ** 2 + p["c2"] ** 2 + 2 * p["l1"] * p["c2"] * sp.cos(q2))
    assert symbolic.is_zero(lag.M[0, 0] - M11)
    assert symbolic.is_zero(lag.M[0, 1] - p["I2"] - p["m2"] * (p["c2"] ** 2 + p["l1"] * p["c2"] * sp.cos(q2)))
    assert symbolic.is_zero(lag.M[1, 1] - p["I2"] - p["m2"] * p["c2"] ** 2)


def test_appendix_d_torques_exact():
    """τ of appendix D from the closed form (35.4452, 4.6628 N·m), equal to fd.rnea."""
    lag = symbolic.lagrangian_two_link(symbolic.APPENDIX_D)
    q, v, a = STATES[1]
    subs = {lag.q[0]: q[0], lag.q[1]: q[1], lag.v[0]: v[0], lag.v[1]: v[1]}
    tau = np.array((lag.M.subs(subs) * sp.Matrix(a) + lag.C.subs(subs) * sp.Matrix(v) + lag.g.subs(subs)).evalf(),
                   dtype=float)[:, 0]
    np.testing.assert_allclose(tau, [35.4452, 4.6628], atol=5e-5)
    np.testing.assert_allclose(tau, fd.rnea(symbolic.two_link_arm(symbolic.APPENDIX_D), q, v, a), atol=1e-12)


def test_mass_matrix_of_a_float_model_is_exact():
    """Float model data enter as the rationals they print as: no 0.43000000000000005."""
    model = symbolic.two_link_arm(symbolic.APPENDIX_D)
    M = symbolic.mass_matrix(model, sp.symbols("q1 q2", real=True))
    assert M[1, 1] == sp.Rational(43, 100)


def test_mass_matrix_of_a_3d_model(pin):
    """A spatial 3-joint chain with numeric data: M(q) symbolic, evaluated, equals Pinocchio's crba."""
    from featherdyn.verify.bridge import pinocchio_model_from

    b = fd.ModelBuilder("3dof")
    I = fd.SpatialInertia(1.5, [0.1, 0.0, 0.2], np.diag([0.02, 0.03, 0.04]))
    l1 = b.add_body("l1", -1, fd.RevoluteJoint([0, 0, 1]), inertia=I)
    l2 = b.add_body("l2", l1, fd.RevoluteJoint([0, 1, 0]), inertia=I, placement=fd.PluckerTransform(np.eye(3), [0, 0, 0.5]))
    b.add_body("l3", l2, fd.RevoluteJoint([1, 0, 0]), inertia=I, placement=fd.PluckerTransform(np.eye(3), [0.5, 0, 0]))
    model = b.build()
    q = sp.symbols("q1:4", real=True)
    M = symbolic.mass_matrix(model, q, pretty=False)
    qn = np.array([0.3, -0.8, 1.7])
    M_num = np.array(M.subs(dict(zip(q, qn, strict=True))).evalf(), dtype=float)
    pm = pinocchio_model_from(model)
    np.testing.assert_allclose(M_num, pin.crba(pm, pm.createData(), qn), atol=1e-12)


def test_symbolic_model_shape_checks():
    model = symbolic.two_link_arm(symbolic.APPENDIX_D)
    with pytest.raises(fd.ShapeError, match="gravity"):
        symbolic.symbolic_model(model, gravity=[0, 0])
    with pytest.raises(fd.ShapeError, match="inertias"):
        symbolic.symbolic_model(model, inertias=fd.SpatialInertia.zero((3,)))
    with pytest.raises(fd.ShapeError, match="q"):
        symbolic.mass_matrix(model, sp.symbols("q1:4"))


def test_missing_sympy_is_reported(monkeypatch):
    monkeypatch.setitem(sys.modules, "sympy", None)  # makes `import sympy` raise ImportError
    with pytest.raises(MissingDependencyError, match="pip install sympy"):
        symbolic.prove_jacobi_identity()
