"""The lane kernels (featherdyn.engine._lanes) against the scalar cores, bit for bit.

The batched RNEA, CRBA and ABA run blocks of ``LANES`` states in SIMD lanes;
every lane must compute exactly what the scalar core computes on its state
(``np.array_equal``, not a tolerance): for batch lengths around the block size
(a partial last block is padded), broadcast inputs, with and without external
forces, with gravity off, on 1–3 threads, on random trees with every joint type
and on three robots — and ABA's singular status must be the scalar batch's.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from _models import TREES, random_inertia, random_placement, random_state, tree

import featherdyn as fd
from featherdyn.engine import _kernels as kern
from featherdyn.engine import _lanes as lanes
from featherdyn.engine import _layout as lay
from featherdyn.engine._dispatch import arrays_of

B = lanes.LANES
SIZES = [1, 3, B - 1, B, B + 1, 37]
ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]


def _axis_tree(seed: int = 21, nbodies: int = 10) -> fd.Model:
    """A random tree whose revolute and prismatic joints are along ±x, ±y, ±z (the kernels' REV_X/Y/Z codes and
    ABA's unit-column branch), hung from a free-flyer, with a spherical and a planar joint in between."""
    rng = np.random.default_rng(seed)
    b = fd.ModelBuilder(f"axis{seed}")
    b.add_body("b0", -1, fd.FreeFlyerJoint(), inertia=random_inertia(rng))
    parents = [-1]
    for i in range(1, nbodies):
        kind = ("revolute", "prismatic", "spherical", "planar", "revolute", "revolute")[i % 6]
        axis = np.zeros(3)
        axis[rng.integers(0, 3)] = rng.choice([-1.0, 1.0])
        joint = {"revolute": fd.RevoluteJoint(axis), "prismatic": fd.PrismaticJoint(axis),
                 "spherical": fd.SphericalJoint(), "planar": fd.PlanarJoint([0.0, 0.0, 1.0])}[kind]
        parent = int(rng.integers(max(0, i - 3), i))
        parents.append(parent)
        b.add_body(f"b{i}", parent, joint, placement=random_placement(rng), inertia=random_inertia(rng))
    return b.build()


@functools.cache
def _model(name: str) -> fd.Model:
    if name == "axis_tree":
        return _axis_tree()
    for robot, floating in ROBOTS:
        if name == robot:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    return fd.load_robot(robot, floating_base=floating)
                except fd.FeatherdynError:  # pragma: no cover - example-robot-data missing
                    pytest.skip(f"{robot} does not load")
    return tree(name)


TREE_NAMES = [s.name for s in TREES] + ["axis_tree"]
ALL_NAMES = TREE_NAMES + [r for r, _ in ROBOTS]


def _inputs(model: fd.Model, n: int, seed: int, perturb: bool = True) -> tuple[np.ndarray, ...]:
    """`(n, ·)` rows: q (with ``perturb``, quaternions off the unit sphere: the kernels must agree on any input),
    v, a (also τ for ABA), f_ext `(n, nb, 6)`."""
    s = random_state(model, seed, (n,))
    rng = np.random.default_rng(seed + 1000)
    q = s.q + 0.05 * rng.normal(size=s.q.shape) if perturb else s.q
    return q, s.v, s.a, s.f_ext


def _row(X: np.ndarray, s: int) -> np.ndarray:
    return X[s if X.shape[0] > 1 else 0]


def _scalar_rnea(md, Q, V, A, FX, gravity, n):  # type: ignore[no-untyped-def]
    out = np.empty((n, md.nv))
    W = np.empty(lay.workspace_size(lay.WS_RNEA, md.nb))
    for s in range(n):
        fx = md.no_fext if FX.shape[1] == 0 else _row(FX, s)
        kern.rnea_core(md.BI, md.BF, md.G, _row(Q, s), _row(V, s), _row(A, s), fx, gravity, out[s], W)
    return out


def _scalar_crba(md, Q, n):  # type: ignore[no-untyped-def]
    out = np.empty((n, md.nv, md.nv))
    W = np.empty(lay.workspace_size(lay.WS_CRBA, md.nb))
    for s in range(n):
        kern.crba_core(md.BI, md.BF, _row(Q, s), out[s], W)
    return out


def _scalar_aba(md, Q, V, T, FX, gravity, n):  # type: ignore[no-untyped-def]
    """``aba_core`` state by state, and the status a batched ABA must return: ``state · nb + joint`` of the
    first singular state, or ``-1``."""
    out = np.empty((n, md.nv))
    W = np.empty(lay.workspace_size(lay.WS_ABA, md.nb))
    status = -1
    for s in range(n):
        fx = md.no_fext if FX.shape[1] == 0 else _row(FX, s)
        bad = kern.aba_core(md.BI, md.BF, md.G, _row(Q, s), _row(V, s), _row(T, s), fx, gravity, out[s], W)
        if bad >= 0 and status < 0:
            status = s * md.nb + bad
    return out, status


NO_FEXT = np.zeros((1, 0, 6))


def _check(model: fd.Model, Q, V, A, FX, gravity, n, threads=2) -> None:  # type: ignore[no-untyped-def]
    md = arrays_of(model)
    what = f"{model.name} n={n} Q{Q.shape} V{V.shape} FX{FX.shape} gravity={gravity} threads={threads}"
    tau = np.full((n, md.nv), np.nan)
    lanes.rnea_lanes(md.BI, md.BF, md.G, Q, V, A, FX, gravity, tau, threads)
    assert np.array_equal(tau, _scalar_rnea(md, Q, V, A, FX, gravity, n)), f"rnea: {what}"
    qdd = np.full((n, md.nv), np.nan)
    status = lanes.aba_lanes(md.BI, md.BF, md.G, Q, V, A, FX, gravity, qdd, threads)
    expected, expected_status = _scalar_aba(md, Q, V, A, FX, gravity, n)
    assert status == expected_status == -1, f"aba status: {what}"
    assert np.array_equal(qdd, expected), f"aba: {what}"


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("name", ALL_NAMES)
def test_lanes_equal_scalar_cores(name: str, n: int) -> None:
    model = _model(name)
    md = arrays_of(model)
    Q, V, A, F = _inputs(model, n, 3 * n + 1)
    _check(model, Q, V, A, NO_FEXT, True, n)
    _check(model, Q, V, A, F, True, n)
    M = np.full((n, md.nv, md.nv), np.nan)
    lanes.crba_lanes(md.BI, md.BF, Q, M, 2)
    assert np.array_equal(M, _scalar_crba(md, Q, n)), f"crba: {name} n={n}"


@pytest.mark.parametrize("name", TREE_NAMES)
def test_lanes_broadcast_rows_gravity_off_and_threads(name: str) -> None:
    model = _model(name)
    md = arrays_of(model)
    n = 2 * B + 3
    Q, V, A, F = _inputs(model, n, 5)
    # one row broadcast to every state, in each input
    _check(model, Q[:1], V, A, NO_FEXT, True, n)
    _check(model, Q, V[:1], A, F[:1], True, n)
    _check(model, Q, V, A[:1], F, False, n)
    _check(model, Q[:1], V[:1], A[:1], F[:1], False, n)
    # chunks of blocks per thread: more threads than blocks, an odd number of blocks per thread
    for threads in (1, 3, 8):
        _check(model, Q, V, A, F, True, n, threads)
    M = np.full((n, md.nv, md.nv), np.nan)
    lanes.crba_lanes(md.BI, md.BF, Q[:1], M, 3)
    assert np.array_equal(M, _scalar_crba(md, Q[:1], n))


@pytest.mark.parametrize("name", ["free_branch", "planar_root_branch"])
def test_crba_lanes_streamed_output(name: str) -> None:
    """A batch above STREAM_MIN entries: non-temporal stores of whole lines, element stores at the ends of each
    block's region — into an output that starts anywhere in a cache line."""
    model = _model(name)
    md = arrays_of(model)
    nn = md.nv * md.nv
    n = lanes.STREAM_MIN // nn + B + 3
    Q = _inputs(model, n, 8)[0]
    expected = _scalar_crba(md, Q, n)
    for shift in (0, 1, 5):
        buf = np.full(n * nn + shift, np.nan)
        M = buf[shift:].reshape(n, md.nv, md.nv)
        lanes.crba_lanes(md.BI, md.BF, Q, M, 2)
        assert np.array_equal(M, expected), f"crba streamed, output shifted by {shift}"


def test_lanes_empty_batch() -> None:
    md = arrays_of(_model("free_branch"))
    empty = np.zeros((0, md.nv))
    lanes.rnea_lanes(md.BI, md.BF, md.G, np.zeros((0, md.nq)), empty, empty, NO_FEXT, True, empty, 2)
    lanes.crba_lanes(md.BI, md.BF, np.zeros((0, md.nq)), np.zeros((0, md.nv, md.nv)), 2)
    assert lanes.aba_lanes(md.BI, md.BF, md.G, np.zeros((0, md.nq)), empty, empty, NO_FEXT, True, empty, 2) == -1


def test_public_batched_calls_equal_single_calls_on_robots() -> None:
    for name, _ in ROBOTS:
        model = _model(name)
        cm = fd.compile(model, warmup=False)
        n = B + 3
        Q, V, A, F = _inputs(model, n, 11, perturb=False)
        tau = cm.rnea_batch(Q, V, A)
        tauf = cm.rnea_batch(Q, V, A, f_ext=F, gravity=False)
        M = cm.crba_batch(Q)
        qdd = cm.aba_batch(Q, V, A)
        for k in range(n):
            assert np.array_equal(tau[k], cm.rnea(Q[k], V[k], A[k]))
            assert np.array_equal(tauf[k], fd.rnea(model, Q[k], V[k], A[k], f_ext=F[k], gravity=False, backend="compiled"))
            public = fd.rnea(model, Q[k], V[k], A[k], f_ext=F[k], gravity=False)  # the C++ core: to round-off
            assert np.allclose(tauf[k], public, rtol=1e-12, atol=1e-12)
            assert np.array_equal(M[k], cm.crba(Q[k]))
            assert np.array_equal(qdd[k], cm.aba(Q[k], V[k], A[k]))


# ---------------------------------------------------------------------------
# ABA's singular status
# ---------------------------------------------------------------------------


def _pendulum_on_massless_link() -> fd.Model:
    """A massless link carrying a point mass on its second axis: joint ``link_joint`` moves nothing when
    ``q₂ = 0`` (the mass then sits on the first axis), and at any other ``q₂`` the mass matrix is regular."""
    b = fd.ModelBuilder("bob")
    b.add_body("link", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), joint_name="link_joint")
    b.add_body("bob", 0, fd.RevoluteJoint([1.0, 0.0, 0.0]), joint_name="bob_joint",
               inertia=fd.SpatialInertia.point_mass(2.0, [0.0, 0.0, 0.3]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return b.build()


@pytest.mark.parametrize("singular", [[13], [13, 30], [0], [36], [B - 1, B], [35, 36], []])
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_aba_singular_status_equals_scalar_batch(singular: list[int], threads: int) -> None:
    model = _pendulum_on_massless_link()
    md = arrays_of(model)
    n = 37
    rng = np.random.default_rng(4)
    Q = rng.uniform(0.2, 1.0, size=(n, 2))
    Q[singular, 1] = 0.0
    V, T = rng.normal(size=(n, 2)), rng.normal(size=(n, 2))
    qdd = np.empty((n, 2))
    status = lanes.aba_lanes(md.BI, md.BF, md.G, Q, V, T, NO_FEXT, True, qdd, threads)
    expected, ref = _scalar_aba(md, Q, V, T, NO_FEXT, True, n)  # the status of kernels.aba_batch
    assert status == ref == (singular[0] * md.nb + 0 if singular else -1)
    if not singular:
        assert np.array_equal(qdd, expected)


def test_aba_singular_batch_index_through_the_public_function() -> None:
    model = _pendulum_on_massless_link()
    rng = np.random.default_rng(5)
    Q = rng.uniform(0.2, 1.0, size=(3, 13, 2))
    Q[2, 4, 1] = 0.0
    Q[2, 7, 1] = 0.0
    with pytest.raises(fd.errors.SingularMassMatrixError, match=r"'link_joint'.*batch index \(2, 4\)"):
        fd.aba(model, Q, np.zeros(2), np.ones(2))


def test_aba_singular_multi_dof_joint() -> None:
    """A spherical joint carrying nothing: the Cholesky pivot of its 3×3 ``D`` flags the lane."""
    b = fd.ModelBuilder("ball")
    b.add_body("base", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), inertia=random_inertia(np.random.default_rng(1)))
    b.add_body("ball", 0, fd.SphericalJoint(), joint_name="ball_joint",
               placement=fd.PluckerTransform(np.eye(3), [0.3, 0.0, 0.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = b.build()
    md = arrays_of(model)
    n = B + 2
    Q, V, A, _F = _inputs(model, n, 6, perturb=False)
    status = lanes.aba_lanes(md.BI, md.BF, md.G, Q, V, A, NO_FEXT, True, np.empty((n, md.nv)), 2)
    assert status == _scalar_aba(md, Q, V, A, NO_FEXT, True, n)[1] == 1
    with pytest.raises(fd.errors.SingularMassMatrixError, match=r"'ball_joint'.*batch index \(0,\)"):
        fd.aba(model, Q, V, A)
