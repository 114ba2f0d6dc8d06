"""The public functions whose one-state calls are finished in C (``_core.declared_call``).

``fd.rnea``, ``fd.nonlinear_effects``, ``fd.generalized_gravity``, ``fd.crba``, ``fd.aba``,
``fd.frame_jacobian``, ``fd.frame_placement`` (a record: a ``PluckerTransform`` made in C) and
``fd.compile(model).fk`` (every declared algorithm's) bind their arguments in the core, compute an exact native float64 ``numpy.ndarray`` state there, and hand every other call
to the Python function they wrap, unchanged. Checked here:

* the fast path returns the numbers of the core's entry points bit for bit, and the reference's
  to round-off, on every test tree;
* every call it declines (keywords it does not bind, lists, float32, strided or big-endian arrays,
  a reference given by name, a bad state, an unknown frame, a wrong ``out=``) gives the result or
  the featherdyn error of the Python function — observed with a spy as the general function;
* the default backend ``"reference"`` sends every call to the Python function;
* the objects look like their functions (name, docstring, signature, pickling by name);
* the per-function cache of the last model's handle: alternating models, a model dropped and
  another made, 8 threads on different models; no reference leaks.
"""

from __future__ import annotations

import inspect
import os
import pickle
import pydoc
import subprocess
import sys
import threading

import numpy as np
import pytest
from _core_helpers import spied
from _models import TREES, random_state, tool_frames, tree

import featherdyn as fd
from featherdyn import core
from featherdyn.api.declarations import DECLARATIONS
from featherdyn.core import _core
from featherdyn.core._model_view import CoreHandle
from featherdyn.errors import ModelError, NonFiniteError, ShapeError

TREE_NAMES = [s.name for s in TREES]
REFERENCES = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)
SLOTS = ("rotation", "translation", "source", "target")


def _frame(model: fd.Model) -> str:
    return tool_frames(model)[-1]


@pytest.mark.parametrize("name", TREE_NAMES)
def test_fast_path_equals_the_core_entry_points_bit_for_bit_and_the_reference(name: str) -> None:
    model = tree(name)
    cm = core._view(model).cm
    frame = _frame(model)
    fid = model.frame_id(frame)
    for seed in range(3):
        q = random_state(model, seed).q
        for code, ref in enumerate(REFERENCES):
            J = fd.frame_jacobian(model, q, frame, ref)
            expected = np.empty((6, model.nv))
            assert K["frame_jacobian"].into(cm, [q], [expected], _core.Options(frame=fid, reference=code)) == 0
            assert type(J) is np.ndarray and J.flags.c_contiguous and J.flags.writeable and J.flags.owndata
            np.testing.assert_array_equal(J, expected)
            np.testing.assert_allclose(J, fd.frame_jacobian(model, q, frame, ref, backend="reference"),
                                       rtol=0, atol=1e-12)
        X = fd.frame_placement(model, q, frame)
        R, p = np.empty((3, 3)), np.empty(3)
        assert K["frame_placement"].into(cm, [q], [R, p], _core.Options(frame=fid)) == 0
        assert type(X) is fd.PluckerTransform and X.source is None and X.target is None
        np.testing.assert_array_equal(X.rotation, R)
        np.testing.assert_array_equal(X.translation, p)
        assert not X.rotation.flags.writeable and not X.translation.flags.writeable
        assert X.rotation.shape == (3, 3) and X.translation.shape == (3,)
        ref_X = fd.frame_placement(model, q, frame, backend="reference")
        np.testing.assert_allclose(X.rotation, ref_X.rotation, rtol=0, atol=1e-12)
        np.testing.assert_allclose(X.translation, ref_X.translation, rtol=0, atol=1e-12)
        H = np.empty((model.nbodies, 4, 4))
        assert K["placements"].into(cm, [q], [H]) == 0
        np.testing.assert_array_equal(fd.compile(model).fk(q), H)


K = _core.kernels


DYNAMICS = ("rnea", "aba", "nonlinear_effects", "generalized_gravity", "crba")


