"""Every declared algorithm (``featherdyn/api/declarations.py``) through every front end its declaration makes.

One state, batches of any shape (equal to the loop over their states, bit for bit, the other inputs
broadcast), the reference backend (agreeing with the core), ``out=`` (one state and batches, a record's
function's too; an ``out`` sharing memory with ``q`` gives the same result), ``fd.compile(model)``'s method (with ``out=`` and with Dask
arrays), the spellings of native float64, float32 (kept), lists, and bad input worded by the public checks.
The numbers themselves are checked against Pinocchio, closed forms and finite differences in each
algorithm's own tests.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.api import declarations
from featherdyn.api.declarations import DECLARATIONS
from featherdyn.api.declared import AFTER_OPTIONS
from featherdyn.core.declared import SPECS
from featherdyn.errors import NonFiniteError, QuaternionNormError, ShapeError

NAMES = sorted(DECLARATIONS)


def _parts(x: Any) -> tuple[np.ndarray, ...]:
    """A result's arrays: the array, each of a tuple's, or a record's (its spatial values' arrays)."""
    if isinstance(x, fd.Kinematics):
        values = (x.placements, x.parent_placements, x.velocities, x.accelerations)
        return tuple(a for v in values if v is not None for a in _parts(v))
    if isinstance(x, fd.PluckerTransform):
        return (x.rotation, x.translation)
    if isinstance(x, (fd.SpatialForce, fd.SpatialMotion)):
        return (x.vector,)
    return tuple(x) if isinstance(x, tuple) else (x,)


def _function(name: str) -> Any:
    """The declaration's public function (``placements`` is only fd.compile's ``fk``)."""
    return getattr(declarations, name)


def _rel(a: Any, b: Any) -> float:
    return max(float(np.abs(x - y).max() / max(1.0, np.abs(y).max())) for x, y in zip(_parts(a), _parts(b), strict=True))


def _equal(a: Any, b: Any) -> bool:
    return len(_parts(a)) == len(_parts(b)) and all(np.array_equal(x, y) for x, y in zip(_parts(a), _parts(b)))


def _empty(shapes: tuple[tuple[int, ...], ...], fill: float = np.nan) -> Any:
    """``out`` for these output shapes: one array, or a tuple of them."""
    arrays = tuple(np.full(s, fill) for s in shapes)
    return arrays[0] if len(arrays) == 1 else arrays


def _args(model: fd.Model, name: str, q: Any, f_ext: Any) -> tuple[tuple[Any, ...], dict[str, Any]]:
    """The declaration's inputs for configurations ``q`` (``q0``; velocities, accelerations, a second configuration
    ``q1`` and a point made from q's batch shape and dtype), and its options: a frame on the last body, in WORLD (in
    LOCAL_WORLD_ALIGNED with a point, where the point changes the result); a point by name (it comes after the
    options)."""
    decl = DECLARATIONS[name]
    qa = np.asarray(q)
    dtype = qa.dtype if qa.dtype.kind == "f" else np.dtype(np.float64)
    vector = (0.3 * np.cos(0.7 * np.arange(model.nv)) * np.ones(qa.shape[:-1] + (1,))).astype(dtype)
    q1 = np.broadcast_to(fd.random_configuration(model, 99).astype(dtype), qa.shape[:-1] + (model.nq,))
    matrix = (vector[..., :, None] * np.sin(np.arange(model.nv))).astype(dtype)  # (W: (..., nv, nv))
    args = tuple(q if n in ("q", "q0") else q1 if n == "q1" else f_ext if n == "f_ext" else matrix if n == "W"
                 else vector for n in decl.inputs if n not in AFTER_OPTIONS)
    kwargs: dict[str, Any] = {}
    if "frame" in decl.options:
        kwargs["frame"] = model.frames[-1].name
    if "reference" in decl.options:
        kwargs["reference"] = fd.LOCAL_WORLD_ALIGNED if "point" in decl.inputs else fd.WORLD
    if "point" in decl.inputs:
        kwargs["point"] = (np.array([0.05, -0.1, 0.2]) * np.ones(qa.shape[:-1] + (1,))).astype(dtype)
    return args, kwargs


def _call(fn: Any, model: fd.Model | None, name: str, q: Any, f_ext: Any, m: fd.Model, **extra: Any) -> Any:
    args, kwargs = _args(m, name, q, f_ext)
    return fn(*args, **kwargs, **extra) if model is None else fn(model, *args, **kwargs, **extra)


def _shapes(model: fd.Model, name: str) -> tuple[tuple[int, ...], ...]:
    """The outputs' shapes of one state."""
    r = _call(_function(name), model, name, fd.neutral(model), np.zeros((model.nbodies, 6)), model)
    return tuple(np.shape(x) for x in _parts(r))


