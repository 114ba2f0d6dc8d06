"""featherdyn's spatial algebra against Pinocchio's, value by value.

Pinocchio stores 6D vectors linear first (``Motion.vector = [v; ω]``,
``Force.vector = [f; n]``); featherdyn angular first. Every comparison here
permutes explicitly with ``P = [[0, 1], [1, 0]]``: ``x_fd = P x_pin`` and
``M_fd = P M_pin P`` for 6×6 operators. Each featherdyn call is batched; the
Pinocchio side loops over the batch (batch == loop against the oracle).
float32 results are compared with Pinocchio's float64 on the same float32
inputs, at float32's tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])


def fd_vec(pin_vector):
    """Pinocchio's linear-first 6-vector in featherdyn's angular-first order."""
    return P @ np.asarray(pin_vector)


def fd_mat(pin_matrix):
    """A 6×6 operator on Pinocchio's linear-first vectors, re-expressed angular first."""
    return P @ np.asarray(pin_matrix) @ P


def to_pin_motion(x: fd.SpatialMotion, idx):
    v = np.asarray(x.vector[idx], dtype=np.float64)
    return pin.Motion(v[3:], v[:3])  # Motion(linear, angular)


def to_pin_force(x: fd.SpatialForce, idx):
    f = np.asarray(x.vector[idx], dtype=np.float64)
    return pin.Force(f[3:], f[:3])  # Force(linear, angular)


def to_pin_se3(X: fd.PluckerTransform, idx):
    return pin.SE3(np.asarray(X.rotation[idx], dtype=np.float64), np.asarray(X.translation[idx], dtype=np.float64))


def to_pin_inertia(inertia: fd.SpatialInertia, idx):
    return pin.Inertia(
        float(inertia.mass[idx]),
        np.asarray(inertia.com[idx], dtype=np.float64),
        np.asarray(inertia.inertia_com[idx], dtype=np.float64),
    )


def loop(batch_shape, fn):
    """Stack ``fn(idx)`` over the batch indices (Pinocchio has no batch axes)."""
    outs = [np.asarray(fn(idx), dtype=np.float64) for idx in np.ndindex(*batch_shape)]
    return np.stack(outs).reshape(tuple(batch_shape) + outs[0].shape)


def test_layout_permutation_is_what_pinocchio_does():
    m = pin.Motion(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))
    np.testing.assert_array_equal(m.linear, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(m.vector, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0])  # linear first
    np.testing.assert_array_equal(fd_vec(m.vector), [4.0, 5.0, 6.0, 1.0, 2.0, 3.0])


def test_skew(batch_shape, dtype, samples):
    w = samples.array(batch_shape, (3,), dtype)
    assert_close(fd.skew(w), loop(batch_shape, lambda i: pin.skew(w[i].astype(np.float64))), "skew", dtype=dtype)


# --------------------------------------------------------------------------
# SE3 vs PluckerTransform
# --------------------------------------------------------------------------


def test_act_on_motion_force_inertia(batch_shape, dtype, samples):
    X = samples.transform(batch_shape, dtype)
    m, f, inertia = samples.motion(batch_shape, dtype), samples.force(batch_shape, dtype), samples.inertia(batch_shape, dtype)
    M = lambda i: to_pin_se3(X, i)  # noqa: E731
    assert_close(X.apply(m).vector, loop(batch_shape, lambda i: fd_vec(M(i).act(to_pin_motion(m, i)).vector)), "SE3.act(Motion)", dtype=dtype)
    assert_close(X.apply(f).vector, loop(batch_shape, lambda i: fd_vec(M(i).act(to_pin_force(f, i)).vector)), "SE3.act(Force)", dtype=dtype)
    XI = X.apply(inertia)
    theirs = [M(i).act(to_pin_inertia(inertia, i)) for i in np.ndindex(*batch_shape)]
    assert_close(XI.mass, np.reshape([t.mass for t in theirs], batch_shape), "SE3.act(Inertia).mass", dtype=dtype)
    assert_close(XI.com, np.reshape([t.lever for t in theirs], batch_shape + (3,)), "SE3.act(Inertia).lever", dtype=dtype)
    assert_close(XI.inertia_com, np.reshape([t.inertia for t in theirs], batch_shape + (3, 3)), "SE3.act(Inertia).inertia", dtype=dtype)
    assert_close(XI.matrix(), loop(batch_shape, lambda i: fd_mat(M(i).act(to_pin_inertia(inertia, i)).matrix())), "SE3.act(Inertia).matrix()", dtype=dtype)


