"""``fd.rnea_vjp`` and ``fd.aba_vjp``: the gradients of ``wᵀ τ`` and ``wᵀ q̈`` in O(nb) (core/cpp/vjp.hpp).

Oracles: Pinocchio's ``computeRNEADerivatives`` / ``computeABADerivatives`` contracted with ``w`` (after the
conventions), central differences of ``wᵀ fd.rnea`` and ``wᵀ fd.aba`` along ``fd.integrate``'s tangent on trees of
every joint kind (with ``f_ext``), and the reference (the contraction of featherdyn's own Jacobians — another kernel,
another road). The front ends (batch, out=, Dask, fd.compile, the frameworks' operations), as every declared
algorithm's, are tested by the suites over all declarations; the frameworks' gradients made of them in
test_jax_ops.py and test_torch_ops.py.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _models import TREES, pinocchio_pair, random_q, tree

import featherdyn as fd
from featherdyn.errors import NonFiniteError, ShapeError, SingularMassMatrixError

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize(("name", "floating"), ROBOTS)
def test_against_pinocchio(name: str, floating: bool) -> None:
    pin = pytest.importorskip("pinocchio")
    model, pm, pd, jm = pinocchio_pair(name, floating)
    rng = np.random.default_rng(5)
    q = fd.random_configuration(model, rng)
    v, a, tau, w = (rng.normal(size=model.nv) for _ in range(4))
    qp, vp = jm.q_to_pin(q), jm.v_to_pin(v)

    def sym(A: np.ndarray) -> np.ndarray:  # (Pinocchio fills the upper triangle of M and M⁻¹)
        A = jm.matrix_from_pin(A.copy())
        return np.triu(A) + np.triu(A, 1).T

    pin.computeRNEADerivatives(pm, pd, qp, vp, jm.v_to_pin(a))
    rnea = (jm.matrix_from_pin(pd.dtau_dq.copy()), jm.matrix_from_pin(pd.dtau_dv.copy()), sym(pd.M))
    pin.computeABADerivatives(pm, pd, qp, vp, jm.v_to_pin(tau))
    aba = (jm.matrix_from_pin(pd.ddq_dq.copy()), jm.matrix_from_pin(pd.ddq_dv.copy()), sym(pd.Minv))
    for g, jacobians in ((fd.rnea_vjp(model, q, v, a, w), rnea), (fd.aba_vjp(model, q, v, tau, w), aba)):
        for got, J in zip(g, jacobians, strict=True):
            assert _rel(got, w @ J) < 1e-9, _rel(got, w @ J)
    assert np.abs(g[0]).max() > 1e-3  # (not a zero gradient)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_central_differences_on_the_group(spec) -> None:  # type: ignore[no-untyped-def]
    """Every joint kind (revolute, prismatic, spherical, planar, free-flyer), with body forces and armature where
    the tree has it: the gradient of ``wᵀ τ`` and of ``wᵀ q̈`` against central differences, ``q`` along
    ``fd.integrate``'s tangent."""
    model = tree(spec.name)
    rng = np.random.default_rng(21)
    q = random_q(model, rng)
    v, a, w = (rng.normal(size=model.nv) for _ in range(3))
    f = rng.normal(size=(model.nbodies, 6))
    E, h = np.eye(model.nv), 1e-6

    for fn, vjp in ((fd.rnea, fd.rnea_vjp), (fd.aba, fd.aba_vjp)):
        gq, gv, ga = vjp(model, q, v, a, w, f)
        fdq = np.array([(w @ fn(model, fd.integrate(model, q, h * e), v, a, f)
                         - w @ fn(model, fd.integrate(model, q, -h * e), v, a, f)) / (2 * h) for e in E])
        fdv = np.array([(w @ fn(model, q, v + h * e, a, f) - w @ fn(model, q, v - h * e, a, f)) / (2 * h) for e in E])
        fda = np.array([(w @ fn(model, q, v, a + h * e, f) - w @ fn(model, q, v, a - h * e, f)) / (2 * h) for e in E])
        for got, expected in ((gq, fdq), (gv, fdv), (ga, fda)):
            assert _rel(got, expected) < 1e-6, (fn.__name__, _rel(got, expected))
        ref = vjp(model, q, v, a, w, f, backend="reference")
        for got, expected in zip((gq, gv, ga), ref, strict=True):
            assert _rel(got, expected) < 1e-12