@pytest.mark.parametrize("name", TREE_NAMES)
def test_dynamics_fast_paths_equal_the_kernels_bit_for_bit(name: str) -> None:
    model = tree(name)
    cm = core._view(model).cm
    for seed in range(2):
        st = random_state(model, seed)
        q, v, a, fx = st.q, st.v, st.a, st.f_ext
        pairs = [
            (fd.rnea(model, q, v, a), K["rnea"].fresh(cm, [q, v, a, None])),
            (fd.rnea(model, q, v, a, fx), K["rnea"].fresh(cm, [q, v, a, fx])),
            (fd.rnea(model, q, v, a, f_ext=fx, gravity=False), K["rnea"].fresh(cm, [q, v, a, fx], _core.Options(gravity=False))),
            (fd.aba(model, q, v, a), K["aba"].fresh(cm, [q, v, a, None])),
            (fd.aba(model, q, v, a, fx, gravity=False), K["aba"].fresh(cm, [q, v, a, fx], _core.Options(gravity=False))),
            (fd.nonlinear_effects(model, q, v), K["nonlinear_effects"].fresh(cm, [q, v])),
            (fd.generalized_gravity(model, q), K["generalized_gravity"].fresh(cm, [q])),
            (fd.crba(model, q), K["crba"].fresh(cm, [q])),
        ]
        for got, expected in pairs:
            assert type(got) is np.ndarray and got.flags.writeable
            np.testing.assert_array_equal(got, expected)
        np.testing.assert_allclose(fd.rnea(model, q, v, a, fx), fd.rnea(model, q, v, a, fx, backend="reference"),
                                   rtol=1e-10, atol=1e-10)


def test_dynamics_declined_calls_reach_the_general_function() -> None:
    model = tree(TREE_NAMES[2])
    st = random_state(model, 9)
    q, v, a, fx = st.q, st.v, st.a, st.f_ext
    fd.rnea(model, q, v, a)  # the model's core handle exists
    rnea, spy = spied("rnea")
    for args, kwargs in [((model, q, v, a), {}), ((model, q, v, a, fx), {}), ((model, q, v, a, None), {}),
                         ((model, q, v, a), {"gravity": False}), ((model, q, v, a), {"f_ext": fx, "gravity": True})]:
        assert isinstance(rnea(*args, **kwargs), np.ndarray), (args, kwargs)
    assert not spy.calls
    declined = [
        ((model, q, v, a, fx, False), {}),  # gravity is keyword-only: Python's TypeError
        ((model, q, v, a), {"gravity": 1}),  # not exactly a bool
        ((model, q, v, a), {"backend": "compiled"}),
        ((model, q, v, a, fx.tolist()), {}),
        ((model, q, v, a, fx[:-1]), {}),
        ((model, q, v.astype(np.float32), a), {}),
        ((model, q, v), {}),
        ((model, q, v, a[:-1]), {}),
    ]
    for args, kwargs in declined:
        spy.calls.clear()
        assert rnea(*args, **kwargs) == "general", (args, kwargs)
        assert len(spy.calls) == 1 and spy.calls[0][1] == kwargs
        assert all(x is y for x, y in zip(spy.calls[0][0], args, strict=True))
    for kind, args in [("aba", (model, q, v, a)), ("nonlinear_effects", (model, q, v)),
                       ("generalized_gravity", (model, q)), ("crba", (model, q))]:
        f, spy = spied(kind)
        assert isinstance(f(*args), np.ndarray) and not spy.calls, kind
        assert f(*args, backend=None) == "general" and len(spy.calls) == 1, kind
        assert f(args[0], args[1].tolist(), *args[2:]) == "general" and len(spy.calls) == 2, kind
    with pytest.raises(TypeError):
        fd.rnea(model, q, v, a, fx, False)
    with pytest.raises(ShapeError):
        fd.aba(model, q, v, a[:-1])


def test_declined_calls_reach_the_general_function_with_the_same_arguments() -> None:
    model = tree(TREE_NAMES[0])
    frame = _frame(model)
    q = random_state(model, 3).q
    fd.frame_jacobian(model, q, frame)  # the model's core handle exists
    jac, spy = spied("frame_jacobian")
    assert isinstance(jac(model, q, frame), np.ndarray) and not spy.calls
    assert isinstance(jac(model, q, frame, fd.WORLD), np.ndarray) and not spy.calls
    assert isinstance(jac(model, q, frame, reference=fd.WORLD), np.ndarray) and not spy.calls
    assert isinstance(jac(model, q=q, frame=frame), np.ndarray) and not spy.calls
    assert isinstance(jac(model, q, model.frame_id(frame)), np.ndarray) and not spy.calls
    assert jac(model, q[None], frame).shape == (1, 6, model.nv) and not spy.calls  # a stack (test_stacked_states.py)
    qn = q.copy()
    qn[0] = np.nan
    big_endian = q.astype(">f8")
    strided = np.repeat(q, 2)[::2]
    declined = [
        ((model, q.tolist(), frame), {}),
        ((model, q.astype(np.float32), frame), {}),
        ((model, big_endian, frame), {}),
        ((model, strided, frame), {}),
        ((model, q, frame, "WORLD"), {}),
        ((model, q, frame), {"backend": "compiled"}),
        ((model, q, frame), {"unknown": 1}),
        ((model, q, frame, fd.LOCAL, 5), {}),
        ((model, q), {}),
        ((model, q, frame), {"frame": frame}),
        ((model, q, "no such frame"), {}),
        ((model, q, -1), {}),
        ((model, q, 10**30), {}),
        ((model, q, True), {}),
        ((model, q[:-1], frame), {}),
        ((model, qn, frame), {}),
        (("not a model", q, frame), {}),
    ]
    for args, kwargs in declined:
        spy.calls.clear()
        assert jac(*args, **kwargs) == "general", (args, kwargs)
        assert len(spy.calls) == 1
        got_args, got_kwargs = spy.calls[0]
        assert got_kwargs == kwargs and len(got_args) == len(args)
        assert all(a is b for a, b in zip(got_args, args, strict=True))
    place, spy = spied("frame_placement")
    assert isinstance(place(model, q, frame), fd.PluckerTransform) and not spy.calls
    for args in [(model, qn, frame), (model, q, "no such frame"), (model, q.tolist(), frame)]:
        assert place(*args) == "general" and len(spy.calls) == 1
        spy.calls.clear()


