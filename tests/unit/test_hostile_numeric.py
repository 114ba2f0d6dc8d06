"""Hostile and odd input to the numeric API: featherdyn errors naming the argument, or correct numbers.

Issue "Hostile input, real files and first use", items 7–9: object arrays are
checked like any other dtype, no raw NumPy/Python exception escapes, finite
input never gives NaN silently, and ``fd.compile`` warms up in O(nb) memory.
"""

from __future__ import annotations

import os
import resource
import sys

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import DTypeError, FeatherdynError, ModelError, NonFiniteError, QuaternionNormError, ShapeError


@pytest.fixture(scope="module")
def panda() -> fd.Model:
    return fd.load_robot("panda")


@pytest.fixture(scope="module")
def floating() -> fd.Model:
    return fd.load_robot("solo12", floating_base=True)


BACKENDS = [None, "reference"]


# ---------------------------------------------------------------------------------------------
# item 7: object-dtype arrays go through the same checks
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", ["reference", None])
def test_object_array_quaternion_off_unit_norm_is_refused(floating: fd.Model, backend: str | None) -> None:
    q = fd.neutral(floating).astype(object)
    q[3:7] = [0.0, 0.0, 0.0, 2.0]  # norm 2: τ would be off by 1 010 N·m
    with pytest.raises(QuaternionNormError, match="root_joint"):
        fd.rnea(floating, q, np.zeros(floating.nv), np.zeros(floating.nv), backend=backend)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), np.float64("-inf"), 10**400])
def test_object_array_non_finite_entry_is_refused(panda: fd.Model, bad: object) -> None:
    q = fd.neutral(panda).astype(object)
    q[2] = bad
    with pytest.raises(NonFiniteError, match=r"q: .*index \(2,\)"):
        fd.rnea(panda, q, np.zeros(panda.nv), np.zeros(panda.nv))


@pytest.mark.parametrize("bad", [None, "1.0", 1 + 2j, object()])
def test_object_array_non_number_is_a_featherdyn_error(panda: fd.Model, bad: object) -> None:
    v = np.zeros(panda.nv, dtype=object)
    v[4] = bad
    with pytest.raises(DTypeError, match=r"v: expected real numbers or SymPy expressions.*index \(4,\)"):
        fd.rnea(panda, fd.neutral(panda), v, np.zeros(panda.nv))


def test_object_array_of_plain_numbers_equals_float64(panda: fd.Model) -> None:
    rng = np.random.default_rng(0)
    q = fd.random_configuration(panda, rng)
    v, a = rng.normal(size=panda.nv), rng.normal(size=panda.nv)
    expected = fd.rnea(panda, q, v, a, backend="reference")
    got = fd.rnea(panda, q.astype(object), v.astype(object), a.astype(object))
    np.testing.assert_allclose(got.astype(float), expected, rtol=1e-12, atol=1e-12)


def test_symbolic_object_arrays_still_work(floating: fd.Model) -> None:
    """A quaternion with a SymPy symbol cannot be judged numerically, so it is not refused."""
    sympy = pytest.importorskip("sympy")
    x = sympy.Symbol("x")
    q = fd.neutral(floating).astype(object)
    q[0] = x  # a symbolic base position
    tau = fd.generalized_gravity(floating, q)
    assert tau.dtype == object and tau.shape == (floating.nv,)


# ---------------------------------------------------------------------------------------------
# item 8: no raw exception escapes
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("frame", [2**70, -(2**70), 10**30])
@pytest.mark.parametrize("backend", BACKENDS)
def test_huge_frame_index_is_a_model_error(panda: fd.Model, frame: int, backend: str | None) -> None:
    q = fd.neutral(panda)
    with pytest.raises(ModelError, match="frame: index"):
        fd.frame_placement(panda, q, frame, backend=backend)
    with pytest.raises(ModelError, match="frame: index"):
        fd.frame_jacobian(panda, q, frame, backend=backend)


