"""The declared derivatives ``fd.generalized_gravity_derivatives`` and ``fd.static_torque_derivatives``.

Against Pinocchio 4.1's ``computeGeneralizedGravityDerivatives`` / ``computeStaticTorqueDerivatives``
(joints mapped by name, the free-flyer's ``[v; ω]`` converted, forces in the joints' LOCAL frames), against
central finite differences along ``fd.integrate``'s tangent, and through every front end the declaration
makes: one state, batches of any shape (equal to a loop bit for bit), ``out=`` (an ``out`` sharing memory
with ``q`` gives the same result), ``fd.compile(model)``'s method, float32, and bad input.
"""

from __future__ import annotations

import numpy as np
import pytest
from _models import library_robot, pinocchio_pair

import featherdyn as fd
from featherdyn.api.declarations import DECLARATIONS
from featherdyn.errors import NonFiniteError, QuaternionNormError, ShapeError

pin = pytest.importorskip("pinocchio")

PAIRS = [("panda", False), ("solo12", True), ("ur5_robot", False), ("anymal-kinova", True), ("talos_full_v2", True)]


_pin_pair = pinocchio_pair


def _pin_forces(model: fd.Model, pm, f_ext: np.ndarray) -> list:  # type: ignore[no-untyped-def]
    """featherdyn body-frame forces ``[n; f]`` `(nb, 6)` → Pinocchio's joint-frame forces ``[f; n]`` (0: universe)."""
    out = [pin.Force.Zero() for _ in range(pm.njoints)]
    for i, name in enumerate(model.joint_names):
        out[pm.getJointId(name)] = pin.Force(np.concatenate([f_ext[i, 3:], f_ext[i, :3]]))
    return out


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize("backend", [None, "reference"])
@pytest.mark.parametrize(("name", "floating"), PAIRS)
def test_against_pinocchio(name: str, floating: bool, backend: str | None) -> None:
    model, pm, pd, jm = _pin_pair(name, floating)
    rng = np.random.default_rng(5)
    q = fd.random_configuration(model, rng)
    f_ext = rng.normal(size=(model.nbodies, 6))
    qp = jm.q_to_pin(q)
    dg = fd.generalized_gravity_derivatives(model, q, backend=backend)
    dg_pin = jm.matrix_from_pin(pin.computeGeneralizedGravityDerivatives(pm, pd, qp).copy())
    assert _rel(dg, dg_pin) < 1e-12, (name, _rel(dg, dg_pin))
    ds = fd.static_torque_derivatives(model, q, f_ext, backend=backend)
    ds_pin = jm.matrix_from_pin(pin.computeStaticTorqueDerivatives(pm, pd, qp, _pin_forces(model, pm, f_ext)).copy())
    assert _rel(ds, ds_pin) < 1e-12, (name, _rel(ds, ds_pin))
    # and not merely the gravity part: the forces change the result
    assert _rel(ds, dg) > 1e-6


@pytest.mark.parametrize(("name", "floating"), [("solo12", True), ("panda", False)])
def test_finite_differences_on_the_group(name: str, floating: bool) -> None:
    model = library_robot(name, floating)
    assert model is not None
    rng = np.random.default_rng(8)
    q = fd.random_configuration(model, rng)
    f_ext = rng.normal(size=(model.nbodies, 6))
    zero = np.zeros(model.nv)
    eps = 1e-6
    dg = fd.generalized_gravity_derivatives(model, q)
    ds = fd.static_torque_derivatives(model, q, f_ext)
    for j in range(model.nv):
        step = np.zeros(model.nv)
        step[j] = eps
        qp, qm = fd.integrate(model, q, step), fd.integrate(model, q, -step)
        fd_g = (fd.generalized_gravity(model, qp) - fd.generalized_gravity(model, qm)) / (2 * eps)
        fd_s = (fd.rnea(model, qp, zero, zero, f_ext) - fd.rnea(model, qm, zero, zero, f_ext)) / (2 * eps)
        assert np.abs(dg[:, j] - fd_g).max() < 1e-6 * max(1.0, np.abs(dg).max()), j
        assert np.abs(ds[:, j] - fd_s).max() < 1e-6 * max(1.0, np.abs(ds).max()), j