def test_a_point_after_the_options_is_bound_in_c() -> None:
    """fd.kinematics_derivatives' point comes after the frame and reference (by position or by name): the core's
    public call binds it there and runs the kernel (the general function not called), bit for bit the kernel's;
    a point it does not take as it is (a list, float32, NaN, a wrong length, a strided view) goes to the general
    function with the same arguments; a stack of points (1, 3) makes a stack of one state."""
    model = tree(TREE_NAMES[1])
    frame = _frame(model)
    fid = model.frame_id(frame)
    s = random_state(model, 6)
    p = np.array([0.1, -0.2, 0.3])
    f, spy = spied("kinematics_derivatives")
    fd.kinematics_derivatives(model, s.q, s.v, s.a, frame)  # (the model's core handle exists)
    for code, ref in enumerate(REFERENCES):
        expected = [np.empty((6, model.nv)) for _ in range(8)]
        assert K["kinematics_derivatives"].into(core._view(model).cm, [s.q, s.v, s.a, p], expected,
                                                _core.Options(frame=fid, reference=code)) == 0
        for args, kwargs in [((model, s.q, s.v, s.a, frame, ref, p), {}), ((model, s.q, s.v, s.a, frame, ref),
                                                                              {"point": p}),
                             ((model, s.q, s.v, s.a, frame), {"reference": ref, "point": p})]:
            r = f(*args, **kwargs)
            assert type(r) is fd.KinematicsDerivatives and not spy.calls
            assert all(np.array_equal(x, y) for x, y in zip(r, expected, strict=True))
    r = f(model, s.q, s.v, s.a, frame, ref, p[None])  # (ref: the last one above, as expected)
    assert not spy.calls and all(np.array_equal(x, y[None]) for x, y in zip(r, expected, strict=True))
    declined = [p.tolist(), p.astype(np.float32), np.array([0.0, np.nan, 0.0]), p[:2], np.repeat(p, 2)[::2]]
    for bad in declined:
        spy.calls.clear()
        assert f(model, s.q, s.v, s.a, frame, fd.LOCAL, bad) == "general" and len(spy.calls) == 1
        assert spy.calls[0][0][-1] is bad


def test_every_kernels_parameters_are_its_public_functions() -> None:
    """The order the core's public calls bind (a point after the options) is the Python signature's, for every
    declared function: fd.<name>'s positional parameters, then gravity and out (keyword-only there)."""
    from featherdyn.api.declared import positional_parameters

    for name, decl in DECLARATIONS.items():
        params = ("model", *positional_parameters(decl), *(("gravity",) if "gravity" in decl.options else ()), "out")
        assert K[name].parameters == params, name
        public = getattr(fd, name, None)  # (placements: fd.compile's fk only)
        if public is not None:
            assert tuple(inspect.signature(public).parameters)[:len(params) - 1] == params[:-1], name


def test_the_public_functions_word_the_errors_of_declined_calls() -> None:
    model = tree(TREE_NAMES[1])
    frame = _frame(model)
    q = random_state(model, 4).q
    qn = q.copy()
    qn[-1] = np.inf
    for f in (lambda *a, **k: fd.frame_jacobian(*a, **k), lambda *a, **k: fd.frame_placement(*a, **k)):
        with pytest.raises(ModelError, match="not found"):
            f(model, q, "no such frame")
        with pytest.raises(ShapeError, match="nq="):
            f(model, q[:2], frame)
        with pytest.raises(NonFiniteError, match="q"):
            f(model, qn, frame)
        with pytest.raises(TypeError):
            f(model, q, frame, nonsense=1)
    # declined inputs that the Python function converts: the same numbers
    J = fd.frame_jacobian(model, q, frame, fd.WORLD)
    np.testing.assert_array_equal(fd.frame_jacobian(model, q.tolist(), frame, "WORLD"), J)
    np.testing.assert_array_equal(fd.frame_jacobian(model, q.astype(">f8"), frame, reference="world"), J)