@pytest.mark.skipif(np.dtype(np.longdouble).itemsize <= 8, reason="long double is float64 on this platform")
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("function", ["rnea", "aba", "crba"])
def test_extended_precision_is_a_dtype_error(panda: fd.Model, backend: str | None, function: str) -> None:
    q = fd.neutral(panda).astype(np.longdouble)
    z = np.zeros(panda.nv)
    args = {"rnea": (q, z, z), "aba": (q, z, z), "crba": (q,)}[function]
    with pytest.raises(DTypeError, match=r"q: extended precision"):
        getattr(fd, function)(panda, *args, backend=backend)


@pytest.mark.parametrize("backend", BACKENDS)
def test_empty_batches_work(floating: fd.Model, backend: str | None) -> None:
    Q = np.zeros((0, floating.nq))
    V = np.zeros((0, floating.nv))
    assert fd.aba(floating, Q, V, V, backend=backend).shape == (0, floating.nv)
    assert fd.rnea(floating, Q, V, V, backend=backend).shape == (0, floating.nv)
    assert fd.crba(floating, Q, backend=backend).shape == (0, floating.nv, floating.nv)
    assert fd.frame_jacobian(floating, Q, 0, backend=backend).shape == (0, 6, floating.nv)


def test_masked_entries_are_refused_and_unmasked_arrays_work(panda: fd.Model) -> None:
    rng = np.random.default_rng(1)
    Q = fd.random_configuration(panda, rng, size=3)
    V = np.zeros((3, panda.nv))
    masked = np.ma.masked_array(Q, mask=np.zeros_like(Q, dtype=bool))
    masked.mask[1, 2] = True
    with pytest.raises(DTypeError, match="q: masked entries"):
        fd.rnea(panda, masked, V, V)
    clear = np.ma.masked_array(Q, mask=False)
    np.testing.assert_array_equal(fd.rnea(panda, clear, V, V), fd.rnea(panda, Q, V, V))
    # one state: the compiled core takes only exact ndarrays, so a masked entry is never read as data
    one = np.ma.masked_array(Q[0], mask=np.zeros(panda.nq, dtype=bool))
    one.mask[3] = True
    for call in (lambda x: fd.rnea(panda, x, V[0], V[0]), lambda x: fd.crba(panda, x),
                 lambda x: fd.aba(panda, x, V[0], V[0]), lambda x: fd.frame_jacobian(panda, x, 0),
                 lambda x: fd.generalized_gravity(panda, x), lambda x: fd.frame_placement(panda, x, 0),
                 lambda x: fd.forward_kinematics(panda, x), lambda x: fd.nonlinear_effects(panda, x, V[0])):
        with pytest.raises(DTypeError, match="q: masked entries"):
            call(one)


@pytest.mark.parametrize("name", ["v", "a"])
@pytest.mark.parametrize("backend", BACKENDS)
def test_none_for_a_required_vector_names_it(panda: fd.Model, name: str, backend: str | None) -> None:
    args = {"v": np.zeros(panda.nv), "a": np.zeros(panda.nv)}
    args[name] = None
    with pytest.raises(ShapeError, match=rf"^{name}: expected an array of shape \(\.\.\., nv=9\), got None"):
        fd.rnea(panda, fd.neutral(panda), args["v"], args["a"], backend=backend)


@pytest.mark.parametrize("backend", BACKENDS)
def test_none_for_tau_and_q(panda: fd.Model, backend: str | None) -> None:
    z = np.zeros(panda.nv)
    with pytest.raises(ShapeError, match=r"^tau: expected an array"):
        fd.aba(panda, fd.neutral(panda), z, None, backend=backend)
    with pytest.raises(ShapeError, match=r"^q: expected an array"):
        fd.crba(panda, None, backend=backend)