@pytest.mark.parametrize("name", NAMES)
def test_front_ends(name: str) -> None:
    model = library_robot("solo12", True)
    assert model is not None
    fn = _function(name)
    rng = np.random.default_rng(3)
    Q = fd.random_configuration(model, rng, size=(2, 3))
    FX = rng.normal(size=(2, 3, model.nbodies, 6))
    shapes = _shapes(model, name)
    # a batch of any shape equals the loop over its states, bit for bit (f_ext broadcast as well)
    batch = _call(fn, model, name, Q, FX, model)
    assert tuple(x.shape for x in _parts(batch)) == tuple((2, 3) + s for s in shapes)
    for i in range(2):
        for k in range(3):
            one_state = _call(fn, model, name, Q[i, k], FX[i, k], model)
            assert all(np.array_equal(x[i, k], y) for x, y in zip(_parts(batch), _parts(one_state), strict=True))
    one = _call(fn, model, name, Q[0, 0], FX[0, 0], model)
    # the reference agrees with the core
    ref = _call(fn, model, name, Q[0, 0], FX[0, 0], model, backend="reference")
    assert _rel(ref, one) < 1e-11
    cm = fd.compile(model, warmup=False)
    method = getattr(cm, DECLARATIONS[name].method or name)
    assert _equal(_call(method, None, name, Q[0, 0], FX[0, 0], model), one)
    if DECLARATIONS[name].result is not None:  # a record (or a function of the outputs): out= holds the outputs
        _record_out_forms(fn, method, model, name, Q, FX, one, batch)
    else:
        _out_forms(fn, method, model, name, Q, FX, shapes, one, batch)
    # dtypes: native float64 spelled any way takes the same path; float32 stays float32
    for dt in ("<f8", "=f8", "d", np.dtype("f8").newbyteorder("=")):
        assert _equal(_call(fn, model, name, Q[0, 0].astype(dt), FX[0, 0].astype(dt), model), one)
    assert _equal(_call(fn, model, name, Q[0, 0].astype(">f8"), FX[0, 0], model), one)
    r32 = _call(fn, model, name, Q[0, 0].astype(np.float32), FX[0, 0].astype(np.float32), model)
    assert all(x.dtype == np.float32 for x in _parts(r32)) and _rel(r32, one) < 1e-3
    assert _equal(_call(fn, model, name, list(Q[0, 0]), FX[0, 0].tolist(), model), one)


def _out_forms(fn: Any, method: Any, model: fd.Model, name: str, Q: np.ndarray, FX: np.ndarray,
               shapes: tuple[tuple[int, ...], ...], one: Any, batch: Any) -> None:
    """out=: written and returned, in one state and in a batch, by the function and the compiled method."""
    out = _empty(shapes)
    assert _call(fn, model, name, Q[0, 0], FX[0, 0], model, out=out) is out and _equal(out, one)
    outs = _empty(tuple((2, 3) + s for s in shapes))
    assert _call(fn, model, name, Q, FX, model, out=outs) is outs and _equal(outs, batch)
    # an out sharing memory with q: the same result as without it (one rule: computed, then written)
    size = int(np.prod(shapes[0]))
    buf = np.zeros(size + model.nq)
    buf[:model.nq] = Q[0, 0]
    first = buf[model.nq - 3: model.nq - 3 + size].reshape(shapes[0])
    shared = first if len(shapes) == 1 else (first, *(np.empty(s) for s in shapes[1:]))
    r = _call(fn, model, name, buf[:model.nq], FX[0, 0], model, out=shared)
    assert r is shared and _equal(shared, one)
    out2 = _empty(shapes)
    assert _call(method, None, name, Q[0, 0], FX[0, 0], model, out=out2) is out2 and _equal(out2, one)