def test_the_reference_default_backend_sends_every_call_to_the_general_function() -> None:
    model = tree(TREE_NAMES[0])
    frame = _frame(model)
    q = random_state(model, 5).q
    jac, spy = spied("frame_jacobian")
    assert isinstance(jac(model, q, frame), np.ndarray) and not spy.calls
    fd.set_default_backend("reference")
    try:
        assert jac(model, q, frame) == "general" and len(spy.calls) == 1
    finally:
        fd.set_default_backend(None)
    assert isinstance(jac(model, q, frame), np.ndarray) and len(spy.calls) == 1


def test_the_objects_look_like_their_functions() -> None:
    names = (*DYNAMICS, "frame_jacobian", "frame_placement", "forward_kinematics", "center_of_mass")
    pairs = [(getattr(fd, name), getattr(fd, name).__wrapped__) for name in names]  # declared
    for f, general in pairs:
        name = f.__name__
        module = "featherdyn"
        assert getattr(fd, name) is f and f.__qualname__ == name
        assert f.__module__ == module and f.__wrapped__ is general
        assert f.__doc__ == general.__doc__ and "`(" in f.__doc__
        assert inspect.signature(f) == inspect.signature(general)
        assert pickle.loads(pickle.dumps(f)) is f
        assert repr(f) == f"<function {module}.{name} (one-state calls in the compiled core)>"
        assert inspect.isroutine(f)  # help() documents it as a function, with its signature
        assert f"{name}(model: 'Model', q: " in pydoc.render_doc(f, renderer=pydoc.plaintext)

        class Holder:
            method = f

        assert Holder.method is f and Holder().method is f  # it does not bind, as a builtin function
    cm = fd.compile(tree(TREE_NAMES[0]))
    assert cm.fk.__qualname__ == "CompiledModel.fk" and "(..., nb, 4, 4)" in cm.fk.__doc__
    assert list(inspect.signature(cm.fk).parameters) == ["q", "out"]


def test_declared_call_refuses_wrong_constants() -> None:
    with pytest.raises(ValueError, match="extra must be"):
        _core.declared_call(K["rnea"], print, (CoreHandle, K["crba"], *REFERENCES, None), None)
    with pytest.raises(ValueError, match="extra must be"):  # no record
        _core.declared_call(K["rnea"], print, (CoreHandle, K["rnea"], *REFERENCES), None)
    bad_records = [
        "not callable",
        ("PluckerTransform", ("rotation", 0)),  # not a class
        (fd.PluckerTransform, ("rotation", 2)),  # frame_placement has two outputs
        (fd.PluckerTransform, ("rotation", -2)),
        (fd.PluckerTransform, ("rotation", 1 << 80)),
        (fd.PluckerTransform, ("rotation",)),
        (fd.PluckerTransform, (0, 0)),
        (fd.PluckerTransform, ["rotation", 0]),
    ]
    for record in bad_records:
        with pytest.raises(ValueError, match="record must be"):
            _core.declared_call(K["frame_placement"], print, (CoreHandle, K["frame_placement"], *REFERENCES, record),
                                None)
    for field in ("inverse", "no_such_field"):  # a method, and no attribute at all: not a data descriptor
        with pytest.raises(ValueError, match="is not a field of"):
            _core.declared_call(K["frame_placement"], print, (CoreHandle, K["frame_placement"], *REFERENCES,
                                                              (fd.PluckerTransform, (field, 0))), None)
    cm = core._view(tree(TREE_NAMES[0])).cm
    with pytest.raises(ValueError, match="record must be"):  # a bound method has no model argument
        _core.declared_call(K["frame_placement"], print, (K["frame_placement"], {}, *REFERENCES,
                                                          (fd.PluckerTransform, ("rotation", -1))), cm)
    with pytest.raises(TypeError, match="core's Model"):
        _core.declared_call(K["placements"], print, (K["placements"], {}, *REFERENCES, None), "not a core model")