def _args(model: fd.Model, name: str, q: np.ndarray, f_ext: np.ndarray) -> tuple[np.ndarray, ...]:
    return (q,) if DECLARATIONS[name].inputs == ("q",) else (q, f_ext)


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_front_ends(name: str) -> None:
    model = library_robot("solo12", True)
    assert model is not None
    fn = getattr(fd, name)
    rng = np.random.default_rng(3)
    Q = fd.random_configuration(model, rng, size=(2, 3))
    FX = rng.normal(size=(2, 3, model.nbodies, 6))
    nv = model.nv
    # a batch of any shape equals the loop over its states, bit for bit (f_ext broadcast as well)
    batch = fn(model, *_args(model, name, Q, FX))
    assert batch.shape == (2, 3, nv, nv)
    for i in range(2):
        for k in range(3):
            assert np.array_equal(batch[i, k], fn(model, *_args(model, name, Q[i, k], FX[i, k])))
    one = fn(model, *_args(model, name, Q[0, 0], FX[0, 0]))
    # the reference agrees with the core
    ref = fn(model, *_args(model, name, Q[0, 0], FX[0, 0]), backend="reference")
    assert _rel(ref, one) < 1e-12
    # out=: written and returned, in one state and in a batch
    out = np.full((nv, nv), np.nan)
    assert fn(model, *_args(model, name, Q[0, 0], FX[0, 0]), out=out) is out and np.array_equal(out, one)
    outs = np.full((2, 3, nv, nv), np.nan)
    assert fn(model, *_args(model, name, Q, FX), out=outs) is outs and np.array_equal(outs, batch)
    # an out sharing memory with q: the same result as without it (one rule: computed, then written)
    buf = np.zeros(nv * nv + model.nq)
    buf[:model.nq] = Q[0, 0]
    shared = buf[model.nq - 3: model.nq - 3 + nv * nv].reshape(nv, nv)
    r = fn(model, *_args(model, name, buf[:model.nq], FX[0, 0]), out=shared)
    assert r is shared and np.array_equal(shared, one)
    # fd.compile(model)'s method, with and without out=
    cm = fd.compile(model, warmup=False)
    method = getattr(cm, name)
    assert np.array_equal(method(*_args(model, name, Q[0, 0], FX[0, 0])), one)
    out2 = np.empty((nv, nv))
    assert method(*_args(model, name, Q[0, 0], FX[0, 0]), out=out2) is out2 and np.array_equal(out2, one)
    # dtypes: native float64 spelled any way takes the same path; float32 stays float32
    for dt in ("<f8", "=f8", "d", np.dtype("f8").newbyteorder("=")):
        assert np.array_equal(fn(model, *_args(model, name, Q[0, 0].astype(dt), FX[0, 0].astype(dt))), one)
    assert np.array_equal(fn(model, *_args(model, name, Q[0, 0].astype(">f8"), FX[0, 0])), one)
    r32 = fn(model, *_args(model, name, Q[0, 0].astype(np.float32), FX[0, 0].astype(np.float32)))
    assert r32.dtype == np.float32 and _rel(r32, one) < 1e-3
    assert np.array_equal(fn(model, *_args(model, name, list(Q[0, 0]), FX[0, 0].tolist())), one)


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_bad_input(name: str) -> None:
    model = library_robot("solo12", True)
    assert model is not None
    fn = getattr(fd, name)
    rng = np.random.default_rng(4)
    q = fd.random_configuration(model, rng)
    fx = rng.normal(size=(model.nbodies, 6))
    with pytest.raises(ShapeError, match="q: expected trailing dimension nq=19"):
        fn(model, *_args(model, name, q[:5], fx))
    bad = q.copy()
    bad[2] = np.nan
    with pytest.raises(NonFiniteError, match="q"):
        fn(model, *_args(model, name, bad, fx))
    bad = q.copy()
    bad[3:7] *= 2
    with pytest.raises(QuaternionNormError):
        fn(model, *_args(model, name, bad, fx))
    with pytest.raises(ShapeError, match="out: expected shape"):
        fn(model, *_args(model, name, q, fx), out=np.empty((3, 3)))
    ro = np.empty((model.nv, model.nv))
    ro.setflags(write=False)
    with pytest.raises(ShapeError, match="read-only"):
        fn(model, *_args(model, name, q, fx), out=ro)
    with pytest.raises(ShapeError, match="out"):
        fn(model, *_args(model, name, q, fx), out=[1, 2])
    with pytest.raises(TypeError, match=name):
        fn(model, *_args(model, name, q, fx), frame="x")
    with pytest.raises(ShapeError, match="model"):
        fn("panda", *_args(model, name, q, fx))
    if "f_ext" in DECLARATIONS[name].inputs:
        with pytest.raises(ShapeError, match="f_ext"):
            fn(model, q, None)
        with pytest.raises(ShapeError, match="f_ext"):
            fn(model, q, fx[:3])
        bad_f = fx.copy()
        bad_f[1, 4] = np.inf
        with pytest.raises(NonFiniteError, match="f_ext"):
            fn(model, q, bad_f)


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_compiled_method_with_dask_arrays(name: str) -> None:
    """fd.compile(model)'s declared method takes Dask arrays as the public function does (the same blocks)."""
    da = pytest.importorskip("dask.array")
    model = library_robot("panda", False)
    assert model is not None
    rng = np.random.default_rng(6)
    Q = fd.random_configuration(model, rng, size=(4,))
    FX = rng.normal(size=(4, model.nbodies, 6))
    expected = getattr(fd, name)(model, *_args(model, name, Q, FX))
    lazy = getattr(fd.compile(model, warmup=False), name)(*_args(model, name, da.from_array(Q, chunks=(2, -1)), FX))
    assert type(lazy).__module__.startswith("dask")
    assert np.array_equal(lazy.compute(scheduler="sync"), expected)
