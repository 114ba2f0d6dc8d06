"""Argument fuzzing of the public functions finished in C (``_core.declared_call``).

Each example (400 per function, seeded) draws a call of ``fd.rnea``, ``fd.aba``, ``fd.nonlinear_effects``,
``fd.generalized_gravity``, ``fd.crba``, ``fd.frame_jacobian`` or ``fd.frame_placement`` —
arguments by position or by keyword, each one a right array or something else (a list, float32,
big-endian, strided, a wrong length, NaN, an off-unit quaternion, ``None``, a string, a number, an
unknown keyword) — and makes it twice: through the public object and through the Python function
it wraps (``__wrapped__``), which is what every declined call runs; the public object is rebuilt
around a counting copy of that function, so the test also knows which calls were finished in C (at least a
fifth must be, and some declined). Both must end alike: the same
exception type and message, or results equal (bit for bit for the arrays the core computes either
way; to 1e-12 for a frame placement, which the Python function composes from the whole forward
kinematics).

The same for stacks of states (``declare.hpp: take``), the public objects' and ``fd.compile``'s methods with
``out=``: each array parameter a stack of the call's leading lengths, one state (read by every state), or a stack that
is not quite one (another stack's lengths, a stack of one against several, an empty stack, a NaN in one state,
strided, Fortran-ordered, float32, a list), and ``out`` a stack of the right shape, another's, read-only, float32,
Fortran-ordered, or the call's own ``v``.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import pytest

import featherdyn as fd

MODEL = fd.load_robot("solo12")  # a floating base: q holds a quaternion
FRAME = "HR_FOOT"
RNG = np.random.default_rng(5)
Q = fd.neutral(MODEL) + 0.0
Q[7:] = RNG.uniform(-1, 1, MODEL.nq - 7)
V = RNG.uniform(-1, 1, MODEL.nv)
A = RNG.uniform(-1, 1, MODEL.nv)
FX = RNG.uniform(-1, 1, (MODEL.nbodies, 6))


def _variants(x: np.ndarray) -> list[Any]:
    """Things that are not quite the array x."""
    bad = x.copy()
    bad.flat[min(2, x.size - 1)] = np.nan
    return [x.tolist(), x.astype(np.float32), x.astype(">f8"), np.repeat(x, 2, axis=-1)[..., ::2], x[..., :-1], bad,
            x[None], None, "q", 3.0]


def _quaternion_off(q: np.ndarray) -> np.ndarray:
    out = q.copy()
    out[3:7] *= 1.1
    return out


#: per parameter: (the values the fast path takes, the others)
ARGS: dict[str, tuple[list[Any], list[Any]]] = {
    "q": ([Q], [*_variants(Q), _quaternion_off(Q)]),
    "v": ([V], _variants(V)),
    "a": ([A], _variants(A)),
    "tau": ([A], _variants(A)),
    "w": ([A], _variants(A)),
    "f_ext": ([None, FX], [FX.tolist(), FX[:-1], FX.astype(np.float32)]),
    "gravity": ([True, False], [1, None]),
    "frame": ([FRAME, MODEL.frame_id(FRAME)], ["nope", -1, 10**6, 2.5, np.int64(3)]),
    "reference": ([fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED], ["world", "LOCAL", 0, None]),
    "backend": ([None], ["compiled", "reference", "bogus"]),  # any backend= is declined: the Python function reads it
}
SIGNATURES = {
    "rnea": (["q", "v", "a", "f_ext"], ["gravity", "backend"]),
    "aba": (["q", "v", "tau", "f_ext"], ["gravity", "backend"]),
    "rnea_vjp": (["q", "v", "a", "w", "f_ext"], ["gravity", "backend"]),
    "nonlinear_effects": (["q", "v"], ["backend"]),
    "generalized_gravity": (["q"], ["backend"]),
    "crba": (["q"], ["backend"]),
    "frame_jacobian": (["q", "frame", "reference"], ["backend"]),
    "frame_placement": (["q", "frame"], ["backend"]),
}


EXAMPLES = 400
REQUIRED = {"q", "v", "a", "tau", "w", "frame"}


def _pick(taken: list[Any], others: list[Any], p: float, rng: np.random.Generator) -> Any:
    """One of ``taken`` with probability p, else one of ``others``."""
    pool = taken if rng.random() < p else others
    return pool[rng.integers(len(pool))]


def _outcome(f: Any, args: tuple[Any, ...], kwargs: dict[str, Any]) -> tuple[str, Any]:
    try:
        return "value", f(*args, **kwargs)
    except Exception as exc:  # the kind and the words are what is compared
        return "error", (type(exc), str(exc))


def _same(name: str, got: tuple[str, Any], expected: tuple[str, Any]) -> None:
    assert got[0] == expected[0], (got, expected)
    if got[0] == "error":
        assert got[1] == expected[1]
        return
    a, b = got[1], expected[1]
    if isinstance(b, fd.PluckerTransform):
        assert isinstance(a, fd.PluckerTransform)
        np.testing.assert_allclose(a.rotation, b.rotation, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a.translation, b.translation, rtol=0, atol=1e-12)
        return
    if isinstance(b, tuple):  # (several outputs: each as one)
        assert isinstance(a, tuple) and len(a) == len(b), name
        for x, y in zip(a, b, strict=True):
            _same(name, ("value", x), ("value", y))
        return
    assert type(a) is type(b) and a.dtype == b.dtype and a.shape == b.shape, name
    if name == "frame_placement":
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    else:
        np.testing.assert_array_equal(a, b)


def _ends_alike(name: str, f: Any, general: Any, counting: Any, call: tuple[Any, Any], twin: tuple[Any, Any]) -> bool:
    """f(*call) and general(*twin) (args, kwargs) end alike (_same); whether f finished the call in C (counting,
    the function general's calls, did not move)."""
    before = counting.calls
    with np.errstate(all="ignore"):
        got = _outcome(f, *call)
    in_c = counting.calls == before
    with np.errstate(all="ignore"):
        expected = _outcome(general, *twin)
    _same(name, got, expected)
    return in_c


class _Counting:
    """The Python function, counting its calls: a call of the public object that does not reach it was finished
    in C."""

    def __init__(self, f: Any) -> None:
        self.f, self.calls = f, 0

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        self.calls += 1
        return self.f(*args, **kwargs)


REFERENCES = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)
K = fd.core._core.kernels