def test_act_inv_on_motion_force_inertia(batch_shape, dtype, samples):
    X = samples.transform(batch_shape, dtype)
    m, f, inertia = samples.motion(batch_shape, dtype), samples.force(batch_shape, dtype), samples.inertia(batch_shape, dtype)
    M = lambda i: to_pin_se3(X, i)  # noqa: E731
    assert_close(X.apply_inverse(m).vector, loop(batch_shape, lambda i: fd_vec(M(i).actInv(to_pin_motion(m, i)).vector)), "SE3.actInv(Motion)", dtype=dtype)
    assert_close(X.apply_inverse(f).vector, loop(batch_shape, lambda i: fd_vec(M(i).actInv(to_pin_force(f, i)).vector)), "SE3.actInv(Force)", dtype=dtype)
    assert_close(
        X.apply_inverse(inertia).matrix(),
        loop(batch_shape, lambda i: fd_mat(M(i).actInv(to_pin_inertia(inertia, i)).matrix())),
        "SE3.actInv(Inertia)",
        dtype=dtype,
    )


def test_action_matrices_and_homogeneous(batch_shape, dtype, samples):
    X = samples.transform(batch_shape, dtype)
    M = lambda i: to_pin_se3(X, i)  # noqa: E731
    assert_close(X.matrix(), loop(batch_shape, lambda i: fd_mat(M(i).toActionMatrix())), "toActionMatrix", dtype=dtype)
    assert_close(X.dual_matrix(), loop(batch_shape, lambda i: fd_mat(M(i).toDualActionMatrix())), "toDualActionMatrix", dtype=dtype)
    assert_close(X.inverse_matrix(), loop(batch_shape, lambda i: fd_mat(M(i).toActionMatrixInverse())), "toActionMatrixInverse", dtype=dtype)
    assert_close(X.homogeneous(), loop(batch_shape, lambda i: M(i).homogeneous), "homogeneous", dtype=dtype)
    back = fd.PluckerTransform.from_homogeneous(loop(batch_shape, lambda i: M(i).homogeneous))
    assert_close(back.translation, X.translation, "from_homogeneous(SE3.homogeneous)", dtype=dtype)


def test_inverse_and_composition(batch_shape, dtype, samples):
    X, Y = samples.transform(batch_shape, dtype), samples.transform(batch_shape, dtype)
    inv = X.inverse()
    assert_close(inv.rotation, loop(batch_shape, lambda i: to_pin_se3(X, i).inverse().rotation), "SE3.inverse().rotation", dtype=dtype)
    assert_close(inv.translation, loop(batch_shape, lambda i: to_pin_se3(X, i).inverse().translation), "SE3.inverse().translation", dtype=dtype)
    XY = X @ Y
    assert_close(XY.rotation, loop(batch_shape, lambda i: (to_pin_se3(X, i) * to_pin_se3(Y, i)).rotation), "(SE3 * SE3).rotation", dtype=dtype)
    assert_close(XY.translation, loop(batch_shape, lambda i: (to_pin_se3(X, i) * to_pin_se3(Y, i)).translation), "(SE3 * SE3).translation", dtype=dtype)


def test_from_pinocchio_random_se3():
    pin.seed(7)
    for _ in range(10):
        M = pin.SE3.Random()
        X = fd.PluckerTransform(M.rotation, M.translation)
        assert_close(X.matrix(), fd_mat(M.toActionMatrix()), "SE3.Random toActionMatrix")
        v = pin.Motion.Random()
        assert_close(X.apply(fd.SpatialMotion.from_vector(fd_vec(v.vector))).vector, fd_vec(M.act(v).vector), "SE3.Random act")


# --------------------------------------------------------------------------
# Motion / Force products
# --------------------------------------------------------------------------