@pytest.mark.parametrize(("name", "floating"), ROBOTS)
@pytest.mark.parametrize("gravity", [True, False])
def test_rows_of_the_jacobians(name: str, floating: bool, gravity: bool) -> None:
    """Equal to ``w @`` the Jacobians of ``fd.rnea_derivatives`` / ``fd.aba_derivatives`` (other kernels), with body
    forces, with and without gravity, and on a batch (one cotangent broadcast against many states)."""
    model = fd.load_robot(name, floating_base=floating)
    rng = np.random.default_rng(6)
    Q = fd.random_configuration(model, rng, size=4)
    V, A = rng.normal(size=(4, model.nv)), rng.normal(size=(4, model.nv))
    F = rng.normal(size=(4, model.nbodies, 6))
    w = rng.normal(size=model.nv)
    for vjp, jac in ((fd.rnea_vjp, fd.rnea_derivatives), (fd.aba_vjp, fd.aba_derivatives)):
        got = vjp(model, Q, V, A, w, F, gravity=gravity)
        J = jac(model, Q, V, A, F, gravity=gravity)
        for g, Jx in zip(got, J, strict=True):
            assert g.shape == (4, model.nv)
            expected = np.einsum("i,bij->bj", w, Jx)
            assert _rel(g, expected) < 1e-11, (vjp.__name__, _rel(g, expected))
        one = vjp(model, Q[2], V[2], A[2], w, F[2], gravity=gravity)
        for g, g1 in zip(got, one, strict=True):
            np.testing.assert_array_equal(g[2], g1)  # (the batch row is the one-state call, bit for bit)


def test_linear_in_the_cotangent() -> None:
    model = fd.load_robot("solo12", floating_base=True)
    rng = np.random.default_rng(7)
    q = fd.random_configuration(model, rng)
    v, a, w1, w2 = (rng.normal(size=model.nv) for _ in range(4))
    for vjp in (fd.rnea_vjp, fd.aba_vjp):
        sum_ = vjp(model, q, v, a, 2.0 * w1 - 3.0 * w2)
        parts = [2.0 * x - 3.0 * y for x, y in zip(vjp(model, q, v, a, w1), vjp(model, q, v, a, w2), strict=True)]
        for s, p in zip(sum_, parts, strict=True):
            assert _rel(s, p) < 1e-12
        for g in vjp(model, q, v, a, np.zeros(model.nv)):
            np.testing.assert_array_equal(g, 0.0)


def test_errors_name_the_cotangent() -> None:
    model = fd.load_robot("panda")
    q, z = fd.neutral(model), np.zeros(model.nv)
    with pytest.raises(ShapeError, match=r"^w: expected trailing dimension nv=9"):
        fd.rnea_vjp(model, q, z, z, np.zeros(3))
    bad = z.copy()
    bad[4] = np.inf
    for vjp in (fd.rnea_vjp, fd.aba_vjp):
        with pytest.raises(NonFiniteError, match=r"^w: .*index \(4,\)"):
            vjp(model, q, z, z, bad)
        with pytest.raises(NonFiniteError, match=r"^v: "):
            vjp(model, q, bad, z, z)
    with pytest.raises(ShapeError, match="w"):
        fd.aba_vjp(model, q, z, z, None)
    rng = np.random.default_rng(8)  # in a batch (the SIMD groups' check): the row and the entry
    Q, V, W = fd.random_configuration(model, rng, size=20), rng.normal(size=(20, 9)), rng.normal(size=(20, 9))
    W[13, 4] = np.nan
    for vjp in (fd.rnea_vjp, fd.aba_vjp):
        with pytest.raises(NonFiniteError, match=r"^w: .*index \(13, 4\)"):
            vjp(model, Q, V, V, W)


