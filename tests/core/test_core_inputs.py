"""What featherdyn.core accepts, converts and refuses, and the errors it raises.

* big-endian, strided, unaligned, read-only, float32, integer and list inputs give
  the numbers of the same state in native float64;
* the binding itself never reinterprets memory: handed anything but a native,
  aligned, C-contiguous float64 array, it raises ``TypeError``;
* bad input (wrong length, NaN, a non-unit quaternion, a singular mass matrix,
  an unknown frame) raises the reference's exception type with the reference's
  message, for one state and for batches;
* a model keeps pickling after the core has cached its arrays on it.
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest
from _core_helpers import same_message
from _models import random_state, tree

import featherdyn as fd
from featherdyn import core
from featherdyn.core import _core


def _variants(x: np.ndarray) -> dict[str, object]:
    """The same numbers as ``x`` (float64, 1-D or 2-D) in layouts the binding does not take."""
    big = x.astype(">f8")
    strided = np.empty(x.shape[:-1] + (2 * x.shape[-1],))
    strided[..., ::2] = x
    buf = np.zeros(x.nbytes + 1, dtype=np.uint8)
    unaligned = buf[1:].view(np.float64).reshape(x.shape)
    unaligned[...] = x
    readonly = x.copy()
    readonly.flags.writeable = False
    return {"big-endian": big, "strided": strided[..., ::2], "unaligned": unaligned, "read-only": readonly,
            "list": x.tolist(), "fortran": np.asfortranarray(x) if x.ndim > 1 else x.copy()}


@pytest.mark.parametrize("layout", ["big-endian", "strided", "unaligned", "read-only", "list", "fortran"])
@pytest.mark.parametrize("batch", [(), (3,)], ids=["one", "batch3"])
def test_layouts_give_the_same_numbers(layout: str, batch: tuple[int, ...]) -> None:
    model = tree("free_branch")
    st = random_state(model, 20, batch)
    expected = core.rnea(model, st.q, st.v, st.a, st.f_ext)
    got = core.rnea(model, _variants(st.q)[layout], _variants(st.v)[layout], _variants(st.a)[layout],
                    _variants(st.f_ext)[layout])
    assert np.array_equal(got, expected), layout
    M = core.crba(model, _variants(st.q)[layout])
    assert np.array_equal(M, core.crba(model, st.q)), layout


def test_many_big_endian_calls_after_an_unaligned_one() -> None:
    """The JIT engine's failure mode (a cached type reused): here every call converts afresh."""
    model = tree("fixed_chain_mixed")
    st = random_state(model, 21)
    expected = core.rnea(model, st.q, st.v, st.a)
    buf = np.zeros(st.q.nbytes + 1, dtype=np.uint8)
    unaligned = buf[1:].view(np.float64)
    unaligned[...] = st.q
    assert np.array_equal(core.rnea(model, unaligned, st.v, st.a), expected)
    for _ in range(20):
        assert np.array_equal(core.rnea(model, st.q.astype(">f8"), st.v.astype(">f8"), st.a.astype(">f8")), expected)


def test_masked_arrays_and_memoryviews_like_the_reference() -> None:
    """A masked array is handled as the reference handles it (its numbers, or the same error); a memoryview works."""
    model = tree("free_branch")
    st = random_state(model, 29)
    for mask in (np.zeros(model.nv, dtype=bool), np.arange(model.nv) == 0):
        v = np.ma.masked_array(st.v, mask=mask)
        try:
            ref = fd.rnea(model, st.q, v, st.a, backend="reference")
        except fd.FeatherdynError:
            _same_error(lambda v=v: core.rnea(model, st.q, v, st.a),  # type: ignore[misc]
                        lambda v=v: fd.rnea(model, st.q, v, st.a, backend="reference"))
        else:
            tau = core.rnea(model, st.q, v, st.a)
            assert np.allclose(tau, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref))), mask
    assert np.array_equal(core.rnea(model, memoryview(st.q), st.v, st.a), core.rnea(model, st.q, st.v, st.a))


def test_float32_and_int_inputs() -> None:
    model = tree("revolute_chain")
    q = np.arange(model.nq) % 3 - 1  # integers
    v = np.ones(model.nv, dtype=np.int64)
    a = np.linspace(-1, 1, model.nv).astype(np.float32)
    tau = core.rnea(model, q, v, a)
    assert tau.dtype == np.float64
    assert np.array_equal(tau, core.rnea(model, q.astype(float), v.astype(float), a.astype(np.float64)))
    ref = fd.rnea(model, q.astype(float), v.astype(float), a.astype(np.float64), backend="reference")
    assert np.allclose(tau, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))