def test_cross_products_and_power(batch_shape, dtype, samples):
    v, m, f = samples.motion(batch_shape, dtype), samples.motion(batch_shape, dtype), samples.force(batch_shape, dtype)
    pv = lambda i: to_pin_motion(v, i)  # noqa: E731
    assert_close(v.cross(m).vector, loop(batch_shape, lambda i: fd_vec(pv(i).cross(to_pin_motion(m, i)).vector)), "Motion.cross(Motion)", dtype=dtype)
    assert_close(v.cross(f).vector, loop(batch_shape, lambda i: fd_vec(pv(i).cross(to_pin_force(f, i)).vector)), "Motion.cross(Force)", dtype=dtype)
    assert_close(v.dot(f), loop(batch_shape, lambda i: pv(i).dot(to_pin_force(f, i))), "Motion.dot(Force)", dtype=dtype)
    assert_close(fd.crm(v), loop(batch_shape, lambda i: fd_mat(pv(i).action)), "Motion.action (crm)", dtype=dtype)
    assert_close(fd.crf(v), loop(batch_shape, lambda i: fd_mat(pv(i).dualAction)), "Motion.dualAction (crf)", dtype=dtype)


# --------------------------------------------------------------------------
# Inertia
# --------------------------------------------------------------------------


def test_inertia_matrix_momentum_sum(batch_shape, dtype, samples):
    a, b = samples.inertia(batch_shape, dtype), samples.inertia(batch_shape, dtype)
    v = samples.motion(batch_shape, dtype)
    pa = lambda i: to_pin_inertia(a, i)  # noqa: E731
    assert_close(a.matrix(), loop(batch_shape, lambda i: fd_mat(pa(i).matrix())), "Inertia.matrix()", dtype=dtype)
    assert_close((a @ v).vector, loop(batch_shape, lambda i: fd_vec((pa(i) * to_pin_motion(v, i)).vector)), "Inertia * Motion", dtype=dtype)
    assert_close(a.kinetic_energy(v), loop(batch_shape, lambda i: 0.5 * pa(i).vtiv(to_pin_motion(v, i))), "½ Inertia.vtiv", dtype=dtype)
    theirs = [pa(i) + to_pin_inertia(b, i) for i in np.ndindex(*batch_shape)]
    s = a + b
    assert_close(s.mass, np.reshape([t.mass for t in theirs], batch_shape), "(Inertia + Inertia).mass", dtype=dtype)
    assert_close(s.com, np.reshape([t.lever for t in theirs], batch_shape + (3,)), "(Inertia + Inertia).lever", dtype=dtype)
    assert_close(s.inertia_com, np.reshape([t.inertia for t in theirs], batch_shape + (3, 3)), "(Inertia + Inertia).inertia", dtype=dtype)


def test_inertia_se3_action(batch_shape, dtype, samples):
    X, inertia = samples.transform(batch_shape, dtype), samples.inertia(batch_shape, dtype)
    pI = lambda i: to_pin_inertia(inertia, i)  # noqa: E731
    assert_close(X.apply(inertia).matrix(), loop(batch_shape, lambda i: fd_mat(pI(i).se3Action(to_pin_se3(X, i)).matrix())), "Inertia.se3Action", dtype=dtype)
    assert_close(
        X.apply_inverse(inertia).matrix(),
        loop(batch_shape, lambda i: fd_mat(pI(i).se3ActionInverse(to_pin_se3(X, i)).matrix())),
        "Inertia.se3ActionInverse",
        dtype=dtype,
    )


def test_inertia_from_pinocchio_random():
    pin.seed(11)
    for _ in range(10):
        theirs = pin.Inertia.Random()
        ours = fd.SpatialInertia.from_matrix(fd_mat(theirs.matrix()))
        assert_close(ours.mass, theirs.mass, "from_matrix mass")
        assert_close(ours.com, theirs.lever, "from_matrix lever")
        assert_close(ours.inertia_com, theirs.inertia, "from_matrix inertia")
        # pin.Inertia.Random() is not always realisable: judge it independently here
        e = np.linalg.eigvalsh(theirs.inertia)
        assert ours.is_physical() == bool(theirs.mass > 0 and e[0] > 0 and e[0] + e[1] >= e[2])