def test_a_record_is_made_in_c_as_in_python() -> None:
    model = tree(TREE_NAMES[2])
    st = random_state(model, 3)
    for args in [(st.q,), (st.q, st.v), (st.q, st.v, st.a)]:
        kin = fd.forward_kinematics(model, *args)  # made in C
        general = fd.forward_kinematics.__wrapped__(model, *args, backend="compiled")  # made in Python
        assert type(kin) is fd.Kinematics and kin.model is model
        for a, b in [(kin.placements, general.placements), (kin.parent_placements, general.parent_placements)]:
            np.testing.assert_array_equal(a.rotation, b.rotation)
            np.testing.assert_array_equal(a.translation, b.translation)
            assert not a.rotation.flags.writeable
        for a, b in [(kin.velocities, general.velocities), (kin.accelerations, general.accelerations)]:
            assert (a is None) == (b is None) and (a is None or np.array_equal(a.vector, b.vector))
        assert (kin.velocities is None) == (len(args) < 2) and (kin.accelerations is None) == (len(args) < 3)
    c = fd.center_of_mass(model, st.q, st.v)  # a function of the outputs
    assert type(c) is fd.CenterOfMass and c.velocity.shape == (3,)
    assert type(fd.center_of_mass(model, st.q)) is np.ndarray
    # with out= the C path declines and the Python path makes the record of the given arrays (one for each output:
    # a (4, 4) array is not frame_placement's (rotation, translation))
    with pytest.raises(fd.ShapeError, match="out: expected 2 arrays for rotation, translation, got ndarray"):
        fd.frame_placement(model, st.q, 0, out=np.empty((4, 4)))
    R, p = np.empty((3, 3)), np.empty(3)
    T = fd.frame_placement(model, st.q, 0, out=(R, p))
    assert np.array_equal(T.rotation, R) and np.array_equal(T.translation, p) and R.flags.writeable
    assert np.array_equal(T.rotation, fd.frame_placement(model, st.q, 0).rotation)


def test_a_named_tuple_record_is_made_in_c_as_its_class_makes_it() -> None:
    """A NamedTuple record (the derivatives') is made in C by tuple.__new__: the same type and fields, bit for bit,
    as the class called with the outputs in Python; Kernel.fresh makes one when given its class, and refuses a
    class that is not a tuple's; no reference is kept."""
    model = tree(TREE_NAMES[2])
    st = random_state(model, 4)
    frame = _frame(model)
    r = fd.kinematics_derivatives(model, st.q, st.v, st.a, frame)  # made in C
    general = fd.kinematics_derivatives.__wrapped__(model, st.q, st.v, st.a, frame, backend="compiled")
    assert type(r) is fd.KinematicsDerivatives and type(general) is fd.KinematicsDerivatives
    assert r._fields == general._fields and len(r) == len(general) == len(fd.KinematicsDerivatives._fields) == 8
    for name in r._fields:
        np.testing.assert_array_equal(getattr(r, name), getattr(general, name))
    cm = core._view(model).cm
    kernel = K["kinematics_derivatives"]
    opts = _core.Options(frame=model.frame_id(frame))
    plain = kernel.fresh(cm, [st.q, st.v, st.a, None], opts)
    made = kernel.fresh(cm, [st.q, st.v, st.a, None], opts, fd.KinematicsDerivatives)
    assert type(plain) is tuple and type(made) is fd.KinematicsDerivatives
    for a, b, c in zip(plain, made, r, strict=True):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(b, c)
    for bad in (dict, fd.KinematicsDerivatives(*plain), "KinematicsDerivatives"):
        with pytest.raises(TypeError, match="record must be None or a NamedTuple class"):
            kernel.fresh(cm, [st.q, st.v, st.a, None], opts, bad)
    watched = (model, st.q, st.v, st.a, fd.KinematicsDerivatives)
    before = [sys.getrefcount(x) for x in watched]
    for _ in range(200):
        fd.kinematics_derivatives(model, st.q, st.v, st.a, frame)
        kernel.fresh(cm, [st.q, st.v, st.a, None], opts, fd.KinematicsDerivatives)
    assert [sys.getrefcount(x) for x in watched] == before