def test_aba_vjp_names_the_joint_of_a_singular_mass_matrix() -> None:
    """A massless link carrying a point mass on its axis at ``q₂ = 0``: ABA's error, naming the joint."""
    b = fd.ModelBuilder("singular")
    b.add_body("link", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]))
    b.add_body("bob", 0, fd.RevoluteJoint([1.0, 0.0, 0.0]), inertia=fd.SpatialInertia.point_mass(2.0, [0.0, 0.0, 0.3]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fd.PhysicalityWarning)
        m = b.build()
    v, tau, w = np.array([0.2, -0.4]), np.array([0.5, 0.1]), np.array([1.0, 2.0])
    with pytest.raises(SingularMassMatrixError, match="'link_joint'"):
        fd.aba_vjp(m, [0.7, 0.0], v, tau, w)
    with pytest.raises(SingularMassMatrixError, match="'link_joint'"):  # in a batch too
        fd.aba_vjp(m, [[0.7, 0.5], [0.7, 0.0]], v, tau, w)
    g = fd.aba_vjp(m, [0.7, 0.5], v, tau, w)  # regular elsewhere
    assert all(np.isfinite(x).all() for x in g)


# --- the mass matrix's: fd.crba_vjp ---------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "floating"), ROBOTS)
def test_crba_vjp_against_pinocchio(name: str, floating: bool) -> None:
    """``Σ_ij W_ij ∂M_ij/∂q`` with Pinocchio's ``∂(M e_j)/∂q``: ``computeRNEADerivatives`` at ``(q, 0, e_j)`` without
    gravity, column by column."""
    pin = pytest.importorskip("pinocchio")
    model, pm, pd, jm = pinocchio_pair(name, floating)
    pm.gravity = pin.Motion.Zero()
    rng = np.random.default_rng(9)
    q, W = fd.random_configuration(model, rng), rng.normal(size=(model.nv, model.nv))
    qp, zero = jm.q_to_pin(q), np.zeros(model.nv)
    expected = np.zeros(model.nv)
    for j, e in enumerate(np.eye(model.nv)):
        pin.computeRNEADerivatives(pm, pd, qp, zero, jm.v_to_pin(e))
        expected += W[:, j] @ jm.matrix_from_pin(pd.dtau_dq.copy())  # (∂(M e_j)/∂q, rows and columns in fd's order)
    got = fd.crba_vjp(model, q, W)
    assert _rel(got, expected) < 1e-10, _rel(got, expected)
    assert np.abs(got).max() > 1e-3


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_crba_vjp_central_differences_on_the_group(spec) -> None:  # type: ignore[no-untyped-def]
    """Every joint kind: ``∂⟨W, M⟩/∂q`` against central differences of ``⟨W, fd.crba⟩`` along ``fd.integrate``'s
    tangent, and the reference (``W`` contracted with the Dual-number ``∂M/∂q``)."""
    model = tree(spec.name)
    rng = np.random.default_rng(23)
    q, W = random_q(model, rng), rng.normal(size=(model.nv, model.nv))
    h = 1e-6
    expected = np.array([(np.sum(W * fd.crba(model, fd.integrate(model, q, h * e)))
                          - np.sum(W * fd.crba(model, fd.integrate(model, q, -h * e)))) / (2 * h)
                         for e in np.eye(model.nv)])
    got = fd.crba_vjp(model, q, W)
    assert _rel(got, expected) < 1e-7, _rel(got, expected)
    assert _rel(got, fd.crba_vjp(model, q, W, backend="reference")) < 1e-12


def test_crba_vjp_batches_and_symmetry() -> None:
    """One ``W`` broadcast against a batch of configurations, each row the one-state call bit for bit; only
    ``W``'s symmetric part enters (``M`` is symmetric); the second-order tensor of ``fd.rnea_second_derivatives``
    agrees on the batch."""
    model = fd.load_robot("talos_full_v2", floating_base=True)
    rng = np.random.default_rng(24)
    Q, W = fd.random_configuration(model, rng, size=5), rng.normal(size=(model.nv, model.nv))
    got = fd.crba_vjp(model, Q, W)
    assert got.shape == (5, model.nv)
    np.testing.assert_array_equal(got[3], fd.crba_vjp(model, Q[3], W))
    assert _rel(fd.crba_vjp(model, Q, 0.5 * (W + W.T)), got) < 1e-12
    assert _rel(fd.crba_vjp(model, Q, W - W.T), np.zeros_like(got)) < 1e-12
    zero = np.zeros((5, model.nv))
    dM = fd.rnea_second_derivatives(model, Q, zero, zero).dM_dq
    assert _rel(got, np.einsum("ij,bijk->bk", W, dM)) < 1e-11


def test_crba_vjp_errors_name_the_cotangent() -> None:
    model = fd.load_robot("panda")
    q = fd.neutral(model)
    with pytest.raises(ShapeError, match=r"^W: expected trailing dimensions \(nv, nv\) = \(9, 9\)"):
        fd.crba_vjp(model, q, np.zeros(9))
    with pytest.raises(ShapeError, match="^W"):
        fd.crba_vjp(model, q, None)
    W = np.zeros((9, 9))
    W[2, 5] = np.nan
    with pytest.raises(NonFiniteError, match=r"^W: .*index \(2, 5\)"):
        fd.crba_vjp(model, q, W)
    Q = fd.random_configuration(model, np.random.default_rng(2), size=12)
    Wb = np.zeros((12, 9, 9))
    Wb[10, 1, 7] = np.inf
    with pytest.raises(NonFiniteError, match=r"^W: .*index \(10, 1, 7\)"):  # (a batch: the SIMD groups' check)
        fd.crba_vjp(model, Q, Wb)