def _public(name: str) -> tuple[Any, Any, Any]:
    """The public object of a declared algorithm rebuilt around a counting copy of its Python function: (object,
    function, counting); the model's core handle exists (a first call may build it on either side)."""
    from featherdyn.api.declarations import DECLARATIONS
    from featherdyn.api.declared import _constants
    from featherdyn.core._model_view import CoreHandle

    general = getattr(fd, name).__wrapped__
    counting = _Counting(general)
    record = _constants(DECLARATIONS[name], None)
    fd.crba(MODEL, Q)
    return (fd.core._core.declared_call(K[name], counting, (CoreHandle, K[name], *REFERENCES, record), None), general,
            counting)


@pytest.mark.parametrize("name", sorted(SIGNATURES))
def test_the_public_object_ends_a_call_as_its_python_function_does(name: str) -> None:
    f, general, counting = _public(name)
    positional, keyword_only = SIGNATURES[name]
    rng = np.random.default_rng(sum(map(ord, name)))
    finished_in_c = 0
    for _ in range(EXAMPLES):
        args: list[Any] = [MODEL]
        kwargs: dict[str, Any] = {}
        for p in positional + keyword_only:
            if rng.random() < (0.05 if p in REQUIRED else 0.85 if p == "backend" else 0.4):
                continue  # left to its default, or missing: a TypeError on both sides
            taken, others = ARGS[p]
            value = _pick(taken, others, 0.8, rng)
            # by position while the positional ones are given in order, else by keyword
            if p in positional and positional.index(p) == len(args) - 1 and not kwargs and rng.random() < 0.7:
                args.append(value)
            else:
                kwargs[p] = value
        if rng.random() < 0.05:
            kwargs["unknown"] = 1
        finished_in_c += _ends_alike(name, f, general, counting, (tuple(args), kwargs), (tuple(args), kwargs))
    assert finished_in_c >= EXAMPLES // 5, f"{name}: only {finished_in_c} of {EXAMPLES} calls were finished in C"
    assert finished_in_c < EXAMPLES, f"{name}: no call was declined"


CM = fd.compile(MODEL)
CM_SIGNATURES = {  # fd.compile(model)'s methods: their parameters (gravity keyword-only, the others not)
    "rnea": ["q", "v", "a", "f_ext", "out", "gravity"],
    "aba": ["q", "v", "tau", "f_ext", "out", "gravity"],
    "nle": ["q", "v", "out"],
    "gravity": ["q", "out"],
    "crba": ["q", "out"],
    "frame_jacobian": ["q", "frame", "reference", "out"],
    "fk": ["q", "out"],
}
OUT = object()  # where the out= value goes in a drawn call
OUT_SHAPES = {"crba": (MODEL.nv, MODEL.nv), "frame_jacobian": (6, MODEL.nv), "fk": (MODEL.nbodies, 4, 4)}