def test_a_named_tuple_records_out_is_written_in_c() -> None:
    """With out= (an array for each output, every output always formed), a NamedTuple record's call stays in C:
    the record of the given arrays themselves, with the fresh call's bits. Arrays the kernel does not take as they
    are (a wrong dtype, shape or count, an output over an input) go to the Python path; no reference is kept."""
    model = tree(TREE_NAMES[2])
    st = random_state(model, 5)
    n = model.nv
    fresh = fd.rnea_second_derivatives(model, st.q, st.v, st.a)
    f, spy = spied("rnea_second_derivatives")
    outs = tuple(np.full((n, n, n), np.nan) for _ in range(4))
    r = f(model, st.q, st.v, st.a, out=outs)
    assert not spy.calls
    assert type(r) is fd.RneaSecondDerivatives and all(x is y for x, y in zip(r, outs, strict=True))
    for x, y in zip(r, fresh, strict=True):
        np.testing.assert_array_equal(x, y)
    r = fd.rnea_second_derivatives(model, st.q, st.v, st.a, out=outs)  # the public function: the same
    assert type(r) is fd.RneaSecondDerivatives and all(x is y for x, y in zip(r, outs, strict=True))
    shared = np.zeros((n, n, n))
    v_in_out = shared.reshape(-1)[n:2 * n]  # an input inside an output's memory
    v_in_out[:] = st.v
    declined = [
        (outs[0].astype(np.float32),) + outs[1:],
        outs[:3],
        (np.empty((n, n, n + 1)),) + outs[1:],
        list(outs),
    ]
    for bad in declined:
        spy.calls.clear()
        assert f(model, st.q, st.v, st.a, out=bad) == "general"
        assert len(spy.calls) == 1 and spy.calls[0][1]["out"] is bad
    spy.calls.clear()
    overlap = (shared,) + outs[1:]
    assert f(model, st.q, v_in_out, st.a, out=overlap) == "general" and len(spy.calls) == 1
    r = fd.rnea_second_derivatives(model, st.q, v_in_out, st.a, out=overlap)  # the one rule: as without out=
    assert r.d2tau_dq2 is shared
    for x, y in zip(r, fresh, strict=True):
        np.testing.assert_array_equal(x, y)
    watched = (model, st.q, st.v, st.a, *outs, fd.RneaSecondDerivatives)
    before = [sys.getrefcount(x) for x in watched]
    for _ in range(200):
        fd.rnea_second_derivatives(model, st.q, st.v, st.a, out=outs)
    assert [sys.getrefcount(x) for x in watched] == before


def test_compiled_fk_writes_out_or_declines() -> None:
    model = tree(TREE_NAMES[2])
    cm = fd.compile(model)
    q = random_state(model, 6).q
    H = np.empty((model.nbodies, 4, 4))
    assert cm.fk(q, out=H) is H
    assert cm.fk(q, H) is H
    fresh = cm.fk(q)
    assert fresh is not H and type(fresh) is np.ndarray and fresh.flags.writeable
    np.testing.assert_array_equal(fresh, H)
    np.testing.assert_array_equal(cm.fk(q.tolist()), H)
    np.testing.assert_array_equal(cm.fk(q=q), H)
    with pytest.raises(ShapeError):
        cm.fk(q, out=np.empty((model.nbodies + 1, 4, 4)))
    ro = np.empty((model.nbodies, 4, 4))
    ro.setflags(write=False)
    with pytest.raises((ValueError, TypeError)):
        cm.fk(q, out=ro)
    with pytest.raises(TypeError):
        cm.fk(q, out=H, extra=1)
    with pytest.raises(ShapeError):
        cm.fk(q[:-1])


def test_alternating_and_replaced_models_use_their_own_handles() -> None:
    a, b = tree(TREE_NAMES[0]), tree(TREE_NAMES[3])
    fa, fb = _frame(a), _frame(b)
    qa, qb = random_state(a, 7).q, random_state(b, 7).q
    Ja, Jb = fd.frame_jacobian(a, qa, fa, backend="compiled"), fd.frame_jacobian(b, qb, fb, backend="compiled")
    for _ in range(3):
        np.testing.assert_array_equal(fd.frame_jacobian(a, qa, fa), Ja)
        np.testing.assert_array_equal(fd.frame_jacobian(b, qb, fb), Jb)
    del a
    for seed in range(4):  # new models, possibly at the dropped one's address
        c = tree(TREE_NAMES[seed % len(TREE_NAMES)])
        fc, qc = _frame(c), random_state(c, seed).q
        np.testing.assert_array_equal(fd.frame_jacobian(c, qc, fc), fd.frame_jacobian(c, qc, fc, backend="compiled"))
        Xc, Xr = fd.frame_placement(c, qc, fc), fd.frame_placement(c, qc, fc, backend="reference")
        np.testing.assert_allclose(Xc.translation, Xr.translation, rtol=0, atol=1e-12)