def test_object_arrays_of_numbers_convert_and_symbols_are_refused() -> None:
    model = tree("revolute_chain")
    st = random_state(model, 22)
    obj = st.q.astype(object)
    assert np.array_equal(core.rnea(model, obj, st.v, st.a), core.rnea(model, st.q, st.v, st.a))
    sympy = pytest.importorskip("sympy")
    sym = np.array([sympy.Symbol(f"q{k}") for k in range(model.nq)], dtype=object)
    with pytest.raises(fd.errors.DTypeError, match="float64"):
        core.rnea(model, sym, st.v, st.a)


@pytest.mark.parametrize("bad", ["big-endian", "strided", "unaligned", "float32", "list", "int"])
def test_the_binding_never_reinterprets_memory(bad: str) -> None:
    """Called directly, the extension refuses every array it would have to reinterpret or copy."""
    model = tree("revolute_chain")
    cm = core._view(model).cm
    st = random_state(model, 23)
    arrays = {"float32": st.q.astype(np.float32), "int": np.zeros(model.nq, dtype=np.int64), "list": st.q.tolist()}
    arrays.update({k: v for k, v in _variants(st.q).items() if k in ("big-endian", "strided", "unaligned")})
    tau = np.empty(model.nv)
    rnea = _core.kernels["rnea"]
    assert rnea.into(cm, [arrays[bad], st.v, st.a, None], [tau]) == -1  # not taken as it is
    assert rnea.fresh(cm, [arrays[bad], st.v, st.a, None]) is None
    with pytest.raises(TypeError):
        rnea.batch(cm, [np.atleast_2d(arrays[bad]) if bad != "list" else [st.q.tolist()], st.v[None], st.a[None], None],
                   [tau[None]])
    assert rnea.into(cm, [st.q, st.v, st.a, None], [tau]) == 0


# ---------------------------------------------------------------------------
# errors: the reference's type and message
# ---------------------------------------------------------------------------


def _same_error(fn_core, fn_ref) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(fd.FeatherdynError) as ref_info:
        fn_ref()
    with pytest.raises(fd.FeatherdynError) as core_info:
        fn_core()
    assert type(core_info.value) is type(ref_info.value), (core_info.value, ref_info.value)
    assert same_message(core_info.value, ref_info.value), (str(core_info.value), str(ref_info.value))


def _bad_states(model: fd.Model, batch: tuple[int, ...]) -> dict[str, tuple[np.ndarray, ...]]:
    st = random_state(model, 24, batch)
    q, v, a, f = st.q, st.v, st.a, st.f_ext
    nan_q, nan_v, nan_a, nan_f = q.copy(), v.copy(), a.copy(), f.copy()
    nan_q[..., 1] = np.nan
    nan_v[..., -1] = np.inf
    nan_a[..., 0] = -np.inf
    nan_f[..., 0, 2] = np.nan
    quat = q.copy()
    quat[..., 6] *= 1.01  # the free-flyer's w
    return {
        "short q": (q[..., :-1], v, a, f),
        "long v": (q, np.concatenate([v, v[..., :1]], -1), a, f),
        "short a": (q, v, a[..., 1:], f),
        "f_ext shape": (q, v, a, f[..., :-1, :]),
        "nan q": (nan_q, v, a, f),
        "inf v": (q, nan_v, a, f),
        "inf a": (q, v, nan_a, f),
        "nan f_ext": (q, v, a, nan_f),
        "quaternion": (quat, v, a, f),
        "nan v and bad quaternion": (quat, nan_v, a, f),
    }


@pytest.mark.parametrize("batch", [(), (3,)], ids=["one", "batch3"])
@pytest.mark.parametrize("case", list(_bad_states(tree("free_branch"), ()).keys()))
def test_bad_input_raises_the_reference_error(case: str, batch: tuple[int, ...]) -> None:
    model = tree("free_branch")
    q, v, a, f = _bad_states(model, batch)[case]
    ref = "reference"
    _same_error(lambda: core.rnea(model, q, v, a, f), lambda: fd.rnea(model, q, v, a, f, backend=ref))
    _same_error(lambda: core.aba(model, q, v, a, f), lambda: fd.aba(model, q, v, a, f, backend=ref))
    if case in ("short a", "inf a") or "f_ext" in case:
        return
    _same_error(lambda: core.nonlinear_effects(model, q, v), lambda: fd.nonlinear_effects(model, q, v, backend=ref))
    if case not in ("short q", "nan q", "quaternion"):
        return
    _same_error(lambda: core.crba(model, q), lambda: fd.crba(model, q, backend=ref))
    _same_error(lambda: core.generalized_gravity(model, q), lambda: fd.generalized_gravity(model, q, backend=ref))
    _same_error(lambda: core.frame_jacobian(model, q, 3, fd.WORLD),
                lambda: fd.frame_jacobian(model, q, 3, fd.WORLD, backend=ref))
    _same_error(lambda: core.frame_placement(model, q, 3), lambda: fd.frame_placement(model, q, 3, backend=ref))