def _compiled_method(name: str) -> tuple[Any, Any, Any]:
    """fd.compile(MODEL)'s method ``name`` rebuilt around a counting copy of its closure: (method, closure,
    counting)."""
    closure = getattr(CM, name).__wrapped__
    counting = _Counting(closure)
    cm = fd.core._view(MODEL).cm
    k = K[{"nle": "nonlinear_effects", "gravity": "generalized_gravity", "fk": "placements"}.get(name, name)]
    return fd.core._core.declared_call(k, counting, (k, MODEL._frame_index, *REFERENCES, None), cm), closure, counting


def _read_only(shape: tuple[int, ...]) -> np.ndarray:
    a = np.empty(shape)
    a.setflags(write=False)
    return a


def _outs(name: str) -> tuple[list[Any], list[Any]]:
    """Makers of out= values (each side of a comparison gets its own): taken, and others."""
    shape = OUT_SHAPES.get(name, (MODEL.nv,))
    wider = shape[:-1] + (shape[-1] + 1,)
    return ([lambda: None, lambda: np.full(shape, np.nan)],
            [lambda: np.empty(wider), lambda: np.empty(shape, dtype=np.float32), lambda: _read_only(shape),
             lambda: np.empty(shape[::-1]).T, lambda: np.zeros(shape).tolist()])


@pytest.mark.parametrize("name", sorted(CM_SIGNATURES))
def test_compiled_methods_end_a_call_as_their_closures_do(name: str) -> None:
    f, closure, counting = _compiled_method(name)
    params = CM_SIGNATURES[name]
    rng = np.random.default_rng(sum(map(ord, name)) + 1)
    finished_in_c = 0
    for _ in range(EXAMPLES):
        args: list[Any] = []
        kwargs: dict[str, Any] = {}
        make_out = None  # the out= maker, called once for each side
        for p in params:
            if rng.random() < (0.05 if p in REQUIRED else 0.4):
                continue
            taken, others = _outs(name) if p == "out" else ARGS[p]
            value = _pick(taken, others, 0.8, rng)
            if p == "out":
                make_out, value = value, OUT
            if len(args) == params.index(p) and not kwargs and rng.random() < 0.7:
                args.append(value)
            else:
                kwargs[p] = value

        def side(args: list[Any] = args, kwargs: dict[str, Any] = kwargs, make: Any = make_out) -> tuple[Any, Any]:
            out = make() if make is not None else None
            return (tuple(out if x is OUT else x for x in args), {k: out if x is OUT else x for k, x in kwargs.items()})

        finished_in_c += _ends_alike(name, f, closure, counting, side(), side())
    assert finished_in_c >= EXAMPLES // 5, f"{name}: only {finished_in_c} of {EXAMPLES} calls were finished in C"
    assert finished_in_c < EXAMPLES, f"{name}: no call was declined"


# --- stacks of states (declare.hpp: take): every array parameter drawn as a stack, one state, or a stack that is
# not quite one; the public object against its Python function as above

STACKABLE = {"q": "nq", "v": "nv", "a": "nv", "tau": "nv", "w": "nv", "f_ext": "fx"}
LEADS = [(3,), (2, 2), (1,), (2 * fd.core._core.simd()[1] + 1,)]


def _stack(p: str, lead: tuple[int, ...], rng: np.random.Generator) -> np.ndarray:
    """A right stack of parameter p under the leading lengths lead (unit quaternions in q)."""
    if p == "q":
        return np.asarray(fd.random_configuration(MODEL, rng, size=lead))
    tail = (MODEL.nbodies, 6) if p == "f_ext" else (MODEL.nv,)
    return rng.uniform(-1, 1, lead + tail)


def _stack_kind(rng: np.random.Generator) -> str:
    """Mostly a right stack or one state (read by every state), else one of the things the binding declines or the
    Python function words: another stack's lengths, a stack of one against several, an empty stack, a NaN in one
    state, strided, Fortran-ordered, float32, a nested list."""
    if rng.random() < 0.85:
        return str(rng.choice(["stack", "stack", "stack", "one"]))
    return str(rng.choice(["other", "ones", "empty", "nan", "strided", "fortran", "float32", "list"]))


def _stack_variant(p: str, lead: tuple[int, ...], kind: str, seed: int) -> Any:
    """Parameter p of the kind _stack_kind drew for a stack of lead (the same seed, the same value)."""
    rng = np.random.default_rng(seed)
    x = _stack(p, lead, rng)
    if kind == "one":
        return x.reshape(-1, *x.shape[len(lead):])[0].copy()
    if kind == "other":
        return _stack(p, lead[:-1] + (lead[-1] + 1,), rng)
    if kind == "ones":
        return _stack(p, (1,) * len(lead), rng)
    if kind == "empty":
        return _stack(p, lead[:-1] + (0,), rng)
    if kind == "nan":
        x.reshape(-1)[rng.integers(x.size)] = np.nan
    elif kind == "strided":
        x = np.repeat(x, 2, axis=0)[::2]
    elif kind == "fortran":
        x = np.asfortranarray(x)
    elif kind == "float32":
        x = x.astype(np.float32)
    elif kind == "list":
        return x.tolist()
    return x


