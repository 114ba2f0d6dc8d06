"""The one-state fast path of the public functions: the declared kernels' ``fresh`` and ``into`` and the array read.

* ``Kernel.fresh`` allocates its result (NumPy's ``PyArray_SimpleNew``) and returns exactly the
  numbers ``Kernel.into`` writes, as a fresh, owned, writeable float64 array; for a state ``into``
  would refuse with a status, and for an array it does not take as it is, it returns ``None`` (the
  caller's general path converts or words the error); ``into`` returns -1 for such an array;
* a float64 array whose dtype object is not NumPy's native singleton (an unpickled dtype) is read
  as native float64, with the same numbers; a read-only output, an ``ndarray`` subclass and a
  strided array are refused; an offset C-contiguous view is read at its offset;
* placements that finite input overflows are reported at the same element as a full scan would
  (only translations can overflow).
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn import core
from featherdyn.core import _core
from featherdyn.errors import NonFiniteError

TREE_NAMES = [s.name for s in TREES]


K = _core.kernels


def _calls(model: fd.Model, seed: int) -> list[tuple[str, object, object]]:
    """``(name, result of Kernel.fresh, what Kernel.into wrote)`` for one random state."""
    cm = core._view(model).cm
    st = random_state(model, seed)
    nv = model.nv
    tau, h, g, qdd = np.empty(nv), np.empty(nv), np.empty(nv), np.empty(nv)
    M, J = np.empty((nv, nv)), np.empty((6, nv))
    assert K["rnea"].into(cm, [st.q, st.v, st.a, st.f_ext], [tau]) == 0
    assert K["nonlinear_effects"].into(cm, [st.q, st.v], [h]) == 0
    assert K["generalized_gravity"].into(cm, [st.q], [g]) == 0
    assert K["crba"].into(cm, [st.q], [M]) == 0
    assert K["aba"].into(cm, [st.q, st.v, st.a, st.f_ext], [qdd], _core.Options(gravity=False)) == 0
    frame = len(model.frames) - 2  # a tool frame on the last body
    rows = [
        ("rnea", K["rnea"].fresh(cm, [st.q, st.v, st.a, st.f_ext]), tau),
        ("nle", K["nonlinear_effects"].fresh(cm, [st.q, st.v]), h),
        ("gravity", K["generalized_gravity"].fresh(cm, [st.q]), g),
        ("crba", K["crba"].fresh(cm, [st.q]), M),
        ("aba", K["aba"].fresh(cm, [st.q, st.v, st.a, st.f_ext], _core.Options(gravity=False)), qdd),
    ]
    for ref in (0, 1, 2):
        assert K["frame_jacobian"].into(cm, [st.q], [J], _core.Options(frame=frame, reference=ref)) == 0
        rows.append((f"frame_jacobian {ref}", K["frame_jacobian"].fresh(cm, [st.q], _core.Options(frame=frame, reference=ref)),
                     J.copy()))
    return rows


@pytest.mark.parametrize("name", TREE_NAMES)
def test_new_entry_points_equal_the_out_entry_points(name: str) -> None:
    for what, got, expected in _calls(tree(name), 41):
        assert isinstance(got, np.ndarray) and type(got) is np.ndarray, what
        assert got.dtype == np.float64 and got.flags.c_contiguous and got.flags.writeable and got.flags.owndata, what
        assert np.array_equal(got, expected), what


def test_new_entry_points_return_none_for_a_state_the_general_path_words() -> None:
    model = tree("free_branch")
    cm = core._view(model).cm
    st = random_state(model, 42)
    nan_q = st.q.copy()
    nan_q[1] = np.nan
    bad_quat = st.q.copy()
    bad_quat[6] *= 1.01
    for q in (nan_q, bad_quat, st.q[:-1]):
        assert K["crba"].fresh(cm, [q]) is None
        assert K["generalized_gravity"].fresh(cm, [q]) is None
        assert K["rnea"].fresh(cm, [q, st.v, st.a, None]) is None
        assert K["frame_jacobian"].fresh(cm, [q], _core.Options(frame=0, reference=0)) is None
    assert K["frame_jacobian"].fresh(cm, [st.q], _core.Options(frame=len(model.frames))) is None  # no such frame
    assert K["frame_jacobian"].fresh(cm, [st.q], _core.Options(frame=0, reference=3)) is None  # no such reference
    with pytest.raises(fd.FeatherdynError):
        fd.crba(model, nan_q)  # and the public function words it


@pytest.mark.parametrize("bad", ["float32", "strided", "big-endian", "list"])
def test_new_entry_points_refuse_arrays_they_would_reinterpret(bad: str) -> None:
    model = tree("revolute_chain")
    cm = core._view(model).cm
    q = random_state(model, 43).q
    strided = np.empty(2 * model.nq)
    strided[::2] = q
    arrays = {"float32": q.astype(np.float32), "strided": strided[::2], "big-endian": q.astype(">f8"), "list": q.tolist()}
    assert K["crba"].fresh(cm, [arrays[bad]]) is None
    assert K["crba"].into(cm, [arrays[bad]], [np.empty((model.nv, model.nv))]) == -1
    converted = np.asarray(arrays[bad], dtype=np.float64)
    assert np.array_equal(core.crba(model, arrays[bad]), core.crba(model, converted))  # the wrapper converts


def test_a_float64_dtype_other_than_numpys_singleton_is_read_as_native_float64() -> None:
    model = tree("free_chain")
    cm = core._view(model).cm
    st = random_state(model, 44)
    other = pickle.loads(pickle.dumps(np.dtype(np.float64)))
    assert other is not np.dtype(np.float64) and other == np.dtype(np.float64)
    q2 = st.q.astype(other)
    tau2 = np.empty(model.nv, dtype=other)
    tau = np.empty(model.nv)
    assert K["rnea"].into(cm, [st.q, st.v, st.a, None], [tau]) == 0
    assert K["rnea"].into(cm, [q2, st.v.astype(other), st.a, None], [tau2]) == 0
    assert np.array_equal(tau, tau2)
    assert np.array_equal(K["crba"].fresh(cm, [q2]), K["crba"].fresh(cm, [st.q]))


def test_outputs_subclasses_and_views() -> None:
    model = tree("fixed_branch_mixed")
    cm = core._view(model).cm
    st = random_state(model, 45)
    M = np.empty((model.nv, model.nv))
    assert K["crba"].into(cm, [st.q], [M]) == 0
    readonly = np.empty_like(M)
    readonly.flags.writeable = False
    assert K["crba"].into(cm, [st.q], [readonly]) == -1

    class Sub(np.ndarray):
        pass

    assert K["crba"].fresh(cm, [st.q.view(Sub)]) is None
    padded = np.concatenate([[7.0, 8.0], st.q, [9.0]])  # an offset, C-contiguous view
    assert np.array_equal(K["crba"].fresh(cm, [padded[2:-1]]), M)
    big = np.empty((3, model.nv, model.nv))
    assert K["crba"].into(cm, [st.q], [big[1]]) == 0  # an output view into a larger array
    assert np.array_equal(big[1], M)


def test_overflowing_placements_are_named_at_the_first_non_finite_element() -> None:
    """Only translations are scanned; the element named is the first non-finite one of the whole array."""
    model = tree("fixed_chain_mixed")  # prismatic root, planar joints: translations grow with q
    q = random_state(model, 3).q.copy()
    q[[0, 5, 6, 15]] = 1.7e308
    with pytest.raises(NonFiniteError, match="overflowed") as info:
        fd.forward_kinematics(model, q, backend="reference")
    with pytest.raises(NonFiniteError, match="overflowed") as info_core:
        fd.forward_kinematics(model, q)
    H = np.empty((model.nbodies, 4, 4))
    status = _core.kernels["placements"].into(core._view(model).cm, [q], [H])
    flat = status >> 8
    assert flat % 16 in (3, 7, 11), flat  # a translation
    assert not np.isfinite(H.reshape(-1)[flat]) and np.isfinite(H.reshape(-1)[:flat]).all()
    assert str(flat) in str(info_core.value) and "(2, 0, 3)" in str(info.value)  # body 2, its x: flat 35


def test_fk_overflow_is_reported_as_an_overflow() -> None:
    """Finite q whose placements overflow: the core's fk (and fd.compile's) word it as the reference does,
    not as a missing velocity."""
    b = fd.ModelBuilder("two_slides")
    box = fd.SpatialInertia.box(1.0, [0.1, 0.1, 0.1])
    i = b.add_body("a", -1, fd.PrismaticJoint([1, 0, 0]), inertia=box)
    b.add_body("b", i, fd.PrismaticJoint([1, 0, 0]), inertia=box)
    model = b.build()
    q = np.array([1.5e308, 1.5e308])
    for call in (lambda: core.placements(model, q), lambda: fd.compile(model).fk(q)):
        with pytest.raises(fd.errors.NonFiniteError, match="placements: the result overflowed"):
            call()