def _output_shapes(model: fd.Model, name: str) -> tuple[tuple[int, ...], ...]:
    """The declared outputs' shapes of one state (every one formed: the calls here give every optional input)."""
    lengths = {"nq": model.nq, "nv": model.nv, "nb": model.nbodies}
    return tuple(tuple(lengths.get(d, d) for d in shape) for _, shape, _ in SPECS[name].outputs)


def _core_outputs(model: fd.Model, name: str, q: Any, f_ext: Any) -> tuple[np.ndarray, ...]:
    """The outputs as arrays, from the core layer (``featherdyn.core.<name>``: the frame by index, the reference by
    code), to hold what ``out=`` received against."""
    args, kwargs = _args(model, name, q, f_ext)
    options = [model.resolve_frame(kwargs["frame"])] if "frame" in kwargs else []
    options += [kwargs["reference"].code] if "reference" in kwargs else []
    r = getattr(fd.core, name)(model, *args, *options, **{n: kwargs[n] for n in AFTER_OPTIONS if n in kwargs})
    return tuple(r) if isinstance(r, tuple) else (r,)


def _record_out_forms(fn: Any, method: Any, model: fd.Model, name: str, Q: np.ndarray, FX: np.ndarray, one: Any,
                      batch: Any) -> None:
    """out= of a function whose result is a record: an array for each output, written (the core layer's outputs),
    the record made of them equal to the one without out=, in one state and in a batch, by the function and the
    compiled method; the arrays stay the caller's (writable: a second call takes them again), and an out sharing
    memory with q gives the same result."""
    shapes = _output_shapes(model, name)
    tuple_record = isinstance(one, tuple) and len(one) == len(shapes)  # (a NamedTuple of the outputs)
    for q, fx, expected, size in ((Q[0, 0], FX[0, 0], one, ()), (Q, FX, batch, (2, 3))):
        out = tuple(np.full(size + s, np.nan) for s in shapes)
        given = out[0] if len(out) == 1 else out
        for _ in range(2):  # twice: the caller's arrays are still writable after the first
            r = _call(fn, model, name, q, fx, model, out=given)
            assert _equal(r, expected)
            assert all(np.array_equal(x, y) for x, y in zip(out, _core_outputs(model, name, q, fx), strict=True))
        if tuple_record:  # a record of the outputs holds the arrays themselves, and is itself an out=
            assert all(x is y for x, y in zip(r, out, strict=True))
            assert all(x is y for x, y in zip(_call(fn, model, name, q, fx, model, out=r), out, strict=True))
        assert all(x.flags.writeable for x in out)
    size = int(np.prod(shapes[0]))
    buf = np.zeros(size + model.nq)
    buf[:model.nq] = Q[0, 0]
    first = buf[model.nq - 3: model.nq - 3 + size].reshape(shapes[0])
    shared = first if len(shapes) == 1 else (first, *(np.empty(s) for s in shapes[1:]))
    assert _equal(_call(fn, model, name, buf[:model.nq], FX[0, 0], model, out=shared), one)
    out2 = tuple(np.empty(s) for s in shapes)
    assert _equal(_call(method, None, name, Q[0, 0], FX[0, 0], model, out=out2[0] if len(out2) == 1 else out2), one)