@pytest.mark.parametrize("name", sorted(SIGNATURES))
def test_a_stack_ends_a_call_as_the_python_function_does(name: str) -> None:
    f, general, counting = _public(name)
    positional, keyword_only = SIGNATURES[name]
    rng = np.random.default_rng(sum(map(ord, name)) + 2)
    finished_in_c = 0
    for _ in range(EXAMPLES // 2):
        lead = LEADS[rng.integers(len(LEADS))]
        args: list[Any] = [MODEL]
        kwargs: dict[str, Any] = {}
        for p in positional + keyword_only:
            if p not in REQUIRED and rng.random() < (0.85 if p == "backend" else 0.4):
                continue
            if p in STACKABLE:
                value = _stack_variant(p, lead, _stack_kind(rng), int(rng.integers(1 << 30)))
            else:
                taken, others = ARGS[p]
                value = _pick(taken, others, 0.9, rng)
            if p in positional and positional.index(p) == len(args) - 1 and not kwargs and rng.random() < 0.7:
                args.append(value)
            else:
                kwargs[p] = value
        finished_in_c += _ends_alike(name, f, general, counting, (tuple(args), kwargs), (tuple(args), kwargs))
    assert finished_in_c >= EXAMPLES // 8, f"{name}: only {finished_in_c} of {EXAMPLES // 2} calls were finished in C"
    assert finished_in_c < EXAMPLES // 2, f"{name}: no call was declined"


def _stack_outs(name: str, lead: tuple[int, ...]) -> tuple[list[Any], list[Any]]:
    """Makers of out= values for a stack of lead: taken, and others (another stack's, one state's, read-only,
    float32, Fortran-ordered; "v": the call's own v, an out over an input)."""
    shape = lead + OUT_SHAPES.get(name, (MODEL.nv,))
    other = lead[:-1] + (lead[-1] + 1,) + shape[len(lead):]
    others = [lambda: np.empty(other), lambda: np.empty(shape[len(lead):]), lambda: _read_only(shape),
              lambda: np.empty(shape, dtype=np.float32), lambda: np.asfortranarray(np.empty(shape))]
    if shape[len(lead):] == (MODEL.nv,) and name != "gravity":
        others.append("v")
    return [lambda: None, lambda: np.full(shape, np.nan)], others


def _given(value: Any) -> Any:
    return value


@pytest.mark.parametrize("name", sorted(CM_SIGNATURES))
def test_a_compiled_methods_stack_ends_a_call_as_its_closure_does(name: str) -> None:
    f, closure, counting = _compiled_method(name)
    params = CM_SIGNATURES[name]
    rng = np.random.default_rng(sum(map(ord, name)) + 3)
    finished_in_c = 0
    for _ in range(EXAMPLES // 2):
        lead = LEADS[rng.integers(len(LEADS))]
        spec: list[tuple[str, Any, bool]] = []  # (parameter, its maker, by position)
        for p in params:
            if p not in REQUIRED and rng.random() < 0.4:
                continue
            if p == "out":
                taken, others = _stack_outs(name, lead)
                make = _pick(taken, others, 0.7, rng)
            elif p in STACKABLE:
                kind, seed = _stack_kind(rng), int(rng.integers(1 << 30))
                make = functools.partial(_stack_variant, p, lead, kind, seed)
            else:
                taken, others = ARGS[p]
                value = _pick(taken, others, 0.9, rng)
                make = functools.partial(_given, value)
            positional = len(spec) == params.index(p) and all(pos for _, _, pos in spec) and rng.random() < 0.7
            spec.append((p, make, positional))

        def side(spec: list[tuple[str, Any, bool]] = spec, lead: tuple[int, ...] = lead
                 ) -> tuple[tuple[Any, ...], dict[str, Any]]:
            made = {p: (make if isinstance(make, str) else make()) for p, make, _ in spec}  # each side its own arrays
            if isinstance(made.get("out"), str):
                made["out"] = made.get("v", np.empty(lead + (MODEL.nv,)))
            return (tuple(made[p] for p, _, pos in spec if pos), {p: made[p] for p, _, pos in spec if not pos})

        finished_in_c += _ends_alike(name, f, closure, counting, side(), side())
    assert finished_in_c >= EXAMPLES // 10, f"{name}: only {finished_in_c} of {EXAMPLES // 2} calls were finished in C"
    assert finished_in_c < EXAMPLES // 2, f"{name}: no call was declined"