def test_fk_accelerations_need_velocities() -> None:
    model = tree("free_branch")
    st = random_state(model, 28)
    fd.forward_kinematics(model, st.q)  # the model's arrays are cached: the one-state fast path is live
    for backend in (None, "reference"):
        with pytest.raises(fd.errors.ShapeError, match="a: needs v as well"):
            fd.forward_kinematics(model, st.q, a=st.a, backend=backend)


def test_batch_shapes_that_do_not_broadcast() -> None:
    model = tree("free_branch")
    st = random_state(model, 25, (3,))
    _same_error(lambda: core.rnea(model, st.q, st.v[:2], st.a),
                lambda: fd.rnea(model, st.q, st.v[:2], st.a, backend="reference"))


def test_unknown_frames_and_references() -> None:
    model = tree("free_branch")
    q = random_state(model, 26).q
    for frame in ("no_such_frame", 10_000, -1, 2.0):
        _same_error(lambda fr=frame: core.frame_jacobian(model, q, fr, fd.LOCAL),  # type: ignore[misc]
                    lambda fr=frame: fd.frame_jacobian(model, q, fr, fd.LOCAL, backend="reference"))
    _same_error(lambda: core.frame_jacobian(model, q, 0, "sideways"),
                lambda: fd.frame_jacobian(model, q, 0, "sideways", backend="reference"))
    assert np.array_equal(core.frame_jacobian(model, q, "b3_tool", "world"), core.frame_jacobian(model, q, "b3_tool", 1))


def _massless_leaf_model() -> fd.Model:
    b = fd.ModelBuilder("massless_leaf")
    inertia = fd.SpatialInertia(1.0, [0.1, 0.0, 0.0], np.diag([0.1, 0.2, 0.3]))
    b.add_body("base", -1, fd.RevoluteJoint([0, 0, 1]), inertia=inertia)
    b.add_body("arm", 0, fd.RevoluteJoint([0, 1, 0]), inertia=inertia, joint_name="shoulder",
               placement=fd.PluckerTransform(np.eye(3), [0.5, 0, 0]))
    b.add_body("tip", 1, fd.PrismaticJoint([1, 0, 0]), joint_name="slider")  # no mass at all
    b.add_body("ball", 0, fd.SphericalJoint(), joint_name="ball", inertia=inertia)
    b.add_body("ghost", 3, fd.SphericalJoint(), joint_name="ghost")  # no mass either
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return b.build()


def test_singular_mass_matrix_raises_the_reference_error() -> None:
    model = _massless_leaf_model()
    q = np.array([0.1, 0.2, 0.3, 0, 0, 0, 1, 0.6, 0, 0.8, 0])
    v, tau = np.zeros(model.nv), np.ones(model.nv)
    _same_error(lambda: core.aba(model, q, v, tau), lambda: fd.aba(model, q, v, tau, backend="reference"))
    for n in (3, 8, 9):  # the tail row by row; full SIMD groups, whose failure is redone row by row
        qs = np.stack([q] * n)
        _same_error(lambda qs=qs: core.aba(model, qs, v, tau),  # type: ignore[misc]
                    lambda qs=qs: fd.aba(model, qs, v, tau, backend="reference"))
    # the other algorithms do not care
    assert np.all(np.isfinite(core.rnea(model, q, v, tau)))
    assert np.linalg.matrix_rank(core.crba(model, q)) == model.nv - 4


def test_a_model_pickles_after_the_core_cached_its_arrays() -> None:
    model = tree("planar_root_branch")
    st = random_state(model, 27)
    tau = core.rnea(model, st.q, st.v, st.a)
    assert hasattr(model, "_core")
    import copy

    for clone in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        assert not hasattr(clone, "_core")
        assert np.array_equal(core.rnea(clone, st.q, st.v, st.a), tau)
        assert clone._core is not model._core
    assert core._view(model) is core._view(model)  # built once per model


def test_a_model_pickles_where_python_replaced_its_getstate(monkeypatch: pytest.MonkeyPatch) -> None:
    """Python 3.10 and 3.11.0-3.11.3 give a slots dataclass a ``__getstate__`` that reads every field, the unset
    caches too (CPython gh-104035): pickling and copying must not go through it."""
    import copy
    import dataclasses

    def every_field(self: fd.Model) -> list[object]:
        return [getattr(self, f.name) for f in dataclasses.fields(self)]  # AttributeError on an unset cache

    monkeypatch.setattr(fd.Model, "__getstate__", every_field)
    model = tree("planar_root_branch")
    st = random_state(model, 28)
    tau = core.rnea(model, st.q, st.v, st.a)
    assert hasattr(model, "_core") and not hasattr(model, "_fast")
    for clone in (pickle.loads(pickle.dumps(model)), copy.copy(model), copy.deepcopy(model)):
        assert not hasattr(clone, "_core")
        assert clone.joint_names == model.joint_names
        assert np.array_equal(core.rnea(clone, st.q, st.v, st.a), tau)
