"""Dask arrays in, Dask arrays out (``featherdyn/_dask.py``): lazy, bit for bit equal to NumPy, one model key.

Oracle: the same public function called on the NumPy arrays the Dask arrays
hold. Equality is exact (``np.array_equal``): every block runs the same
batched code on the same states.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.api import declarations
from featherdyn.api.declarations import DECLARATIONS
import featherdyn._dask

da = pytest.importorskip("dask.array")  # a test dependency: installed by the `test` extra, so this runs in CI
import dask  # noqa: E402

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


@pytest.fixture(scope="module")
def panda() -> fd.Model:
    return fd.load_robot("panda")


@pytest.fixture(scope="module")
def solo() -> fd.Model:
    return fd.load_robot("solo12", floating_base=True)


def _states(model: fd.Model, batch: tuple[int, ...], seed: int = 0) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng, batch)
    return {"q": q, "v": rng.standard_normal(batch + (model.nv,)), "a": rng.standard_normal(batch + (model.nv,)),
            "tau": rng.standard_normal(batch + (model.nv,)),
            "f_ext": rng.standard_normal(batch + (model.nbodies, 6)),
            "q0": q, "q1": fd.random_configuration(model, rng, batch), "w": rng.standard_normal(batch + (model.nv,)),
            "W": rng.standard_normal(batch + (model.nv, model.nv)),  # (fd.difference's configurations)
            "point": rng.standard_normal(batch + (3,))}  # (fd.kinematics_derivatives' point in the frame)


def _lazy(x: np.ndarray, chunks: int) -> Any:
    """``x`` as a Dask array chunked along its first (batch) axis only."""
    return da.from_array(x, chunks=(chunks,) + (-1,) * (x.ndim - 1))


def _arrays(result: Any) -> list[Any]:
    """The arrays of a result in a fixed order (plain, tuple, record, spatial object)."""
    if result is None or isinstance(result, (str, int, float, fd.Model, fd.ReferenceFrame)):
        return []
    if isinstance(result, (np.ndarray, np.generic)) or type(result).__module__.startswith("dask"):
        return [result]
    if isinstance(result, (tuple, list)):
        return [x for item in result for x in _arrays(item)]
    fields = getattr(type(result), "FIELDS", None) or getattr(result, "__dataclass_fields__", None)
    assert fields is not None, type(result)
    return [x for name in fields for x in _arrays(getattr(result, name))]


def _end(model: fd.Model) -> str:
    return model.frames[-1].name


# (name, function of (model, states dict, frame) -> result): every batched public function
CALLS: list[tuple[str, Callable[..., Any]]] = [
    ("rnea", lambda m, s, f: fd.rnea(m, s["q"], s["v"], s["a"])),
    ("rnea_fext_nograv", lambda m, s, f: fd.rnea(m, s["q"], s["v"], s["a"], s["f_ext"], gravity=False)),
    ("nonlinear_effects", lambda m, s, f: fd.nonlinear_effects(m, s["q"], s["v"])),
    ("generalized_gravity", lambda m, s, f: fd.generalized_gravity(m, s["q"])),
    ("crba", lambda m, s, f: fd.crba(m, s["q"])),
    ("aba", lambda m, s, f: fd.aba(m, s["q"], s["v"], s["tau"], s["f_ext"])),
    ("coriolis_matrix", lambda m, s, f: fd.coriolis_matrix(m, s["q"], s["v"])),
    ("forward_kinematics", lambda m, s, f: fd.forward_kinematics(m, s["q"], s["v"], s["a"])),
    ("frame_placement", lambda m, s, f: fd.frame_placement(m, s["q"], f)),
    ("frame_velocity", lambda m, s, f: fd.frame_velocity(m, s["q"], s["v"], f, fd.WORLD)),
    ("frame_acceleration", lambda m, s, f: fd.frame_acceleration(m, s["q"], s["v"], s["a"], f, fd.LOCAL)),
    ("frame_classical_acceleration",
     lambda m, s, f: fd.frame_classical_acceleration(m, s["q"], s["v"], s["a"], f, fd.LOCAL_WORLD_ALIGNED)),
    ("joint_jacobians", lambda m, s, f: fd.joint_jacobians(m, s["q"])),
    ("frame_jacobian", lambda m, s, f: fd.frame_jacobian(m, s["q"], f, fd.LOCAL_WORLD_ALIGNED)),
    ("frame_jacobian_time_variation", lambda m, s, f: fd.frame_jacobian_time_variation(m, s["q"], s["v"], f, fd.WORLD)),
    ("kinetic_energy", lambda m, s, f: fd.kinetic_energy(m, s["q"], s["v"])),
    ("potential_energy", lambda m, s, f: fd.potential_energy(m, s["q"])),
    ("center_of_mass", lambda m, s, f: fd.center_of_mass(m, s["q"])),
    ("center_of_mass_v", lambda m, s, f: fd.center_of_mass(m, s["q"], s["v"])),
    ("centroidal_momentum_matrix", lambda m, s, f: fd.centroidal_momentum_matrix(m, s["q"])),
    ("centroidal_momentum", lambda m, s, f: fd.centroidal_momentum(m, s["q"], s["v"])),
    ("rnea_derivatives", lambda m, s, f: fd.rnea_derivatives(m, s["q"], s["v"], s["a"], s["f_ext"])),
    ("aba_derivatives", lambda m, s, f: fd.aba_derivatives(m, s["q"], s["v"], s["tau"])),
    ("mass_matrix_inverse", lambda m, s, f: fd.mass_matrix_inverse(m, s["q"])),
    ("frame_velocity_derivatives", lambda m, s, f: fd.frame_velocity_derivatives(m, s["q"], s["v"], f)),
    ("frame_acceleration_derivatives",
     lambda m, s, f: fd.frame_acceleration_derivatives(m, s["q"], s["v"], s["a"], f, reference=fd.WORLD)),
    ("joint_torque_regressor", lambda m, s, f: fd.joint_torque_regressor(m, s["q"], s["v"], s["a"])),
    # every declared algorithm (api/declarations.py), with its declared state arguments (by name: a point comes
    # after the frame)
    *[(d.name, lambda m, s, f, d=d: getattr(declarations, d.name)(m, **{n: s[n] for n in d.inputs},
                                                        **({"frame": f} if "frame" in d.options else {})))
      for d in DECLARATIONS.values()],
    ("integrate", lambda m, s, f: fd.integrate(m, s["q"], s["v"])),
    ("difference", lambda m, s, f: fd.difference(m, s["q"], fd.integrate(m, s["q"], s["a"]))),
    ("integrate_derivatives", lambda m, s, f: fd.integrate_derivatives(m, s["q"], s["v"])),
    ("difference_derivatives", lambda m, s, f: fd.difference_derivatives(m, s["q"], fd.integrate(m, s["q"], s["v"]))),
    ("operational_space_inertia", lambda m, s, f: fd.operational_space_inertia(m, s["q"], f)),
    ("operational_space", lambda m, s, f: fd.operational_space(m, s["q"], s["v"], f)),
]

CONSTRAINT_CALLS: list[tuple[str, Callable[..., Any]]] = [
    ("constraint_jacobian", lambda m, s, c: fd.constraint_jacobian(m, s["q"], c)),
    ("constraint_drift", lambda m, s, c: fd.constraint_drift(m, s["q"], s["v"], c)),
    ("delassus", lambda m, s, c: fd.delassus(m, s["q"], c)),
    ("constrained_dynamics", lambda m, s, c: fd.constrained_dynamics(m, s["q"], s["v"], s["tau"], c)),
    ("impulse_dynamics", lambda m, s, c: fd.impulse_dynamics(m, s["q"], s["v"], c, restitution=0.5)),
]


def _compare(expected: Any, result: Any) -> None:
    lazy_arrays = _arrays(result)
    assert lazy_arrays, "a result without arrays"
    assert all(type(x).__module__.startswith("dask") for x in lazy_arrays), [type(x) for x in lazy_arrays]
    if not isinstance(expected, np.ndarray):
        assert type(result) is type(expected)
    computed = dask.compute(*lazy_arrays, scheduler="sync")
    wanted = _arrays(expected)
    assert len(computed) == len(wanted)
    for got, want in zip(computed, wanted, strict=True):
        assert got.shape == want.shape and got.dtype == want.dtype
        assert np.array_equal(got, want), float(np.max(np.abs(got - want)))


@pytest.mark.parametrize("name,call", CALLS, ids=[c[0] for c in CALLS])
@pytest.mark.parametrize("robot", ["panda", "solo"])
def test_every_batched_function_equals_numpy_bit_for_bit(name: str, call: Callable[..., Any], robot: str,
                                                          request: pytest.FixtureRequest) -> None:
    model = request.getfixturevalue(robot)
    states = _states(model, (23,))
    lazy = {k: _lazy(x, 7) for k, x in states.items()}  # 7 + 7 + 7 + 2: an uneven last block
    _compare(call(model, states, _end(model)), call(model, lazy, _end(model)))


@pytest.mark.parametrize("name,call", CONSTRAINT_CALLS, ids=[c[0] for c in CONSTRAINT_CALLS])
def test_constraint_functions_equal_numpy(name: str, call: Callable[..., Any], solo: fd.Model) -> None:
    states = _states(solo, (11,), seed=3)
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET[:3]] + [fd.FrameContact(FEET[3])]
    lazy = {k: _lazy(x, 4) for k, x in states.items()}
    _compare(call(solo, states, cons), call(solo, lazy, cons))


def test_two_batch_axes_mixed_with_numpy_and_broadcast(panda: fd.Model) -> None:
    s = _states(panda, (6, 5), seed=1)
    q = da.from_array(s["q"], chunks=(4, 2, -1))
    v = s["v"][0]                       # NumPy (5, nv): broadcast over the first batch axis
    a = da.from_array(s["a"][0, 0], chunks=-1)   # one state, a Dask array
    tau = fd.rnea(panda, q, v, a)
    assert tau.shape == (6, 5, panda.nv)
    assert np.array_equal(tau.compute(), fd.rnea(panda, s["q"], v, s["a"][0, 0]))


def test_float32_stays_float32(panda: fd.Model) -> None:
    s = _states(panda, (8,))
    q32, v32 = s["q"].astype(np.float32), s["v"].astype(np.float32)
    h = fd.nonlinear_effects(panda, _lazy(q32, 3), _lazy(v32, 3))
    assert h.dtype == np.float32
    assert np.array_equal(h.compute(), fd.nonlinear_effects(panda, q32, v32))


def test_one_state_dask_array(panda: fd.Model) -> None:
    s = _states(panda, ())
    M = fd.crba(panda, da.from_array(s["q"]))
    assert M.shape == (panda.nv, panda.nv)
    assert np.array_equal(M.compute(), fd.crba(panda, s["q"]))


def test_the_call_is_lazy(panda: fd.Model) -> None:
    """Nothing is computed when the function returns; each block is computed once when asked."""
    calls: list[int] = []
    q_np = _states(panda, (12,))["q"]

    def source(block: np.ndarray) -> np.ndarray:
        calls.append(block.shape[0])
        return block

    q = _lazy(q_np, 4).map_blocks(source, dtype=q_np.dtype, meta=np.empty((0, 0)))
    g = fd.generalized_gravity(panda, q)
    assert calls == []
    assert np.array_equal(g.compute(scheduler="sync"), fd.generalized_gravity(panda, q_np))
    assert sorted(calls) == [4, 4, 4]


def test_the_model_is_one_key_of_the_graph(panda: fd.Model) -> None:
    s = _states(panda, (40,))
    tau = fd.rnea(panda, _lazy(s["q"], 5), _lazy(s["v"], 5), _lazy(s["a"], 5))
    graph = dict(tau.__dask_graph__())
    model_keys = [k for k in graph if str(k).startswith("featherdyn-model-")]
    assert len(model_keys) == 1
    assert graph[model_keys[0]] is panda or getattr(graph[model_keys[0]], "value", None) is panda  # the object itself
    # every one of the 8 block tasks refers to that key, none holds a copy of the model
    blocks = [k for k in graph if isinstance(k, tuple) and str(k[0]).startswith("featherdyn-rnea-")]
    assert len(blocks) == 8
    for k in blocks:
        assert model_keys[0] in graph[k].dependencies
    # the same model gives the same key; another model another key
    assert featherdyn._dask.model_key(panda) == featherdyn._dask.model_key(fd.load_robot("panda"))
    assert featherdyn._dask.model_key(panda) != featherdyn._dask.model_key(fd.load_robot("panda", floating_base=True))


def _raises_like_numpy(numpy_call: Callable[[], Any], lazy_call: Callable[[], Any]) -> None:
    with pytest.raises(fd.errors.FeatherdynError) as want:
        numpy_call()
    with pytest.raises(type(want.value)) as got:
        lazy_call()
    assert str(got.value) == str(want.value)


def test_errors_are_the_numpy_errors_and_come_before_any_work(panda: fd.Model) -> None:
    s = _states(panda, (10,))
    q_bad = s["q"][:, :-1]
    _raises_like_numpy(lambda: fd.rnea(panda, q_bad, s["v"], s["a"]),
                       lambda: fd.rnea(panda, _lazy(q_bad, 5), s["v"], s["a"]))
    _raises_like_numpy(lambda: fd.frame_placement(panda, s["q"], "no_such_frame"),
                       lambda: fd.frame_placement(panda, _lazy(s["q"], 5), "no_such_frame"))
    _raises_like_numpy(lambda: fd.frame_jacobian(panda, s["q"], _end(panda), "sideways"),
                       lambda: fd.frame_jacobian(panda, _lazy(s["q"], 5), _end(panda), "sideways"))
    _raises_like_numpy(lambda: fd.aba(panda, s["q"], s["v"], s["tau"], s["f_ext"][:, :-1]),
                       lambda: fd.aba(panda, _lazy(s["q"], 5), s["v"], s["tau"], s["f_ext"][:, :-1]))


def test_chunks_along_the_state_axis_are_refused(panda: fd.Model) -> None:
    q = da.from_array(_states(panda, (10,))["q"], chunks=(5, 4))
    with pytest.raises(fd.errors.ShapeError, match=r"q: a Dask array may be chunked only along its batch axes.*rechunk"):
        fd.crba(panda, q)


def test_batch_shapes_that_do_not_broadcast(panda: fd.Model) -> None:
    s = _states(panda, (10,))
    with pytest.raises(fd.errors.ShapeError, match="batch shapes do not broadcast"):
        fd.nonlinear_effects(panda, _lazy(s["q"], 5), s["v"][:7])


def test_chunks_of_unknown_size_are_refused(panda: fd.Model) -> None:
    q = _lazy(_states(panda, (10,))["q"], 5)
    q = q[q[:, 0] > -10]        # boolean indexing: chunk sizes unknown until computed
    with pytest.raises(fd.errors.ShapeError, match="unknown size"):
        fd.generalized_gravity(panda, q)


def test_a_bad_state_raises_at_compute_with_the_numpy_message(panda: fd.Model) -> None:
    s = _states(panda, (6,))
    q = s["q"].copy()
    q[4, 2] = np.nan
    with pytest.raises(fd.errors.NonFiniteError) as want:
        fd.generalized_gravity(panda, q)
    g = fd.generalized_gravity(panda, _lazy(q, 3))  # values are not known before compute
    with pytest.raises(fd.errors.NonFiniteError) as got:
        g.compute(scheduler="sync")
    assert str(got.value) == str(want.value)


def test_importing_featherdyn_does_not_import_dask() -> None:
    out = subprocess.run([sys.executable, "-c", "import sys, featherdyn; print('dask' in sys.modules)"],
                         capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_kinematics_derivatives_at_a_point_stay_lazy(solo: fd.Model) -> None:
    """The point path (``point=``) took Dask arrays and returned NumPy arrays, computing every block at once; it now
    returns Dask arrays like the frame's path, bit for bit the NumPy call's, a Dask point included."""
    s = _states(solo, (9,), seed=3)
    points = np.random.default_rng(4).normal(size=(9, 3)) * 0.1
    expected = fd.kinematics_derivatives(solo, s["q"], s["v"], s["a"], "HR_FOOT", fd.LOCAL_WORLD_ALIGNED, points)
    one = fd.kinematics_derivatives(solo, s["q"], s["v"], s["a"], "HR_FOOT", fd.LOCAL_WORLD_ALIGNED, points[0])
    for point, want in ((points, expected), (_lazy(points, 4), expected), (points[0], one)):
        got = fd.kinematics_derivatives(solo, _lazy(s["q"], 4), _lazy(s["v"], 3), s["a"], "HR_FOOT",
                                        fd.LOCAL_WORLD_ALIGNED, point)
        assert isinstance(got, fd.KinematicsDerivatives)
        assert all(isinstance(x, da.Array) for x in got)
        assert all(np.array_equal(x.compute(), y) for x, y in zip(got, want, strict=True))
    with pytest.raises(fd.ShapeError, match="point"):  # checked before any block is computed
        fd.kinematics_derivatives(solo, _lazy(s["q"], 4), s["v"], s["a"], "HR_FOOT", fd.LOCAL, np.zeros(2))
    with pytest.raises(fd.ModelError, match="nope"):
        fd.kinematics_derivatives(solo, _lazy(s["q"], 4), s["v"], s["a"], "nope", fd.LOCAL, points)