def test_eight_threads_on_different_models_get_their_results() -> None:
    models = [tree(TREE_NAMES[k % len(TREE_NAMES)]) for k in range(8)]
    states = [random_state(m, 10 + k).q for k, m in enumerate(models)]
    expected = [fd.frame_jacobian(m, q, _frame(m), fd.WORLD, backend="compiled") for m, q in zip(models, states, strict=True)]
    errors: list[str] = []

    def work(k: int) -> None:
        m, q, frame = models[k], states[k], _frame(models[k])
        for _ in range(300):
            if not np.array_equal(fd.frame_jacobian(m, q, frame, fd.WORLD), expected[k]):
                errors.append(f"thread {k}")
                return

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors


def test_no_reference_leaks_on_fast_declined_and_failing_calls() -> None:
    model = tree(TREE_NAMES[1])
    frame = _frame(model)
    q = random_state(model, 8).q
    qn = q.copy()
    qn[0] = np.nan
    cm = fd.compile(model)
    H = np.empty((model.nbodies, 4, 4))

    v = np.ones(model.nv)

    def calls() -> None:
        fd.rnea(model, q, v, v)
        fd.aba(model, q, v, v, gravity=False)
        fd.crba(model, q)
        with pytest.raises(NonFiniteError):
            fd.rnea(model, qn, v, v)
        fd.frame_jacobian(model, q, frame)
        fd.frame_jacobian(model, q, frame, reference=fd.WORLD)
        fd.frame_placement(model, q, frame)
        cm.fk(q, out=H)
        cm.fk(q)
        fd.frame_jacobian(model, q.tolist(), frame)
        for bad in (qn, q[:1]):
            with pytest.raises((NonFiniteError, ShapeError)):
                fd.frame_jacobian(model, bad, frame)
            with pytest.raises((NonFiniteError, ShapeError)):
                fd.frame_placement(model, bad, frame)

    calls()
    watched = (model, q, qn, v, frame, H, fd.LOCAL, fd.WORLD)
    before = [sys.getrefcount(x) for x in watched]
    for _ in range(200):
        calls()
    assert [sys.getrefcount(x) for x in watched] == before


def _prismatic_pair() -> fd.Model:
    b = fd.ModelBuilder("slides")
    inertia = fd.SpatialInertia(1.0, [0.0, 0.0, 0.05], np.eye(3) * 0.01)
    for i in range(2):
        b.add_body(f"s{i}", parent=i - 1, joint=fd.PrismaticJoint(np.array([1.0, 0.0, 0.0])),
                   placement=fd.PluckerTransform(np.eye(3), [0.0, 0.1, 0.0]), inertia=inertia)
    return b.build()


def test_an_overflowing_jacobian_is_a_non_finite_error_at_its_first_element() -> None:
    model = _prismatic_pair()  # two slides of 1e308 along x: the frame's origin overflows
    q = np.array([1e308, 1e308])
    cm = core._view(model).cm
    frame = model.frames[-1].name
    for code, ref in enumerate(REFERENCES):
        J = np.empty((6, model.nv))
        status = K["frame_jacobian"].into(cm, [q], [J], _core.Options(frame=model.frame_id(frame), reference=code))
        assert status & 7 == 2 and status >> 8 == np.flatnonzero(~np.isfinite(J))[0]  # NONFINITE, first element
        for backend in (None, "reference", "compiled"):
            with pytest.raises(NonFiniteError, match="overflowed"):
                fd.frame_jacobian(model, q, frame, ref, backend=backend)
    for backend in (None, "reference", "compiled"):
        with pytest.raises(NonFiniteError, match="overflowed"):
            fd.frame_placement(model, q, frame, backend=backend)
    np.testing.assert_array_equal(fd.frame_jacobian(model, np.array([1e300, 1e300]), frame),
                                  fd.frame_jacobian(model, np.array([1e300, 1e300]), frame, backend="compiled"))


class _Name(str):
    """A str subclass (its hash and equality could run Python code): declined, the general path reads it."""


def test_unusual_frame_and_reference_objects_are_declined_and_read_by_the_general_path() -> None:
    model = tree(TREE_NAMES[0])
    frame = _frame(model)
    fid = model.frame_id(frame)
    q = random_state(model, 11).q
    J = fd.frame_jacobian(model, q, frame, fd.WORLD)
    np.testing.assert_array_equal(fd.frame_jacobian(model, q, _Name(frame), fd.WORLD), J)
    np.testing.assert_array_equal(fd.frame_jacobian(model, q, np.int64(fid), fd.WORLD), J)
    np.testing.assert_array_equal(fd.frame_jacobian(model, q, fid, fd.WORLD), J)
    X = fd.frame_placement(model, q, _Name(frame))
    np.testing.assert_array_equal(X.translation, fd.frame_placement(model, q, frame).translation)
    with pytest.raises((TypeError, ValueError)):
        fd.frame_jacobian(model, q, frame, True)
    with pytest.raises((TypeError, ValueError, ModelError)):
        fd.frame_jacobian(model, q, 2.0)


