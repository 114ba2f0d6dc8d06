"""Stacked states taken in C: the declared kernels' ``fresh`` / ``into`` and the public calls built on them.

An input of its declared shape under leading lengths B (the same B for every input that has leading lengths; an input
of exactly its declared shape is read by every state) is a stack of ∏ B states, and the core runs it on its one batch
path (``declare.hpp: run_taken`` → ``run_rows``) without the Python batch path (``core.declared.run``). Checked here:

* for every declared algorithm, the stacked call equals the Python batch path bit for bit, with a broadcast one-state
  input too, fresh and into given arrays; a public call with a stack does not reach its Python function;
* a record's stacked arrays are read-only, as the Python path makes them;
* everything else goes to the Python function with the same arguments, which gives the result or words the error:
  broadcast leading lengths, an empty stack, more than eight leading lengths, a bad row (its batch index named), an
  ``out`` over an input (the one rule: the result as without it), an ``out`` of another stack's shape.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from _core_helpers import spied
from _models import library_robot

import featherdyn as fd
from featherdyn import core
from featherdyn.api.declarations import DECLARATIONS
from featherdyn.core import _core
from featherdyn.core import declared as _declared
from featherdyn.errors import NonFiniteError, ShapeError

K = _core.kernels
WIDTH = _core.simd()[1]
N = 2 * WIDTH + 3  # two full SIMD groups and a tail


def _model() -> fd.Model:
    model = library_robot("solo12", True)
    assert model is not None
    return model


def _lengths(model: fd.Model, shape: tuple[Any, ...]) -> tuple[int, ...]:
    lengths = {"nq": model.nq, "nv": model.nv, "nb": model.nbodies, "np": 10 * model.nbodies}
    return tuple(lengths[d] if isinstance(d, str) else int(d) for d in shape)


def _inputs(model: fd.Model, name: str, lead: tuple[int, ...], seed: int) -> list[np.ndarray]:
    """Every input of the declared kernel ``name`` (optional ones given) under the leading lengths ``lead``."""
    rng = np.random.default_rng(seed)
    xs = []
    for n, shape, _ in _declared.SPECS[name].inputs:
        if n in ("q", "q0", "q1"):
            xs.append(np.asarray(fd.random_configuration(model, rng, size=lead) if lead else
                                 fd.random_configuration(model, rng)))
        else:
            xs.append(0.5 * rng.normal(size=lead + _lengths(model, shape)))
    return xs


def _options(model: fd.Model, name: str) -> dict[str, Any]:
    opts: dict[str, Any] = {}
    for o in _declared.SPECS[name].options:
        opts[o] = {"frame": len(model.frames) - 1, "reference": 1, "gravity": True}[o]
    return opts


def _arrays(r: Any) -> tuple[np.ndarray, ...]:
    return tuple(r) if isinstance(r, tuple) else (r,)


def _same(a: Any, b: Any) -> bool:
    xs, ys = _arrays(a), _arrays(b)
    return len(xs) == len(ys) and all(x.shape == y.shape and np.array_equal(x, y) for x, y in zip(xs, ys, strict=True))


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_a_stack_equals_the_python_batch_path_bit_for_bit(name: str) -> None:
    model = _model()
    cm = core._view(model).cm
    opts = _options(model, name)
    core_opts = _declared.call_options(**opts)
    for lead in ((N,), (2, 3), (1,)):
        xs = _inputs(model, name, lead, seed=len(lead))
        expected = _declared.run(name, model, lead, xs, options=opts)
        got = K[name].fresh(cm, xs, core_opts)
        assert got is not None and _same(got, expected), lead
        assert all(x.shape[:len(lead)] == lead for x in _arrays(got))
        outs = [np.full(x.shape, np.nan) for x in expected]
        assert K[name].into(cm, xs, outs, core_opts) == 0
        assert _same(tuple(outs), expected)
    # an input of one state among stacked ones is read by every state (the Python path broadcasts it)
    for one in range(len(xs) if len(xs) > 1 else 0):
        xs = _inputs(model, name, (N,), seed=7)
        xs[one] = np.ascontiguousarray(xs[one][0])
        got = K[name].fresh(cm, xs, core_opts)
        assert got is not None and _same(got, _declared.run(name, model, (N,), xs, options=opts)), one


def test_a_public_call_with_a_stack_is_finished_in_c() -> None:
    model = _model()
    q, v, a, _ = _inputs(model, "rnea", (N,), seed=1)
    fd.rnea(model, q[0], v[0], a[0])  # (the model's core handle exists)
    rnea, spy = spied("rnea")
    expected = _declared.run("rnea", model, (N,), [q, v, a, None], options={"gravity": True})[0]
    for args, kwargs in [((model, q, v, a), {}), ((model, q), {"v": v, "a": a}), ((model, q, v, a), {"gravity": True})]:
        r = rnea(*args, **kwargs)
        assert not spy.calls and type(r) is np.ndarray and r.flags.writeable and np.array_equal(r, expected)
    out = np.full((N, model.nv), np.nan)
    assert rnea(model, q, v, a, out=out) is out and np.array_equal(out, expected) and not spy.calls
    # one state broadcast to the stack
    r = rnea(model, q, v[0], a)
    assert not spy.calls and np.array_equal(r, _declared.run("rnea", model, (N,), [q, v[0], a, None])[0])
    # the public function itself
    np.testing.assert_array_equal(fd.rnea(model, q.reshape(1, N, -1), v.reshape(1, N, -1), a.reshape(1, N, -1)),
                                  expected.reshape(1, N, -1))


def test_a_records_stacked_arrays_are_read_only() -> None:
    model = _model()
    q = _inputs(model, "frame_placement", (N,), seed=2)[0]
    frame = model.frames[-1].name
    fd.frame_placement(model, q[0], frame)
    place, spy = spied("frame_placement")
    X = place(model, q, frame)
    assert not spy.calls and type(X) is fd.PluckerTransform
    R, p = _declared.run("frame_placement", model, (N,), [q], options={"frame": len(model.frames) - 1})
    np.testing.assert_array_equal(X.rotation, R)
    np.testing.assert_array_equal(X.translation, p)
    assert not X.rotation.flags.writeable and not X.translation.flags.writeable
    with pytest.raises(ValueError):
        X.rotation[0, 0, 0] = 1.0
    Y = fd.frame_placement(model, q, frame, backend="compiled")  # the Python path's record
    assert not Y.rotation.flags.writeable and np.array_equal(Y.rotation, R)


def test_what_a_stack_is_not_goes_to_the_python_function() -> None:
    model = _model()
    q, v, a, _ = _inputs(model, "rnea", (N,), seed=3)
    fd.rnea(model, q[0], v[0], a[0])
    rnea, spy = spied("rnea")
    nan_row = v.copy()
    nan_row[3, 1] = np.nan
    many = q.reshape((1,) * 8 + (N, model.nq))
    shared = np.concatenate([q.reshape(-1), np.zeros(N * model.nv)])
    over_q = shared[: N * model.nv].reshape(N, model.nv)  # an out over q
    declined = [
        ((model, q, v[:1], a), {}),  # a leading length of 1 broadcast: NumPy's rule, the Python path's
        ((model, q, v[:-1], a), {}),  # lengths that do not broadcast
        ((model, q[:0], v[:0], a[:0]), {}),  # an empty stack
        ((model, many, v, a), {}),  # nine leading lengths
        ((model, q, nan_row, a), {}),  # a bad row
        ((model, shared[: N * model.nq].reshape(N, model.nq), v, a), {"out": over_q}),
        ((model, q, v, a), {"out": np.empty((N + 1, model.nv))}),
        ((model, q, v, a), {"out": np.empty(model.nv)}),
        ((model, q, v, a), {"out": np.empty((N, model.nv), dtype=np.float32)}),
    ]
    for args, kwargs in declined:
        spy.calls.clear()
        assert rnea(*args, **kwargs) == "general", [np.shape(x) for x in args[1:]]
        assert len(spy.calls) == 1 and all(x is y for x, y in zip(spy.calls[0][0], args, strict=True))
    # ... which gives the result or words the error
    expected = _declared.run("rnea", model, (N,), [q, v, a, None])[0]
    np.testing.assert_array_equal(fd.rnea(model, q, v[:1], a), _declared.run("rnea", model, (N,), [q, v[:1], a, None])[0])
    with pytest.raises(ShapeError):
        fd.rnea(model, q, v[:-1], a)
    assert fd.rnea(model, q[:0], v[:0], a[:0]).shape == (0, model.nv)
    np.testing.assert_array_equal(fd.rnea(model, many, v, a).reshape(N, -1), expected)
    with pytest.raises(NonFiniteError, match=r"v: .* at index \(3, 1\)"):
        fd.rnea(model, q, nan_row, a)
    qs = shared[: N * model.nq].reshape(N, model.nq)
    qs[...] = q
    r = fd.rnea(model, qs, v, a, out=over_q)
    assert r is over_q and np.array_equal(r, expected)  # the one rule: the result as without out
    with pytest.raises(ShapeError):
        fd.rnea(model, q, v, a, out=np.empty((N + 1, model.nv)))


def test_the_contact_kernels_take_stacks_as_their_public_functions_give_them() -> None:
    """fd.constrained_dynamics, its derivatives and the impulse derivatives on a stack (f_ext too) equal the loop over
    their states bit for bit: the kernels' fresh takes the stack (the public function's one path to its batch)."""
    model = _model()
    cons = [fd.PointContact(f) for f in ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")]
    rng = np.random.default_rng(5)
    q = np.asarray(fd.random_configuration(model, rng, size=(2, WIDTH + 1)))
    v = 0.3 * rng.normal(size=(2, WIDTH + 1, model.nv))
    tau = rng.normal(size=(2, WIDTH + 1, model.nv))
    fx = 0.1 * rng.normal(size=(2, WIDTH + 1, model.nbodies, 6))
    for f, args, kwargs in [(fd.constrained_dynamics, (q, v, tau), {"f_ext": fx}),
                            (fd.constrained_dynamics_derivatives, (q, v, tau), {"f_ext": fx}),
                            (fd.impulse_dynamics_derivatives, (q, v), {})]:
        stacked = f(model, *args, cons, **kwargs)
        for i in range(2):
            for k in range(WIDTH + 1):
                one = f(model, *(x[i, k] for x in args), cons, **{n: x[i, k] for n, x in kwargs.items()})
                for name in ("ddq", "lagrange") if f is fd.constrained_dynamics else one._fields:
                    assert np.array_equal(getattr(stacked, name)[i, k], getattr(one, name)), (f.__name__, name)
        if f is fd.constrained_dynamics:
            assert [x.shape for x in stacked.forces] == [(2, WIDTH + 1, 3)] * 4
            assert stacked.residual.shape == (2, WIDTH + 1)


def test_a_compiled_models_method_takes_a_stack_in_c() -> None:
    """fd.compile(model)'s methods are the same public calls bound to the model: a stack runs in C there too (its
    Python function, which would re-check the arguments, is not called), with the Python batch path's bits."""
    model = _model()
    cm = fd.compile(model, warmup=False)
    q, v, a, _ = _inputs(model, "rnea", (2, 5), seed=9)
    expected = _declared.run("rnea", model, (2, 5), [q, v, a, None])[0]
    calls = []
    general = cm.rnea.__wrapped__

    def spy(*args: Any, **kwargs: Any) -> Any:
        calls.append(args)
        return general(*args, **kwargs)

    bound = _core.declared_call(K["rnea"], spy, (K["rnea"], core._view(model).frames, fd.LOCAL, fd.WORLD,
                                                 fd.LOCAL_WORLD_ALIGNED, None), core._view(model).cm)
    np.testing.assert_array_equal(bound(q, v, a), expected)
    out = np.empty_like(expected)
    assert bound(q, v, a, out=out) is out and np.array_equal(out, expected) and not calls
    np.testing.assert_array_equal(cm.rnea(q, v, a), expected)
    np.testing.assert_array_equal(bound(q.tolist(), v, a), expected)  # a list: the Python function converts it
    assert len(calls) == 1
