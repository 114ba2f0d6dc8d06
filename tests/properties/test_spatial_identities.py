"""Spatial-algebra identities (chapter appendix F, RBDA ch. 2) as hypothesis properties.

Hypothesis draws the seed of the random values (``SpatialSamples``); every
property runs for every batch shape and for float64 and float32. The float32
results are compared with the float64 evaluation of the same float32 inputs,
at float32's tolerance.

Chapter erratum checked here: appendix F.2 row 4 prints
``v ×* (I v) = −I(v × v) + (v×)ᵀ I v``. Since ``v × v = 0`` and
``(v×)ᵀ = −(v×*)``, its right side is ``−v ×* (I v)``: the identity as printed
says ``v ×* (I v) = 0``, which is false. The correct version (the rate of
change of I for a body moving with v, ``İ = v×* I − I v×``, applied to v) is
``v ×* (I v) = −I(v × v) − (v×)ᵀ I v``; :func:`test_F2_row4_force_cross_of_momentum`
tests it and shows the printed one fails, and :func:`test_inertia_rate_explains_F2_row4`
derives it from the motion of a body.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn.testing import assert_close

seeds = st.integers(min_value=0, max_value=2**32 - 1)


def f64(x):
    return np.asarray(x, dtype=np.float64)


def matvec(M, x):
    return (f64(M) @ f64(x)[..., None])[..., 0]


def mT(M):
    return np.swapaxes(M, -1, -2)


# --------------------------------------------------------------------------
# cross products (F.2)
# --------------------------------------------------------------------------


@given(seed=seeds)
def test_crf_is_minus_crm_transpose(make_samples, batch_shape, dtype, seed):
    v = make_samples(seed).array(batch_shape, (6,), dtype)
    assert_close(fd.crf(v), -mT(fd.crm(v)), "crf(v) vs −crm(v)ᵀ", dtype=dtype)


@given(seed=seeds)
def test_self_cross_is_zero(make_samples, batch_shape, dtype, seed):
    v = make_samples(seed).motion(batch_shape, dtype)
    assert_close(v.cross(v).vector, np.zeros(batch_shape + (6,)), "v × v", dtype=dtype)


@given(seed=seeds)
def test_cross_is_antisymmetric(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    v, m = s.motion(batch_shape, dtype), s.motion(batch_shape, dtype)
    assert_close(v.cross(m).vector, -f64(m.cross(v).vector), "v × m vs −m × v", dtype=dtype)


@given(seed=seeds)
def test_jacobi_identity(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    a, b, c = (s.motion(batch_shape, dtype) for _ in range(3))
    total = a.cross(b.cross(c)) + b.cross(c.cross(a)) + c.cross(a.cross(b))
    assert_close(total.vector, np.zeros(batch_shape + (6,)), "Jacobi sum", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_cross_products_are_dual(make_samples, batch_shape, dtype, seed):
    # (v × m) · f = −m · (v ×* f): the force cross product is minus the adjoint
    s = make_samples(seed)
    v, m, f = s.motion(batch_shape, dtype), s.motion(batch_shape, dtype), s.force(batch_shape, dtype)
    assert_close(v.cross(m).dot(f), -f64(m.dot(v.cross(f))), "(v × m)·f vs −m·(v ×* f)", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_force_cross_does_no_work(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    v, f = s.motion(batch_shape, dtype), s.force(batch_shape, dtype)
    assert_close(v.dot(v.cross(f)), np.zeros(batch_shape), "v · (v ×* f)", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_cross_is_equivariant(make_samples, batch_shape, dtype, seed):
    # (Xv) × (Xw) = X(v × w) and (Xv) ×* (X* f) = X*(v ×* f)
    s = make_samples(seed)
    X = s.transform(batch_shape, dtype)
    v, w, f = s.motion(batch_shape, dtype), s.motion(batch_shape, dtype), s.force(batch_shape, dtype)
    assert_close(X.apply(v).cross(X.apply(w)).vector, X.apply(v.cross(w)).vector, "(Xv)×(Xw) vs X(v×w)", scale=10.0, dtype=dtype)
    assert_close(X.apply(v).cross(X.apply(f)).vector, X.apply(v.cross(f)).vector, "(Xv)×*(X*f) vs X*(v×*f)", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_F2_row4_force_cross_of_momentum(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    inertia, v = s.inertia(batch_shape, dtype), s.motion(batch_shape, dtype)
    I, crm_v = f64(inertia.matrix()), f64(fd.crm(v))
    lhs = v.cross(inertia @ v).vector
    v_cross_v = matvec(crm_v, v.vector)
    correct = -matvec(I, v_cross_v) - matvec(mT(crm_v), matvec(I, v.vector))
    assert_close(lhs, correct, "v ×* (I v) vs −I(v×v) − (v×)ᵀ I v", scale=10.0, dtype=dtype)
    printed = -matvec(I, v_cross_v) + matvec(mT(crm_v), matvec(I, v.vector))
    # the chapter's printed right side is exactly −lhs, wrong wherever v ×* (I v) ≠ 0
    assert_close(printed, -f64(lhs), "chapter F.2 row 4 right side vs −lhs", scale=10.0, dtype=dtype)
    assert np.all(np.abs(f64(lhs)).max(axis=-1) > 1e-3)


def expm6(A, terms=14):
    """Matrix exponential by its Taylor series (enough for the small arguments used here)."""
    out = term = np.broadcast_to(np.eye(6), A.shape).copy()
    for k in range(1, terms):
        term = term @ A / k
        out = out + term
    return out


@given(seed=seeds)
def test_inertia_rate_explains_F2_row4(make_samples, batch_shape, seed):
    # A body moving with the fixed-frame twist v has pose X(t) = exp(t [v]×), so its
    # inertia in the fixed frame is I(t) = X* I X⁻¹ and İ = v×* I − I v×; then
    # İ v = v ×* (I v) − I (v × v): the F.2 row-4 identity, with the correct sign.
    s = make_samples(seed)
    inertia, v = s.inertia(batch_shape), s.motion(batch_shape)
    dt = 1e-5

    def inertia_at(t):
        return fd.PluckerTransform.from_matrix(expm6(t * fd.crm(v))).apply(inertia).matrix()

    I_dot = (inertia_at(dt) - inertia_at(-dt)) / (2 * dt)
    I, C = inertia.matrix(), fd.crm(v)
    assert_close(I_dot, fd.crf(v) @ I - I @ C, "finite-difference İ vs v×* I − I v×", rtol=1e-6, atol=1e-6)
    assert_close(matvec(I_dot, v.vector), v.cross(inertia @ v).vector, "İ v vs v ×* (I v)", rtol=1e-6, atol=1e-6)


# --------------------------------------------------------------------------
# transforms (F.1)
# --------------------------------------------------------------------------


@given(seed=seeds)
def test_dual_matrix_is_inverse_transpose(make_samples, batch_shape, dtype, seed):
    X = make_samples(seed).transform(batch_shape, dtype)
    inv = np.linalg.inv(f64(X.matrix()))
    assert_close(X.dual_matrix(), mT(inv), "X* vs X⁻ᵀ", scale=10.0, dtype=dtype)
    # X*ᵀ = X⁻¹ and (X*)⁻¹ = (X⁻¹)*
    assert_close(mT(X.dual_matrix()), X.inverse().matrix(), "X*ᵀ vs X⁻¹", dtype=dtype)
    assert_close(np.linalg.inv(f64(X.dual_matrix())), X.inverse().dual_matrix(), "(X*)⁻¹ vs (X⁻¹)*", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_determinant_is_one(make_samples, batch_shape, dtype, seed):
    X = make_samples(seed).transform(batch_shape, dtype)
    assert_close(np.linalg.det(f64(X.matrix())), np.ones(batch_shape), "det X", dtype=dtype)
    assert_close(np.linalg.det(f64(X.dual_matrix())), np.ones(batch_shape), "det X*", dtype=dtype)


@given(seed=seeds)
def test_power_is_invariant(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X = s.transform(batch_shape, dtype)
    m, f = s.motion(batch_shape, dtype), s.force(batch_shape, dtype)
    assert_close(X.apply(m).dot(X.apply(f)), f64(m.dot(f)), "(Xm)·(X*f) vs m·f", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_composition_is_matrix_product(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X, Y = s.transform(batch_shape, dtype), s.transform(batch_shape, dtype)
    XY = X @ Y
    assert XY.dtype == dtype and XY.shape == batch_shape
    assert_close(XY.matrix(), f64(X.matrix()) @ f64(Y.matrix()), "(X @ Y).matrix() vs X Y", scale=10.0, dtype=dtype)
    assert_close(XY.dual_matrix(), f64(X.dual_matrix()) @ f64(Y.dual_matrix()), "(X @ Y)* vs X* Y*", scale=10.0, dtype=dtype)
    m = s.motion(batch_shape, dtype)
    assert_close(XY.apply(m).vector, X.apply(Y.apply(m)).vector, "(X @ Y) m vs X (Y m)", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_apply_inverse_is_inverse_apply(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X = s.transform(batch_shape, dtype)
    m, f, inertia = s.motion(batch_shape, dtype), s.force(batch_shape, dtype), s.inertia(batch_shape, dtype)
    inv = X.inverse()
    assert_close(X.apply_inverse(m).vector, inv.apply(m).vector, "X.apply_inverse(m)", scale=10.0, dtype=dtype)
    assert_close(X.apply_inverse(f).vector, inv.apply(f).vector, "X.apply_inverse(f)", scale=10.0, dtype=dtype)
    assert_close(X.apply_inverse(inertia).matrix(), inv.apply(inertia).matrix(), "X.apply_inverse(I)", scale=10.0, dtype=dtype)
    assert_close(X.apply_inverse(X.apply(m)).vector, m.vector, "X⁻¹ X m", scale=10.0, dtype=dtype)
    assert_close((inv @ X).matrix(), np.broadcast_to(np.eye(6), batch_shape + (6, 6)), "X⁻¹ X", scale=10.0, dtype=dtype)


# --------------------------------------------------------------------------
# inertia (F.3)
# --------------------------------------------------------------------------


@given(seed=seeds)
def test_inertia_transform_is_congruence(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X, inertia = s.transform(batch_shape, dtype), s.inertia(batch_shape, dtype)
    expected = f64(X.dual_matrix()) @ f64(inertia.matrix()) @ np.linalg.inv(f64(X.matrix()))
    assert_close(X.apply(inertia).matrix(), expected, "X.apply(I) vs X* I X⁻¹", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_kinetic_energy_and_momentum_are_covariant(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X, inertia, v = s.transform(batch_shape, dtype), s.inertia(batch_shape, dtype), s.motion(batch_shape, dtype)
    T = f64(inertia.kinetic_energy(v))
    assert_close(X.apply(inertia).kinetic_energy(X.apply(v)), T, "T after transform", scale=10.0, dtype=dtype)
    assert_close((X.apply(inertia) @ X.apply(v)).vector, X.apply(inertia @ v).vector, "(X*IX⁻¹)(Xv) vs X*(Iv)", scale=10.0, dtype=dtype)
    assert np.all(T >= 0)


@given(seed=seeds)
def test_composite_inertia_is_sum_of_transformed(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    bodies = [(s.transform(batch_shape, dtype), s.inertia(batch_shape, dtype)) for _ in range(3)]
    composite = sum(X.apply(inertia) for X, inertia in bodies)
    expected = sum(f64(X.dual_matrix()) @ f64(inertia.matrix()) @ np.linalg.inv(f64(X.matrix())) for X, inertia in bodies)
    assert_close(composite.matrix(), expected, "Σ X* I X⁻¹", scale=10.0, dtype=dtype)
    assert np.all(composite.is_physical())


@given(seed=seeds)
def test_from_matrix_inverts_matrix(make_samples, batch_shape, dtype, seed):
    inertia = make_samples(seed).inertia(batch_shape, dtype)
    back = fd.SpatialInertia.from_matrix(inertia.matrix())
    assert_close(back.mass, inertia.mass, "mass", dtype=dtype)
    assert_close(back.com, inertia.com, "com", dtype=dtype)
    assert_close(back.inertia_com, inertia.inertia_com, "inertia_com", scale=10.0, dtype=dtype)
    assert_close(back.matrix(), inertia.matrix(), "from_matrix ∘ matrix", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_inertia_times_motion_is_matrix_product(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    inertia, v = s.inertia(batch_shape, dtype), s.motion(batch_shape, dtype)
    assert_close((inertia @ v).vector, matvec(inertia.matrix(), v.vector), "I @ v vs matrix @ v", scale=10.0, dtype=dtype)


@given(seed=seeds)
def test_physical_inertia_matrix_is_symmetric_positive_definite(make_samples, batch_shape, dtype, seed):
    M = f64(make_samples(seed).inertia(batch_shape, dtype).matrix())
    assert_close(M, mT(M), "I vs Iᵀ", dtype=dtype)
    assert np.all(np.linalg.eigvalsh(M) > 0)


@given(seed=seeds)
def test_batch_equals_loop(make_samples, batch_shape, dtype, seed):
    s = make_samples(seed)
    X, inertia, v = s.transform(batch_shape, dtype), s.inertia(batch_shape, dtype), s.motion(batch_shape, dtype)
    batched = (X.apply(inertia) @ X.apply(v)).vector
    for idx in np.ndindex(*batch_shape):
        single = (X[idx].apply(inertia[idx]) @ X[idx].apply(v[idx])).vector if idx else batched
        np.testing.assert_array_equal(batched[idx], single)
