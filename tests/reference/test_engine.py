"""The compiled engine (featherdyn.engine) against the reference algorithms and Pinocchio.

* every robot of example-robot-data that loads, fixed and floating base:
  FK (placements, velocities, accelerations), RNEA (with ``f_ext``, without
  gravity), NLE, generalized gravity, CRBA, ABA and frame Jacobians in the
  three reference frames, single state and batched, through the public
  functions (which pick the engine for float64) and through ``fd.compile``;
  relative error ≤ 1e-12 of the largest reference entry;
* the random trees of ``tests/_models.py`` (every joint type);
* input handling: non-contiguous, integer, float32, object and broadcast
  inputs, the reference's input errors, the singular mass matrix;
* spot checks against Pinocchio on panda, solo12 and talos_full_v2;
* memory: a batched call allocates its outputs and one workspace per thread.

The kernels are generic (compiled once, cached by Numba), so the many robots
cost no compilation; speed is measured in ``benchmarks/``, never here.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn.errors import BackendError
from tests._models import library_robot, library_robot_names

RTOL = 1e-12  # relative to the largest entry of the reference result


def assert_aba(actual: np.ndarray, expected: np.ndarray, M: np.ndarray, what: str) -> None:
    """q̈ agrees to 1e-12 normwise in the metric of the mass matrix: ``|M (q̈ − q̈_ref)| <= 1e-12 |M| |q̈_ref|``.

    ABA solves ``M q̈ = τ − h``; both implementations are backward stable, so
    their q̈ differ by up to cond(M)·ε — 5e-12 relative for robots with tiny link
    inertias (icub, human) — while each is the exact answer for a mass matrix
    perturbed by ~1e-15 |M|.
    """
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    if not expected.size:
        return
    err = float(np.max(np.abs(np.einsum("...ij,...j->...i", M, actual - expected))))
    scale = float(np.max(np.abs(M))) * float(np.max(np.abs(expected)))
    assert err <= RTOL * scale, f"{what}: max |M (q̈ − q̈_ref)| = {err:.3g} > {RTOL:g} × |M| |q̈_ref| = {scale:.3g}"
REFS = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)
SPOT_ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]


def assert_rel(actual: np.ndarray, expected: np.ndarray, what: str, rtol: float = RTOL) -> None:
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = max(float(np.max(np.abs(expected))) if expected.size else 0.0, 1e-300)
    err = float(np.max(np.abs(actual - expected))) if expected.size else 0.0
    if err > rtol * scale:
        idx = np.unravel_index(int(np.argmax(np.abs(actual - expected))), expected.shape)
        pytest.fail(f"{what}: max |engine − reference| = {err:.3g} > {rtol:g} × {scale:.3g} at index {idx}")


_robot = library_robot
_robots = library_robot_names


def _state(model: fd.Model, seed: int, size: tuple[int, ...] = ()) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng, size=size or None)
    q = np.asarray(q, dtype=np.float64).reshape(size + (model.nq,))
    v = rng.normal(size=size + (model.nv,))
    a = rng.normal(size=size + (model.nv,))
    tau = 5 * rng.normal(size=size + (model.nv,))
    f = rng.normal(size=size + (model.nbodies, 6))
    return q, v, a, tau, f


def _frames(model: fd.Model) -> list[int]:
    """A few frames: the first, the last and one in the middle (the world frame included if present)."""
    n = len(model.frames)
    return sorted({0, n // 2, n - 1}) if n else []


def _check_all(model: fd.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, tau: np.ndarray, f: np.ndarray,
               label: str) -> None:
    """Every engine quantity of the public functions against ``backend="reference"``."""

    def both(fn, *args, **kw):  # type: ignore[no-untyped-def]
        return fn(*args, **kw, backend="compiled"), fn(*args, **kw, backend="reference")

    e, r = both(fd.rnea, model, q, v, a)
    assert_rel(e, r, f"{label}: rnea")
    e, r = both(fd.rnea, model, q, v, a, f_ext=f, gravity=False)
    assert_rel(e, r, f"{label}: rnea with f_ext, no gravity")
    assert_rel(*both(fd.nonlinear_effects, model, q, v), f"{label}: nonlinear_effects")
    assert_rel(*both(fd.generalized_gravity, model, q), f"{label}: generalized_gravity")
    M, M_ref = both(fd.crba, model, q)
    assert_rel(M, M_ref, f"{label}: crba")
    assert np.array_equal(M, np.swapaxes(M, -1, -2)), f"{label}: crba not exactly symmetric"
    try:
        ddq_ref = fd.aba(model, q, v, tau, f_ext=f, backend="reference")
    except fd.errors.SingularMassMatrixError as exc:
        joint = str(exc).split("'")[1]
        with pytest.raises(fd.errors.SingularMassMatrixError, match=joint):
            fd.aba(model, q, v, tau, f_ext=f, backend="compiled")
    else:
        assert_aba(fd.aba(model, q, v, tau, f_ext=f, backend="compiled"), ddq_ref, M_ref, f"{label}: aba")
    ke, kr = both(fd.forward_kinematics, model, q, v, a)
    for what, x, y in [
        ("placements.rotation", ke.placements.rotation, kr.placements.rotation),
        ("placements.translation", ke.placements.translation, kr.placements.translation),
        ("parent_placements.translation", ke.parent_placements.translation, kr.parent_placements.translation),
        ("velocities", ke.velocities.vector, kr.velocities.vector),
        ("accelerations", ke.accelerations.vector, kr.accelerations.vector),
    ]:
        assert_rel(x, y, f"{label}: forward_kinematics {what}")
    for fid in _frames(model):
        for ref in REFS:
            assert_rel(*both(fd.frame_jacobian, model, q, fid, ref),
                       f"{label}: frame_jacobian({model.frames[fid].name!r}, {ref.name})")


def _check_compiled(model: fd.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, tau: np.ndarray,
                    f: np.ndarray, label: str) -> None:
    """The single-state methods of ``fd.compile(model)`` against the reference."""
    cm = fd.compile(model, warmup=False)
    assert_rel(cm.rnea(q, v, a), fd.rnea(model, q, v, a, backend="reference"), f"{label}: compiled rnea")
    assert_rel(cm.rnea(q, v, a, f_ext=f), fd.rnea(model, q, v, a, f_ext=f, backend="reference"),
               f"{label}: compiled rnea f_ext")
    assert_rel(cm.nle(q, v), fd.nonlinear_effects(model, q, v, backend="reference"), f"{label}: compiled nle")
    assert_rel(cm.gravity(q), fd.generalized_gravity(model, q, backend="reference"), f"{label}: compiled gravity")
    assert_rel(cm.crba(q), fd.crba(model, q, backend="reference"), f"{label}: compiled crba")
    kin = fd.forward_kinematics(model, q, backend="reference")
    H = cm.fk(q)
    assert_rel(H[:, :3, :3], kin.placements.rotation, f"{label}: compiled fk rotation")
    assert_rel(H[:, :3, 3], kin.placements.translation, f"{label}: compiled fk translation")
    for fid in _frames(model):
        for ref in REFS:
            assert_rel(cm.frame_jacobian(q, fid, ref), fd.frame_jacobian(model, q, fid, ref, backend="reference"),
                       f"{label}: compiled frame_jacobian({fid}, {ref.name})")
    try:
        expected = fd.aba(model, q, v, tau, backend="reference")
    except fd.errors.SingularMassMatrixError:
        with pytest.raises(fd.errors.SingularMassMatrixError):
            cm.aba(q, v, tau)
    else:
        assert_aba(cm.aba(q, v, tau), expected, fd.crba(model, q, backend="reference"), f"{label}: compiled aba")


# ---------------------------------------------------------------------------
# every robot, fixed and floating
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("name", _robots())
def test_engine_matches_reference_on_every_robot(name: str, floating: bool) -> None:
    model = _robot(name, floating)
    if model is None:
        pytest.skip(f"{name} does not load")
    q, v, a, tau, f = _state(model, 3)
    _check_all(model, q, v, a, tau, f, f"{name} ({'floating' if floating else 'fixed'}) single")
    _check_compiled(model, q, v, a, tau, f, f"{name} ({'floating' if floating else 'fixed'})")
    qb, vb, ab, taub, fb = _state(model, 4, (3,))
    _check_all(model, qb, vb, ab, taub, fb, f"{name} ({'floating' if floating else 'fixed'}) batch (3,)")


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
@pytest.mark.parametrize("size", [(), (4,), (2, 3)], ids=lambda s: f"batch{s}".replace(" ", ""))
def test_engine_matches_reference_on_random_trees(spec, size) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 5, size)
    _check_all(model, st.q, st.v, st.a, st.tau, st.f_ext, f"{spec.name} batch{size}")
    if size == ():
        _check_compiled(model, st.q, st.v, st.a, st.tau, st.f_ext, spec.name)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_batched_equals_loop_of_single_calls(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 6, (5,))
    cm = fd.compile(model, warmup=False)
    tau = cm.rnea_batch(st.q, st.v, st.a)
    M = cm.crba_batch(st.q)
    ddq = cm.aba_batch(st.q, st.v, st.tau)
    H = cm.fk_batch(st.q)
    J = cm.frame_jacobian_batch(st.q, "b1_tool", fd.WORLD)
    for k in range(5):
        assert np.array_equal(tau[k], cm.rnea(st.q[k], st.v[k], st.a[k]))
        assert np.array_equal(M[k], cm.crba(st.q[k]))
        assert np.array_equal(ddq[k], cm.aba(st.q[k], st.v[k], st.tau[k]))
        assert np.array_equal(H[k], cm.fk(st.q[k]))
        assert np.array_equal(J[k], cm.frame_jacobian(st.q[k], "b1_tool", fd.WORLD))


def test_broadcasting_batch_axes() -> None:
    model = tree("free_branch")
    st = random_state(model, 7, (2, 3))
    q1 = st.q[0, 0]  # one configuration for every state
    f1 = st.f_ext[:1]  # (1, 3, nb, 6) broadcast along the first axis
    e = fd.rnea(model, q1, st.v, st.a[1], f_ext=f1)
    r = fd.rnea(model, q1, st.v, st.a[1], f_ext=f1, backend="reference")
    assert e.shape == (2, 3, model.nv)
    assert_rel(e, r, "broadcast rnea")
    e = fd.aba(model, st.q[:, :1], st.v, st.tau, f_ext=f1)
    assert_rel(e, fd.aba(model, st.q[:, :1], st.v, st.tau, f_ext=f1, backend="reference"), "broadcast aba", 1e-10)
    kin = fd.forward_kinematics(model, q1, st.v)
    assert kin.placements.rotation.shape == (2, 3, model.nbodies, 3, 3)
    assert_rel(kin.velocities.vector, fd.forward_kinematics(model, q1, st.v, backend="reference").velocities.vector,
               "broadcast fk")
    empty = fd.rnea(model, np.zeros((0, model.nq)), np.zeros((0, model.nv)), np.zeros((0, model.nv)))
    assert empty.shape == (0, model.nv)


# ---------------------------------------------------------------------------
# input handling and errors
# ---------------------------------------------------------------------------


def test_dtype_routing() -> None:
    model = tree("fixed_branch_mixed")
    st = random_state(model, 8, (3,))
    expected = fd.rnea(model, st.q, st.v, st.a, backend="reference")
    # non-contiguous float64 (every other column of a wider array, Fortran order)
    wide = np.zeros((3, 2 * model.nq))
    wide[:, ::2] = st.q
    assert_rel(fd.rnea(model, wide[:, ::2], np.asfortranarray(st.v), st.a), expected, "non-contiguous rnea")
    # integers become float64 and go to the engine (the neutral configuration is integral here)
    qn = np.asarray(fd.neutral(model)).astype(np.int64)
    vi = np.ones((2, model.nv), dtype=np.int32)
    out = fd.rnea(model, qn, vi, vi)
    assert out.dtype == np.float64
    assert_rel(out, fd.rnea(model, qn.astype(float), vi.astype(float), vi.astype(float), backend="reference"), "int")
    # float32 stays on the reference by default (float32 out); forcing the engine computes in float64, returns float32
    q32, v32, a32 = (x.astype(np.float32) for x in (st.q, st.v, st.a))
    r32 = fd.rnea(model, q32, v32, a32)
    c32 = fd.rnea(model, q32, v32, a32, backend="compiled")
    assert r32.dtype == np.float32 and c32.dtype == np.float32
    np.testing.assert_allclose(c32, fd.rnea(model, q32.astype(float), v32.astype(float), a32.astype(float)),
                               rtol=1e-6, atol=1e-5)
    M32 = fd.crba(model, q32, backend="compiled")
    assert M32.dtype == np.float32
    kin32 = fd.forward_kinematics(model, q32, v32, backend="compiled")
    assert kin32.placements.rotation.dtype == np.float32 and kin32.velocities.vector.dtype == np.float32
    # object arrays of numbers can be forced through the engine; symbols cannot
    qo = st.q[0].astype(object)
    assert_rel(fd.rnea(model, qo, st.v[0], st.a[0], backend="compiled"), expected[0], "object numbers")
    sympy = pytest.importorskip("sympy")
    qs = np.array([sympy.Symbol(f"q{i}") for i in range(model.nq)], dtype=object)
    with pytest.raises(BackendError, match="float64"):
        fd.crba(model, qs, backend="compiled")
    with pytest.raises(BackendError, match="backend"):
        fd.rnea(model, st.q, st.v, st.a, backend="fast")


def test_backend_selection(monkeypatch: pytest.MonkeyPatch) -> None:
    from featherdyn.api._backend import select_backend
    from featherdyn.engine import _dispatch

    f64, f32, obj = np.dtype(np.float64), np.dtype(np.float32), np.dtype(object)
    assert select_backend(None, f64) == "compiled"
    assert select_backend(None, f32) == select_backend(None, obj) == "reference"
    assert select_backend("reference", f64) == "reference"
    assert select_backend("compiled", f32) == "compiled"
    model = tree("revolute_chain")
    st = random_state(model, 12, (3,))
    calls: list[str] = []
    original = _dispatch.rnea
    monkeypatch.setattr(_dispatch, "rnea", lambda *a, **k: calls.append("batch") or original(*a, **k))
    import featherdyn.api.dynamics as api_dynamics

    core = api_dynamics.CORE

    class LoggedCore:
        """The compiled core, logging a one-state RNEA it accepted."""

        def __getattr__(self, name: str) -> object:
            return getattr(core, name)

        def rnea(self, *args: object) -> int:
            status = core.rnea(*args)
            if status == 0:
                calls.append("one")
            return int(status)

    monkeypatch.setattr(api_dynamics, "CORE", LoggedCore())
    try:
        fd.rnea(model, st.q, st.v, st.a)  # a batch: the general engine path
        fd.rnea(model, st.q[0], st.v[0], st.a[0])  # one float64 state: the compiled core
        fd.rnea(model, st.q.astype(np.float32), st.v, st.a)  # promoted to float64 by v, a: compiled
        fd.rnea(model, st.q, st.v, st.a, backend="reference")
        assert calls == ["batch", "one", "batch"]
        fd.set_default_backend("reference")
        assert fd.default_backend() == "reference"
        assert select_backend(None, f64) == "reference"
        fd.rnea(model, st.q, st.v, st.a)
        fd.rnea(model, st.q[0], st.v[0], st.a[0])
        assert calls == ["batch", "one", "batch"]
        with pytest.raises(BackendError, match="backend"):
            fd.set_default_backend("fast")
    finally:
        fd.set_default_backend(None)
    assert select_backend(None, f64) == "compiled"


def test_backend_environment_variable() -> None:
    """``FEATHERDYN_BACKEND=reference`` at import makes the reference the default."""
    import os
    import subprocess
    import sys

    code = ("import featherdyn as fd; from featherdyn.api._backend import select_backend; import numpy as np; "
            "print(fd.default_backend(), select_backend(None, np.dtype(np.float64)))")
    env = {**os.environ, "FEATHERDYN_BACKEND": "reference"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["reference", "reference"]


def test_reference_input_errors_still_raised() -> None:
    model = tree("free_chain")
    st = random_state(model, 9)
    with pytest.raises(fd.ShapeError, match="nq"):
        fd.rnea(model, st.q[:-1], st.v, st.a)
    with pytest.raises(fd.ShapeError, match="nv"):
        fd.aba(model, st.q, st.v[:-1], st.tau)
    bad = st.q.copy()
    bad[0] = np.nan
    with pytest.raises(fd.NonFiniteError):
        fd.rnea(model, bad, st.v, st.a)
    q = st.q.copy()
    q[3:7] *= 1.01  # free-flyer quaternion off unit norm
    with pytest.raises(fd.QuaternionNormError, match="quaternion"):
        fd.crba(model, q)
    with pytest.raises(fd.ShapeError, match="f_ext"):
        fd.rnea(model, st.q, st.v, st.a, f_ext=np.zeros((model.nbodies, 3)))
    with pytest.raises(fd.ModelError, match="not found"):
        fd.frame_jacobian(model, st.q, "no_such_frame")
    with pytest.raises(fd.ShapeError, match="reference"):
        fd.frame_jacobian(model, st.q, 0, "sideways")
    with pytest.raises(fd.DTypeError):
        fd.rnea(model, st.q.astype(complex), st.v, st.a)


def test_compiled_model_input_handling() -> None:
    model = tree("fixed_chain_mixed")
    st = random_state(model, 10)
    cm = fd.compile(model)
    expected = fd.rnea(model, st.q, st.v, st.a, backend="reference")
    assert_rel(cm.rnea(list(st.q), st.v, st.a), expected, "list input")
    v32 = st.v.astype(np.float32)  # converted to float64 (not computed in float32)
    assert_rel(cm.rnea(st.q, v32, st.a), fd.rnea(model, st.q, v32.astype(float), st.a, backend="reference"),
               "float32 input")
    q_ro = st.q.copy()
    q_ro.flags.writeable = False
    assert_rel(cm.rnea(q_ro, st.v, st.a), expected, "read-only input")
    wide = np.zeros(2 * model.nq)
    wide[::2] = st.q
    assert_rel(cm.rnea(wide[::2], st.v, st.a), expected, "strided input")
    out = np.empty(model.nv)
    assert cm.rnea(st.q, st.v, st.a, out=out) is out
    with pytest.raises(fd.ShapeError, match="q: expected shape"):
        cm.rnea(st.q[:-1], st.v, st.a)
    with pytest.raises(fd.ShapeError, match="out"):
        cm.crba(st.q, out=np.empty((model.nv, model.nv + 1)))
    with pytest.raises(TypeError, match="out"):
        cm.rnea(st.q, st.v, st.a, out=np.empty(model.nv, dtype=np.float32))
    with pytest.raises(fd.ModelError):
        cm.frame_jacobian(st.q, "nope")
    with pytest.raises(fd.ModelError):
        cm.frame_jacobian(st.q, len(model.frames))
    assert_rel(cm.frame_jacobian(st.q, "b2_tool", "world"),
               fd.frame_jacobian(model, st.q, "b2_tool", fd.WORLD, backend="reference"), "string reference")
    with pytest.raises(fd.ModelError):
        fd.compile("panda")  # type: ignore[arg-type]


# ---------------------------------------------------------------------------
# the singular mass matrix
# ---------------------------------------------------------------------------


def _massless_leaf_model() -> fd.Model:
    b = fd.ModelBuilder("massless_leaf")
    inertia = fd.SpatialInertia(1.0, [0.1, 0.0, 0.0], np.diag([0.1, 0.2, 0.3]))
    b.add_body("base", -1, fd.RevoluteJoint([0, 0, 1]), inertia=inertia)
    b.add_body("arm", 0, fd.RevoluteJoint([0, 1, 0]), inertia=inertia, joint_name="shoulder",
               placement=fd.PluckerTransform(np.eye(3), [0.5, 0, 0]))
    b.add_body("tip", 1, fd.PrismaticJoint([1, 0, 0]), joint_name="slider")  # no mass at all
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return b.build()


def test_singular_mass_matrix_names_the_joint() -> None:
    model = _massless_leaf_model()
    q, v, tau = np.array([0.1, 0.2, 0.3]), np.zeros(3), np.ones(3)
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'slider'"):
        fd.aba(model, q, v, tau, backend="reference")
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'slider'"):
        fd.aba(model, q, v, tau)
    with pytest.raises(fd.errors.SingularMassMatrixError, match=r"'slider'.*batch index \(0,\)"):
        fd.aba(model, np.stack([q, q]), v, tau)
    cm = fd.compile(model)
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'slider'"):
        cm.aba(q, v, tau)
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'slider'"):
        cm.aba_batch(np.stack([q, q]), v, tau)
    # the other algorithms do not care
    assert np.all(np.isfinite(fd.rnea(model, q, v, tau)))
    assert np.linalg.matrix_rank(fd.crba(model, q)) == 2


# ---------------------------------------------------------------------------
# against Pinocchio
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "floating"), SPOT_ROBOTS, ids=[n for n, _ in SPOT_ROBOTS])
def test_engine_matches_pinocchio(pin, name: str, floating: bool) -> None:  # type: ignore[no-untyped-def]
    from featherdyn.verify.bridge import JointMap, from_pin6_rows

    model = _robot(name, floating)
    if model is None:
        pytest.skip(f"{name} does not load")
    path = str(fd.robots.robot_path(name))
    pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    pdata = pm.createData()
    jm = JointMap(model, pm)
    cm = fd.compile(model)
    for seed in range(3):
        q, v, a, tau, _ = _state(model, 100 + seed)
        qp, vp, ap, tp = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a), jm.v_to_pin(tau)
        assert_rel(cm.rnea(q, v, a), jm.v_from_pin(pin.rnea(pm, pdata, qp, vp, ap)), f"{name}: rnea", 1e-10)
        assert_rel(fd.rnea(model, q, v, a), jm.v_from_pin(pin.rnea(pm, pdata, qp, vp, ap)), f"{name}: fd.rnea",
                   1e-10)
        assert_rel(cm.crba(q), jm.matrix_from_pin(pin.crba(pm, pdata, qp)), f"{name}: crba", 1e-10)
        assert_rel(cm.aba(q, v, tau), jm.v_from_pin(pin.aba(pm, pdata, qp, vp, tp)), f"{name}: aba", 1e-8)
        pin.forwardKinematics(pm, pdata, qp)
        H = cm.fk(q)
        for i, body in enumerate(model.body_names):
            oMf = pdata.oMf[pm.getFrameId(body)] if pm.existFrame(body) else None
            if oMf is None:
                continue
            pin.updateFramePlacements(pm, pdata)
            oMf = pdata.oMf[pm.getFrameId(body)]
            assert_rel(H[i, :3, :3], oMf.rotation, f"{name}: placement rotation of {body}", 1e-10)
            assert_rel(H[i, :3, 3], oMf.translation, f"{name}: placement of {body}", 1e-10)
        frame = model.frames[-1].name
        fid = pm.getFrameId(frame)
        for ref, pref in [(fd.LOCAL, pin.LOCAL), (fd.WORLD, pin.WORLD),
                          (fd.LOCAL_WORLD_ALIGNED, pin.LOCAL_WORLD_ALIGNED)]:
            J_pin = jm.columns_from_pin(from_pin6_rows(pin.computeFrameJacobian(pm, pdata, qp, fid, pref)))
            assert_rel(cm.frame_jacobian(q, frame, ref), J_pin, f"{name}: frame_jacobian {ref.name}", 1e-10)


# ---------------------------------------------------------------------------
# import and memory
# ---------------------------------------------------------------------------


def _run(code: str, **env: str) -> str:
    src = Path(__file__).resolve().parents[2] / "src"
    full_env = {**os.environ, "PYTHONPATH": f"{src}{os.pathsep}{os.environ.get('PYTHONPATH', '')}", **env}
    res = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=full_env,
                         timeout=600, check=False)
    assert res.returncode == 0, res.stderr
    return res.stdout


def test_import_compiles_nothing() -> None:
    out = _run("""
        import sys
        import featherdyn as fd
        print("numba" in sys.modules, "featherdyn.engine._kernels" in sys.modules)
    """)
    assert out.split() == ["False", "False"]


def test_batched_call_allocates_outputs_and_workspaces_only() -> None:
    out = _run("""
        import numpy as np, numba, warnings
        warnings.simplefilter("ignore")
        from numba.core.runtime import rtsys
        import featherdyn as fd
        b = fd.ModelBuilder("chain")
        for i in range(12):
            b.add_body(f"b{i}", i - 1, fd.RevoluteJoint([0, 0, 1]), inertia=fd.SpatialInertia(1.0, [0.1, 0, 0],
                       np.eye(3) * 0.01), placement=fd.PluckerTransform(np.eye(3), [0.2, 0, 0]))
        m = b.build()
        cm = fd.compile(m)
        for N in (10, 5000):
            Q, V = np.random.rand(N, m.nq), np.random.rand(N, m.nv)
            counts = []
            for fn in (lambda: cm.rnea_batch(Q, V, V), lambda: cm.aba_batch(Q, V, V), lambda: cm.crba_batch(Q),
                       lambda: cm.fk_batch(Q)):
                fn()  # load the kernels
                s0 = rtsys.get_allocation_stats()
                fn()
                counts.append(rtsys.get_allocation_stats().alloc - s0.alloc)
            print(N, numba.get_num_threads(), *counts)
    """, NUMBA_NRT_STATS="1")
    lines = [[int(x) for x in line.split()] for line in out.strip().splitlines()]
    (n1, threads, *small), (n2, _, *large) = lines
    # a fixed number of Numba allocations per call (parfor bookkeeping, one workspace per thread) —
    # the same for 10 states as for 5000: nothing is allocated per state
    assert small == large, f"Numba allocations per batched call: {small} for {n1} states, {large} for {n2}"
    assert max(large) <= 4 * threads + 8, f"{large} Numba allocations per call on {threads} threads"


def test_bench_runs(pin, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    """``featherdyn bench`` end to end on tiny settings (a smoke test: speed is measured in benchmarks/, not here)."""
    from featherdyn.cli import main

    out = tmp_path / "bench.md"
    code = main(["bench", "panda", "--repeats", "1", "--batch", "4", "--chains", "8", "--no-compile-times",
                 "--output", str(out)])
    assert code == 0
    text = out.read_text(encoding="utf-8")
    for heading in ("Single calls", "Batched throughput", "Scaling over revolute chains"):
        assert heading in text
    assert "| panda nv=9 | RNEA |" in text
    assert "featherdyn compiled engine vs Pinocchio" in capsys.readouterr().out