@pytest.mark.parametrize("name", NAMES)
def test_bad_input(name: str) -> None:
    model = library_robot("solo12", True)
    assert model is not None
    fn = _function(name)
    decl = DECLARATIONS[name]
    rng = np.random.default_rng(4)
    q = fd.random_configuration(model, rng)
    fx = rng.normal(size=(model.nbodies, 6))
    shapes = _shapes(model, name)
    with pytest.raises(ShapeError, match=f"{decl.inputs[0]}: expected trailing dimension nq=19"):  # (q or q0)
        _call(fn, model, name, q[:5], fx, model)
    bad = q.copy()
    bad[2] = np.nan
    with pytest.raises(NonFiniteError, match="q"):
        _call(fn, model, name, bad, fx, model)
    bad = q.copy()
    bad[3:7] *= 2
    with pytest.raises(QuaternionNormError):
        _call(fn, model, name, bad, fx, model)
    # out= of every declared function (a record's: an array for each output): a wrong shape, a read-only array,
    # not arrays
    shapes = _output_shapes(model, name) if decl.result is not None else shapes
    with pytest.raises(ShapeError, match="out: expected"):
        _call(fn, model, name, q, fx, model, out=_empty(tuple((3, 3, 3) for _ in shapes)))
    ro = _empty(shapes)
    for x in _parts(ro):
        x.setflags(write=False)
    with pytest.raises(ShapeError, match="read-only"):
        _call(fn, model, name, q, fx, model, out=ro)
    with pytest.raises(ShapeError, match="out"):
        _call(fn, model, name, q, fx, model, out=[1, 2])
    with pytest.raises(TypeError, match=name):
        _call(fn, model, name, q, fx, model, no_such_option="x")
    with pytest.raises(ShapeError, match="model"):
        _call(fn, "panda", name, q, fx, model)
    if "gravity" in decl.options:
        with pytest.raises(fd.errors.DTypeError, match="gravity"):
            _call(fn, model, name, q, fx, model, gravity="no")
    if "f_ext" in decl.inputs:
        args, kwargs = _args(model, name, q, fx)
        at = decl.inputs.index("f_ext")
        for bad_f, error in [(fx[:3], ShapeError), (np.where(np.arange(6) == 4, np.inf, fx), NonFiniteError)]:
            with pytest.raises(error, match="f_ext"):
                fn(model, *args[:at], bad_f, *args[at + 1:], **kwargs)
        if "f_ext" not in decl.optional:
            with pytest.raises(ShapeError, match="f_ext"):
                fn(model, *args[:at], None, *args[at + 1:], **kwargs)
    if "point" in decl.inputs:  # (its shape, values and dtype, by the function and the compiled method)
        args, kwargs = _args(model, name, q, fx)
        method = getattr(fd.compile(model, warmup=False), decl.method or name)
        for bad_p, error in [(np.zeros(2), ShapeError), (np.array([0.0, np.nan, 0.0]), NonFiniteError),
                             (np.array(["a", "b", "c"]), fd.errors.DTypeError),
                             (np.zeros((4, 3)), ShapeError)]:  # (batch shapes (4,) and (2,) do not broadcast)
            state = tuple(np.stack([x] * 2) for x in args) if bad_p.shape == (4, 3) else args
            for f in (lambda *a, **k: fn(model, *a, **k), method):
                with pytest.raises(error, match="point"):
                    f(*state, **{**kwargs, "point": bad_p})


@pytest.mark.parametrize("name", NAMES)
def test_compiled_method_with_dask_arrays(name: str) -> None:
    """fd.compile(model)'s declared method takes Dask arrays as the public function does (the same blocks)."""
    da = pytest.importorskip("dask.array")
    model = library_robot("panda", False)
    assert model is not None
    rng = np.random.default_rng(6)
    Q = fd.random_configuration(model, rng, size=(4,))
    FX = rng.normal(size=(4, model.nbodies, 6))
    expected = _call(_function(name), model, name, Q, FX, model)
    method = getattr(fd.compile(model, warmup=False), DECLARATIONS[name].method or name)
    lazy = _call(method, None, name, da.from_array(Q, chunks=(2, -1)), FX, model)
    assert all(type(x).__module__.startswith("dask") for x in _parts(lazy))
    assert _equal(tuple(x.compute(scheduler="sync") for x in _parts(lazy)), expected)