# ---------------------------------------------------------------------------------------------
# finite input never gives NaN silently
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", [None, "reference", "compiled"])
def test_overflowing_state_is_a_non_finite_error(panda: fd.Model, backend: str | None) -> None:
    q = fd.neutral(panda)
    v = np.full(panda.nv, 1e200)  # v × I v overflows float64
    with np.errstate(all="raise"):  # and no NumPy warning is emitted on the way
        with pytest.raises(NonFiniteError, match=r"rnea: the result overflowed .* every input is finite"):
            fd.rnea(panda, q, v, np.zeros(panda.nv), backend=backend)
        with pytest.raises(NonFiniteError, match=r"aba: the result overflowed"):
            fd.aba(panda, q, v, np.zeros(panda.nv), backend=backend)
        with pytest.raises(NonFiniteError, match=r"kinetic_energy: the result overflowed"):
            fd.kinetic_energy(panda, q, v, backend=backend)


def test_large_but_representable_state_is_computed(panda: fd.Model) -> None:
    q = fd.neutral(panda)
    v = np.full(panda.nv, 1e100)
    tau = fd.rnea(panda, q, v, np.zeros(panda.nv))
    assert np.isfinite(tau).all()
    np.testing.assert_allclose(tau, fd.rnea(panda, q, v, np.zeros(panda.nv), backend="reference"), rtol=1e-10)


# ---------------------------------------------------------------------------------------------
# item 9: fd.compile warms up in O(nb) memory
# ---------------------------------------------------------------------------------------------


def _chain(n: int) -> fd.Model:
    b = fd.ModelBuilder("chain")
    inertia = fd.SpatialInertia(1.0, [0.0, 0.0, 0.05], np.eye(3) * 0.01)
    for i in range(n):
        b.add_body(f"l{i}", parent=i - 1, joint=fd.RevoluteJoint(np.array([0.0, 0.0, 1.0])),
                   placement=fd.PluckerTransform(np.eye(3), [0.0, 0.0, 0.1]), inertia=inertia)
    return b.build()


@pytest.mark.skipif(sys.platform != "linux", reason="ru_maxrss in KiB is Linux's")
def test_compile_of_a_long_chain_does_not_build_its_mass_matrix() -> None:
    model = _chain(6000)  # M would take 6000² · 8 B = 288 MB
    fd.compile(_chain(2))  # the extension loaded before measuring
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    cm = fd.compile(model)
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    assert grown_mb < 100, f"fd.compile grew the process by {grown_mb:.0f} MB for a 6000-link chain"
    tau = cm.rnea(fd.neutral(model), np.zeros(model.nv), np.zeros(model.nv))
    assert tau.shape == (6000,) and np.isfinite(tau).all()


def test_every_error_above_is_a_featherdyn_error() -> None:
    """The hierarchy the tests rely on: each error a caller catches is a FeatherdynError."""
    for cls in (DTypeError, NonFiniteError, ShapeError, ModelError, QuaternionNormError):
        assert issubclass(cls, FeatherdynError)


# ---------------------------------------------------------------------------------------------
# fd.set_num_threads: the batched calls' threads, checked argument
# ---------------------------------------------------------------------------------------------


def test_set_num_threads_sets_the_batched_calls_threads(panda: fd.Model) -> None:
    rng = np.random.default_rng(3)
    Q = fd.random_configuration(panda, rng, size=40)
    V = rng.normal(size=(40, panda.nv))
    expected = fd.rnea(panda, Q, V, V)
    try:
        fd.set_num_threads(1)
        assert fd.get_num_threads() == 1
        np.testing.assert_array_equal(fd.rnea(panda, Q, V, V), expected)  # the lanes do not depend on threads
    finally:
        fd.set_num_threads(0)
    assert fd.get_num_threads() == len(os.sched_getaffinity(0))  # the default: the cores available


@pytest.mark.parametrize("bad", [1.5, "2", None, True, np.float64(2.0)])
def test_set_num_threads_refuses_non_integers(bad: object) -> None:
    with pytest.raises(DTypeError, match="n: expected an integer"):
        fd.set_num_threads(bad)  # type: ignore[arg-type]