class _Raising:
    """A model stand-in whose ``_core`` raises: the fast path declines, the general path words it."""

    @property
    def _core(self) -> object:
        raise RuntimeError("not a model")


def test_a_model_stand_in_whose_core_attribute_raises_gets_the_general_error() -> None:
    q = np.zeros(3)
    for call in (lambda: fd.frame_jacobian(_Raising(), q, "f"), lambda: fd.crba(_Raising(), q),
                 lambda: fd.rnea(_Raising(), q, q, q), lambda: fd.frame_placement(_Raising(), q, 0)):
        with pytest.raises(fd.errors.FeatherdynError, match="expected a featherdyn Model, got _Raising"):
            call()


def test_the_reference_backend_from_the_environment_switches_the_objects_off() -> None:
    script = (
        "import featherdyn as fd, numpy as np\n"
        "from featherdyn import core\n"
        "from featherdyn.api import _backend\n"
        "from featherdyn.core._model_view import CoreHandle\n"
        "calls = []\n"
        "k = core._core.kernels['crba']\n"
        "refs = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)\n"
        "crba = core._core.declared_call(k, lambda *a, **kw: calls.append(a) or 'general', (CoreHandle, k, *refs, None), None)\n"
        "m = fd.load_robot('panda'); core._view(m)  # the core handle exists\n"
        "q = fd.neutral(m)\n"
        "r = crba(m, q)\n"
        "print(fd.default_backend(), isinstance(r, str), len(calls))\n"
    )
    env = dict(os.environ)
    for value, expected in (("reference", "reference True 1"), ("", "None False 0")):
        env["FEATHERDYN_BACKEND"] = value
        out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True)
        assert out.stdout.split() == expected.split(), out.stdout + out.stderr


@pytest.mark.parametrize("name", TREE_NAMES)
def test_compiled_methods_equal_their_entry_points_and_write_into_out(name: str) -> None:
    model = tree(name)
    cm = fd.compile(model)
    h = core._view(model).cm
    st = random_state(model, 12)
    q, v, a, fx = st.q, st.v, st.a, st.f_ext
    frame = _frame(model)
    fid = model.frame_id(frame)
    nv = model.nv
    cases = [
        (lambda out=None: cm.rnea(q, v, a, out=out), K["rnea"].fresh(h, [q, v, a, None]), (nv,)),
        (lambda out=None: cm.rnea(q, v, a, fx, out), K["rnea"].fresh(h, [q, v, a, fx]), (nv,)),
        (lambda out=None: cm.aba(q, v, a, f_ext=fx, out=out), K["aba"].fresh(h, [q, v, a, fx]), (nv,)),
        (lambda out=None: cm.nle(q, v, out=out), K["nonlinear_effects"].fresh(h, [q, v]), (nv,)),
        (lambda out=None: cm.gravity(q, out), K["generalized_gravity"].fresh(h, [q]), (nv,)),
        (lambda out=None: cm.crba(q, out=out), K["crba"].fresh(h, [q]), (nv, nv)),
        (lambda out=None: cm.frame_jacobian(q, frame, fd.WORLD, out), K["frame_jacobian"].fresh(h, [q], _core.Options(frame=fid, reference=1)), (6, nv)),
        (lambda out=None: cm.frame_jacobian(q, fid, out=out), K["frame_jacobian"].fresh(h, [q], _core.Options(frame=fid)), (6, nv)),
    ]
    for call, expected, shape in cases:
        got = call()
        assert type(got) is np.ndarray and got.flags.owndata
        np.testing.assert_array_equal(got, expected)
        out = np.full(shape, np.nan)
        assert call(out) is out
        np.testing.assert_array_equal(out, expected)
        with pytest.raises(ShapeError):
            call(np.empty(shape[:-1] + (shape[-1] + 1,)))
    np.testing.assert_array_equal(cm.rnea(q.tolist(), v, a), cm.rnea(q, v, a))  # declined: converted
    np.testing.assert_array_equal(cm.frame_jacobian(q, frame, "WORLD"), cm.frame_jacobian(q, frame, fd.WORLD))
    with pytest.raises(TypeError):
        cm.rnea(q, v, a, None, None, True)  # a sixth positional argument (gravity is keyword-only): a TypeError
    for method in ("rnea", "nle", "gravity", "crba", "aba", "fk", "frame_jacobian"):
        f = getattr(cm, method)
        assert f.__qualname__ == f"CompiledModel.{method}" and f.__doc__ and f.__wrapped__.__name__ == method