def test_gravity_false_is_the_kernel_without_gravity() -> None:
    """The option reaches the core and the reference alike (rnea and aba with gravity=False)."""
    model = library_robot("panda", False)
    assert model is not None
    rng = np.random.default_rng(7)
    q = fd.random_configuration(model, rng, size=(3,))
    v, a = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    for backend in (None, "reference"):
        with_g = fd.rnea(model, q, v, a, backend=backend)
        without = fd.rnea(model, q, v, a, gravity=False, backend=backend)
        assert _rel(with_g - without, fd.generalized_gravity(model, q)) < 1e-12
        qdd = fd.aba(model, q, v, without, gravity=False, backend=backend)
        assert _rel(qdd, a) < 1e-9
    cm = fd.compile(model)
    assert np.array_equal(cm.rnea(q[0], v[0], a[0], gravity=False), fd.rnea(model, q[0], v[0], a[0], gravity=False))


DIFFERENTIABLE = sorted(n for n, d in DECLARATIONS.items() if d.derivative)


def test_the_declared_derivatives_are_declarations_with_an_output_per_input() -> None:
    assert DIFFERENTIABLE == ["aba", "difference", "frame_acceleration", "frame_velocity", "generalized_gravity",
                              "integrate", "kinetic_energy", "rnea"]
    for name in DIFFERENTIABLE:
        decl, deriv = DECLARATIONS[name], DECLARATIONS[DECLARATIONS[name].derivative]  # type: ignore[index]
        inputs = tuple(n for n in decl.inputs if n != "f_ext")
        assert len(deriv.outputs) == len(inputs) and deriv.inputs == decl.inputs, name


@pytest.mark.parametrize("name", DIFFERENTIABLE)
@pytest.mark.parametrize("robot", [("solo12", True), ("panda", False)])
def test_a_declared_derivative_is_the_derivative_of_its_function(name: str, robot: tuple[str, bool]) -> None:
    """Each output of the declared derivative against central differences of the function: along the tangent of
    fd.integrate for a configuration (q, q0, q1; and for integrate's output), plainly for the vectors."""
    model = library_robot(*robot)
    assert model is not None
    decl = DECLARATIONS[name]
    fn, deriv = getattr(fd, name), getattr(fd, decl.derivative)  # type: ignore[arg-type]
    rng = np.random.default_rng(11)
    state = {"q": fd.random_configuration(model, rng), "v": rng.normal(size=model.nv),
             "a": rng.normal(size=model.nv), "tau": rng.normal(size=model.nv), "f_ext": None}
    state["q0"], state["q1"] = state["q"], fd.random_configuration(model, rng)
    state["w"] = rng.normal(size=model.nv)
    state["W"] = rng.normal(size=(model.nv, model.nv))
    configuration_output = SPECS[name].outputs[0][1] == ("nq",)  # (integrate: its output moves on the group too)
    args = [state[n] for n in decl.inputs]
    frame = [model.frames[-1].name] if "frame" in decl.options else []  # (a frame at the end of a chain)
    partials = _parts(deriv(model, *args, *frame))
    eps = 1e-6
    for k, n in enumerate(n for n in decl.inputs if n != "f_ext"):
        at = decl.inputs.index(n)
        for j in range(model.nv):
            step = np.zeros(model.nv)
            step[j] = eps

            def moved(sign: float, at: int = at, n: str = n, step: np.ndarray = step) -> np.ndarray:
                x = list(args)
                x[at] = fd.integrate(model, args[at], sign * step) if n in ("q", "q0", "q1") else args[at] + sign * step
                r = np.asarray(getattr((r := fn(model, *x, *frame)), "vector", r))  # (a frame's motion: its vector)
                return fd.difference(model, fn(model, *args, *frame), r) if configuration_output else r

            column = (moved(1.0) - moved(-1.0)) / (2 * eps)
            scale = max(1.0, float(np.abs(partials[k]).max()))
            assert np.abs(partials[k][..., j] - column).max() < 1e-5 * scale, (name, n, j)
