"""The one-state fast path of the public functions (api/_backend.py: ``core_path``, ``fast_path``).

``fd.rnea(model, q, v, a)`` with one float64 state hands its arguments to the
compiled C++ core (``fd.rnea``, ``nonlinear_effects``, ``generalized_gravity``,
``crba``, ``aba``, ``frame_jacobian``, ``frame_placement``), which validates
inside the compiled code; ``fd.forward_kinematics`` still takes the Numba
engine's checked kernel. These tests pin down that the fast path changes
nothing a caller can observe except time: the same numbers as the general
engine path and the reference (to 1e-12), the same exceptions with the same
messages, every odd input handled, safe from several threads.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.engine import _fast
from tests._models import random_state, tree

TREES = ["revolute_chain", "fixed_chain_mixed", "fixed_branch_mixed", "planar_root_branch", "free_chain", "free_branch"]


def _calls(model: fd.Model, st: object) -> dict[str, object]:
    q, v, a, tau = st.q, st.v, st.a, st.tau  # type: ignore[attr-defined]
    frame = model.frames[-1].name
    return {
        "rnea": lambda **k: fd.rnea(model, q, v, a, **k),
        "rnea_nograv": lambda **k: fd.rnea(model, q, v, a, gravity=False, **k),
        "nle": lambda **k: fd.nonlinear_effects(model, q, v, **k),
        "gravity": lambda **k: fd.generalized_gravity(model, q, **k),
        "crba": lambda **k: fd.crba(model, q, **k),
        "aba": lambda **k: fd.aba(model, q, v, tau, **k),
        "aba_nograv": lambda **k: fd.aba(model, q, v, tau, gravity=False, **k),
        "J_local": lambda **k: fd.frame_jacobian(model, q, frame, fd.LOCAL, **k),
        "J_world": lambda **k: fd.frame_jacobian(model, q, frame, fd.WORLD, **k),
        "J_lwa": lambda **k: fd.frame_jacobian(model, q, len(model.frames) - 1, fd.LOCAL_WORLD_ALIGNED, **k),
    }


@pytest.mark.parametrize("name", TREES)
def test_fast_equals_engine_and_reference(name: str) -> None:
    model = tree(name)
    for seed in range(3):
        st = random_state(model, seed)
        for label, call in _calls(model, st).items():
            fast = call()
            assert isinstance(fast, np.ndarray) and fast.dtype == np.float64
            ref = call(backend="reference")
            engine = call(backend="compiled")  # the general engine path (input validated in NumPy)
            scale = max(1.0, float(np.max(np.abs(ref))))
            assert np.max(np.abs(fast - engine)) <= 1e-12 * scale, f"{name} {label}: fast path != general engine path"
            assert np.max(np.abs(fast - ref)) <= 1e-12 * scale, f"{name} {label}: fast path != reference"


def test_fast_path_is_taken_for_one_float64_state() -> None:
    from featherdyn.core import _core

    model = tree("free_chain")
    st = random_state(model, 1)
    fd.rnea(model, st.q, st.v, st.a)
    handle = model._core  # made by the first one-state call
    tau = np.empty(model.nv)
    assert _core.rnea(handle.cm, st.q, st.v, st.a, None, True, tau) == 0
    assert np.array_equal(fd.rnea(model, st.q, st.v, st.a), tau)  # the public call is the core's, bit for bit
    # forward kinematics still runs the Numba engine's checked kernel, in the model's workspace
    fast = _fast.attach(model)
    assert fast is not None and model._fast is fast
    before = fast.MD.copy()
    fd.forward_kinematics(model, st.q, st.v)
    assert not np.array_equal(before, fast.MD)
    assert _fast.attach("not a model") is None


@pytest.mark.parametrize("label", ["rnea", "nle", "gravity", "crba", "aba", "J_local", "J_world"])
def test_odd_inputs_take_the_general_path(label: str) -> None:
    """Lists, float32, ints, strided and read-only arrays, batches: the same results as the reference."""
    model = tree("free_chain")
    st = random_state(model, 4)
    expected = _calls(model, st)[label](backend="reference")

    def variant(convert: object) -> object:
        return type(st)(**{k: convert(getattr(st, k)) for k in ("q", "v", "a", "tau", "f_ext")})  # type: ignore

    readonly = variant(lambda x: x.copy())
    for x in (readonly.q, readonly.v, readonly.a, readonly.tau):  # type: ignore[attr-defined]
        x.setflags(write=False)
    cases = {
        "list": variant(lambda x: x.tolist()),
        "strided": variant(lambda x: np.repeat(x, 2, axis=-1)[..., ::2]),
        "readonly": readonly,
        "batch of one": variant(lambda x: x[None]),
    }
    for case, stv in cases.items():
        got = np.asarray(_calls(model, stv)[label]())
        assert got.shape[-expected.ndim :] == expected.shape, f"{label} {case}"
        assert np.allclose(got.reshape(expected.shape), expected, rtol=1e-12, atol=1e-12), f"{label} {case}"
    got32 = _calls(model, variant(lambda x: x.astype(np.float32)))[label]()
    assert got32.dtype == np.float32  # float32 stays float32 (the reference)


def _error(call: object) -> tuple[type, str]:
    with pytest.raises(fd.FeatherdynError) as info:
        call()  # type: ignore[operator]
    return type(info.value), str(info.value)


@pytest.mark.parametrize("label", ["rnea", "rnea_nograv", "nle", "gravity", "crba", "aba", "J_local"])
def test_bad_single_states_raise_the_reference_errors(label: str) -> None:
    model = tree("free_chain")
    st = random_state(model, 5)
    nan_q = st.q.copy()
    nan_q[2] = np.nan
    inf_v = st.v.copy()
    inf_v[0] = np.inf
    off_quat = st.q.copy()
    off_quat[3:7] *= 1.01  # the free-flyer quaternion, off unit norm
    bad = {
        "nan in q": dict(q=nan_q),
        "inf in v": dict(v=inf_v),
        "short q": dict(q=st.q[:-1].copy()),
        "long v": dict(v=np.append(st.v, 0.0)),
        "short a": dict(a=st.a[:-1].copy(), tau=st.tau[:-1].copy()),
        "quaternion": dict(q=off_quat),
    }
    checked = 0
    for case, change in bad.items():
        stb = type(st)(**{**{k: getattr(st, k) for k in ("q", "v", "a", "tau", "f_ext")}, **change})
        call = _calls(model, stb)[label]
        try:
            expected = _error(lambda call=call: call(backend="reference"))
        except pytest.fail.Exception:
            continue  # this function does not read the changed argument (e.g. crba and v)
        assert _error(call) == expected, f"{label} {case}"
        checked += 1
    assert checked >= 3


def test_bad_frame_and_reference_raise_the_reference_errors() -> None:
    model = tree("free_chain")
    st = random_state(model, 6)
    for frame, reference in [("no such frame", fd.LOCAL), (len(model.frames), fd.LOCAL), (-1, fd.WORLD),
                             (0, "sideways"), (0, 7)]:
        expected = _error(lambda f=frame, r=reference: fd.frame_jacobian(model, st.q, f, r, backend="reference"))
        assert _error(lambda f=frame, r=reference: fd.frame_jacobian(model, st.q, f, r)) == expected
    # string spellings of the reference take the general path and agree
    assert np.allclose(fd.frame_jacobian(model, st.q, 0, "world"), fd.frame_jacobian(model, st.q, 0, fd.WORLD),
                       rtol=1e-12, atol=1e-12)


def test_threads_share_a_model_safely() -> None:
    """Threads calling fd.rnea on one model at once get the single-threaded results."""
    model = tree("free_branch")
    states = [random_state(model, s) for s in range(8)]
    expected = [fd.rnea(model, st.q, st.v, st.a, backend="reference") for st in states]
    failures: list[int] = []

    def work(k: int) -> None:
        for _ in range(300):
            for j, st in enumerate(states):
                got = fd.rnea(model, st.q, st.v, st.a)
                if not np.allclose(got, expected[j], rtol=1e-12, atol=1e-12):
                    failures.append(k)
                    return

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert failures == []


def test_pickled_model_rebuilds_its_fast_path() -> None:
    import copy
    import pickle

    model = tree("free_chain")
    st = random_state(model, 7)
    tau = fd.rnea(model, st.q, st.v, st.a)
    for clone in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        assert np.array_equal(fd.rnea(clone, st.q, st.v, st.a), tau)
        assert clone._core is not model._core


@pytest.mark.parametrize("name", TREES)
def test_fast_forward_kinematics(name: str) -> None:
    model = tree(name)
    st = random_state(model, 8)
    for args in [(st.q,), (st.q, st.v), (st.q, st.v, st.a)]:
        fast = fd.forward_kinematics(model, *args)
        engine = fd.forward_kinematics(model, *args, backend="compiled")
        ref = fd.forward_kinematics(model, *args, backend="reference")
        for attr in ("placements", "parent_placements"):
            for part in ("rotation", "translation"):
                got = getattr(getattr(fast, attr), part)
                assert np.array_equal(got, getattr(getattr(engine, attr), part)), f"{name} {attr}.{part}"
                assert np.allclose(got, getattr(getattr(ref, attr), part), rtol=1e-12, atol=1e-12)
                assert not got.flags.writeable
        for attr in ("velocities", "accelerations"):
            if getattr(ref, attr) is None:
                assert getattr(fast, attr) is None
            else:
                assert np.array_equal(getattr(fast, attr).vector, getattr(engine, attr).vector)
                assert np.allclose(getattr(fast, attr).vector, getattr(ref, attr).vector, rtol=1e-12, atol=1e-12)
    # bad input: the reference's errors
    nan_q = st.q.copy()
    nan_q[0] = np.nan
    for args in [(nan_q,), (st.q, np.zeros(0)), (st.q, None, st.a), (st.q, st.v, st.a[:-1].copy()),
                 (st.q[:-1].copy(), st.v)]:
        assert _error(lambda a=args: fd.forward_kinematics(model, *a)) == \
            _error(lambda a=args: fd.forward_kinematics(model, *a, backend="reference"))


@pytest.mark.parametrize("name", TREES)
def test_fast_frame_placement(name: str) -> None:
    model = tree(name)
    st = random_state(model, 9)
    for fid in range(len(model.frames)):
        for frame in (fid, model.frames[fid].name):
            fast = fd.frame_placement(model, st.q, frame)
            ref = fd.frame_placement(model, st.q, frame, backend="reference")
            if isinstance(frame, str) and model.frame_id(frame) != fid:
                continue  # a duplicated name resolves to its first frame
            assert np.allclose(fast.rotation, ref.rotation, rtol=0, atol=1e-12), f"{name} frame {frame}"
            assert np.allclose(fast.translation, ref.translation, rtol=0, atol=1e-12), f"{name} frame {frame}"
            assert fast.rotation.shape == (3, 3) and fast.translation.shape == (3,)
            assert not fast.rotation.flags.writeable
    nan_q = st.q.copy()
    nan_q[-1] = np.nan
    for frame, q in [("no such frame", st.q), (len(model.frames), st.q), (-1, st.q), (0, nan_q), (0, st.q[:-1].copy()),
                     (1.5, st.q)]:
        assert _error(lambda f=frame, x=q: fd.frame_placement(model, x, f)) == \
            _error(lambda f=frame, x=q: fd.frame_placement(model, x, f, backend="reference"))


def test_exotic_arrays_are_computed_correctly() -> None:
    """Big-endian, unaligned and subclassed float64 arrays: whichever path takes them, the numbers are right."""
    model = tree("free_chain")
    st = random_state(model, 10)
    expected_tau = fd.rnea(model, st.q, st.v, st.a, backend="reference")
    expected_M = fd.crba(model, st.q, backend="reference")
    buf = np.zeros(model.nq * 8 + 1, np.uint8)
    unaligned = buf[1:].view(np.float64)
    unaligned[:] = st.q
    assert not unaligned.flags.aligned
    subclass = st.q.view(type("Sub", (np.ndarray,), {}))
    for q in (st.q.astype(">f8"), unaligned, subclass):
        assert np.allclose(fd.rnea(model, q, st.v, st.a), expected_tau, rtol=1e-12, atol=1e-12)
        assert np.allclose(fd.crba(model, q), expected_M, rtol=1e-12, atol=1e-12)


def test_objects_numba_cannot_type_get_the_reference_errors() -> None:
    """An empty list makes Numba's dispatch raise ValueError (not TypeError): still the reference's error."""
    model = tree("free_chain")
    st = random_state(model, 11)
    for bad in ([], {}, set(), object(), (), [[]], b""):
        for call in (lambda x: fd.rnea(model, x, st.v, st.a), lambda x: fd.crba(model, x),
                     lambda x: fd.aba(model, st.q, x, st.tau), lambda x: fd.generalized_gravity(model, x),
                     lambda x: fd.frame_jacobian(model, x, 0), lambda x: fd.frame_placement(model, x, 0),
                     lambda x: fd.forward_kinematics(model, x), lambda x: fd.nonlinear_effects(model, st.q, x)):
            with pytest.raises(fd.FeatherdynError):
                call(bad)


def test_model_without_bodies() -> None:
    """A model with no moving bodies: empty results, and a frame index is refused with a clear error."""
    import warnings

    b = fd.ModelBuilder("empty")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = b.build()
    z = np.zeros(0)
    assert fd.rnea(model, z, z, z).shape == (0,)
    assert fd.crba(model, z).shape == (0, 0)
    assert fd.aba(model, z, z, z).shape == (0,)
    assert fd.generalized_gravity(model, z).shape == (0,)
    assert fd.forward_kinematics(model, z).placements.rotation.shape == (0, 3, 3)
    with pytest.raises(fd.ModelError, match="no frames"):
        fd.frame_jacobian(model, z, 0)
    with pytest.raises(fd.ModelError, match="no frames"):
        fd.frame_placement(model, z, 0)

