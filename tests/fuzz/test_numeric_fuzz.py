"""Hypothesis fuzzing of the numeric API: shapes, dtypes, strides, odd values, non-unit quaternions.

Every public dynamics call gets arguments that start from a valid state and
are then bent: other shapes (a missing or extra entry, extra batch axes,
scalars), other dtypes (float32, float16, integers, booleans, complex, object,
extended precision, big-endian, strings), other memory layouts (strided,
read-only, unaligned), other values (NaN, ±inf, huge, subnormal, −0.0,
quaternions scaled off unit norm), ``None`` and plain lists. The assertion is
the library's contract for bad input:

* the call returns, or raises a :class:`featherdyn.errors.FeatherdynError`
  (no raw NumPy / Numba / Python exception, no crash, no hang);
* when every input is finite, the result has no NaN or inf (finite input never
  gives NaN silently — an overflow is a :class:`NonFiniteError`);
* no NumPy overflow / invalid / division warning on the way (turned into errors here).

Seeded (the suite's hypothesis profile is derandomized) and bounded to keep
the run short in CI.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn.errors import FeatherdynError
from _models import random_tree

MODELS = {
    "panda": lambda: fd.load_robot("panda"),
    "solo12_floating": lambda: fd.load_robot("solo12", floating_base=True),
    "every_joint_type": lambda: random_tree(7, 7, root="free_flyer", branching=True),
}
_CACHE: dict[str, fd.Model] = {}


def _model(name: str) -> fd.Model:
    if name not in _CACHE:
        _CACHE[name] = MODELS[name]()
    return _CACHE[name]


ODD_VALUES = [np.nan, np.inf, -np.inf, 1e300, -1e300, 1e154, 5e-324, -0.0, 1e-300, 1e30]
DTYPES = ["float64", "float32", "float16", "int64", "int8", "bool", "complex128", "object", "longdouble", ">f8",
          "<f8", "U5"]


@st.composite
def bent_array(draw: st.DrawFn, base: np.ndarray) -> Any:
    """``base`` (a valid argument) bent in zero to three ways."""
    x: Any = np.array(base, dtype=np.float64, copy=True)
    for _ in range(draw(st.integers(0, 3))):
        how = draw(st.sampled_from(["value", "shape", "dtype", "layout", "batch", "quaternion", "none", "list"]))
        if how == "value" and isinstance(x, np.ndarray) and x.size and x.dtype.kind in "fcO":
            x = np.array(x, copy=True)
            flat = x.reshape(-1)
            flat[draw(st.integers(0, flat.size - 1))] = draw(st.sampled_from(ODD_VALUES))
        elif how == "shape" and isinstance(x, np.ndarray):
            change = draw(st.sampled_from(["drop", "add", "scalar", "2d"]))
            if change == "drop" and x.shape and x.shape[-1]:
                x = x[..., :-1]
            elif change == "add":
                x = np.concatenate([x, np.zeros(x.shape[:-1] + (1,))], axis=-1) if x.ndim else np.zeros(1)
            elif change == "scalar":
                x = np.float64(1.0)
            else:
                x = x.reshape(-1, 1)
        elif how == "dtype" and isinstance(x, np.ndarray):
            dt = draw(st.sampled_from(DTYPES))
            try:
                with warnings.catch_warnings(), np.errstate(all="ignore"):  # the bending itself may lose values
                    warnings.simplefilter("ignore")
                    x = x.astype(dt)
            except (ValueError, OverflowError):
                pass
        elif how == "layout" and isinstance(x, np.ndarray) and x.ndim:
            layout = draw(st.sampled_from(["strided", "readonly", "unaligned", "fortran"]))
            if layout == "strided":
                big = np.zeros(x.shape[:-1] + (2 * x.shape[-1],), dtype=x.dtype)
                big[..., ::2] = x
                x = big[..., ::2]
            elif layout == "readonly":
                x = np.array(x, copy=True)
                x.flags.writeable = False
            elif layout == "unaligned" and x.dtype.kind == "f" and x.dtype.itemsize == 8:
                raw = np.zeros(x.nbytes + 1, dtype=np.uint8)
                y = raw[1:].view(x.dtype).reshape(x.shape)
                y[...] = x
                x = y
            elif layout == "fortran":
                x = np.asfortranarray(np.broadcast_to(x, (2,) + x.shape))
        elif how == "batch" and isinstance(x, np.ndarray):
            x = np.broadcast_to(x, (draw(st.integers(0, 3)),) + x.shape).copy()
        elif how == "quaternion":
            x = np.array(x, dtype=np.float64, copy=True) * draw(st.sampled_from([0.5, 1.0001, 2.0, 0.0, -1.0]))
        elif how == "none":
            x = None
        elif how == "list" and isinstance(x, np.ndarray):
            x = x.tolist()
    return x


def _all_finite(*args: Any) -> bool:
    for a in args:
        if a is None:
            return False
        try:
            arr = np.asarray(a, dtype=np.float64)
        except (TypeError, ValueError, OverflowError):
            return False
        if not np.isfinite(arr).all():
            return False
    return True


def _check(call: Callable[[], Any], *inputs: Any) -> None:
    """The contract: a result (finite for finite input) or a featherdyn error; no warning."""
    try:
        with np.errstate(over="raise", invalid="raise", divide="raise", under="ignore"):  # underflow is benign
            out = call()
    except FeatherdynError:
        return
    values = [out] if isinstance(out, np.ndarray) else []
    if isinstance(out, fd.SpatialMotion | fd.SpatialForce):
        values = [out.vector]
    elif isinstance(out, fd.PluckerTransform):
        values = [out.rotation, out.translation]
    elif isinstance(out, fd.Kinematics):
        values = [out.placements.translation] + [m.vector for m in (out.velocities, out.accelerations) if m is not None]
    if _all_finite(*inputs):
        for v in values:
            if v.dtype.kind == "f":
                assert np.isfinite(v).all(), f"finite input gave a non-finite result: {v}"


FUNCTIONS = ["rnea", "aba", "crba", "nonlinear_effects", "generalized_gravity", "frame_jacobian",
             "forward_kinematics", "frame_placement", "kinetic_energy", "center_of_mass"]


@settings(max_examples=1500, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data(), model_name=st.sampled_from(sorted(MODELS)), function=st.sampled_from(FUNCTIONS),
       backend=st.sampled_from([None, None, "reference", "compiled"]))
def test_public_calls_raise_featherdyn_errors_or_return_finite_numbers(data: st.DataObject, model_name: str,
                                                                       function: str, backend: str | None) -> None:
    model = _model(model_name)
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    q0 = fd.random_configuration(model, rng)
    v0 = rng.normal(size=model.nv)
    a0 = rng.normal(size=model.nv)
    q = data.draw(bent_array(q0), "q")
    v = data.draw(bent_array(v0), "v")
    a = data.draw(bent_array(a0), "a")
    frame = data.draw(st.sampled_from([0, len(model.frames) - 1, -1, 2**70, "nope", 1.5, None,
                                       model.frames[-1].name]), "frame")
    f = getattr(fd, function)
    calls: dict[str, tuple[Callable[[], Any], tuple[Any, ...]]] = {
        "rnea": (lambda: f(model, q, v, a, backend=backend), (q, v, a)),
        "aba": (lambda: f(model, q, v, a, backend=backend), (q, v, a)),
        "crba": (lambda: f(model, q, backend=backend), (q,)),
        "nonlinear_effects": (lambda: f(model, q, v, backend=backend), (q, v)),
        "generalized_gravity": (lambda: f(model, q, backend=backend), (q,)),
        "frame_jacobian": (lambda: f(model, q, frame, backend=backend), (q,)),
        "forward_kinematics": (lambda: f(model, q, v, a, backend=backend), (q, v, a)),
        "frame_placement": (lambda: f(model, q, frame, backend=backend), (q,)),
        "kinetic_energy": (lambda: f(model, q, v, backend=backend), (q, v)),
        "center_of_mass": (lambda: f(model, q, v, backend=backend), (q, v)),
    }
    call, inputs = calls[function]
    _check(call, *inputs)


@pytest.mark.parametrize("function", ["rnea", "aba"])
@settings(max_examples=60)
@given(data=st.data())
def test_f_ext_is_checked(data: st.DataObject, function: str) -> None:
    model = _model("solo12_floating")
    q = fd.neutral(model)
    z = np.zeros(model.nv)
    f_ext = data.draw(bent_array(np.zeros((model.nbodies, 6))), "f_ext")
    _check(lambda: getattr(fd, function)(model, q, z, z, f_ext), q, f_ext)


# ---------------------------------------------------------------------------------------------------------
# the derivatives (issue 30): the same contract, with frames, references, points and external forces bent too
# ---------------------------------------------------------------------------------------------------------

DERIVATIVE_FUNCTIONS = ["rnea_derivatives", "aba_derivatives", "generalized_gravity_derivatives",
                        "static_torque_derivatives", "kinematics_derivatives", "center_of_mass_derivatives",
                        "centroidal_dynamics_derivatives", "rnea_second_derivatives", "aba_second_derivatives"]
REFERENCES = [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED, "local", "WORLD", "sideways", "", 0, 1.5, None, b"LOCAL",
              ["LOCAL"]]


def _finite_fields(out: Any) -> list[np.ndarray]:
    """The arrays of a result: an array, or each field of a record (a named tuple of arrays)."""
    if isinstance(out, np.ndarray):
        return [out]
    if isinstance(out, tuple):
        return [x for x in out if isinstance(x, np.ndarray)]
    return []


def _check_derivative(call: Callable[[], Any], *inputs: Any) -> None:
    """:func:`_check`'s contract for a record of derivative arrays."""
    try:
        with np.errstate(over="raise", invalid="raise", divide="raise", under="ignore"):
            out = call()
    except FeatherdynError:
        return
    values = _finite_fields(out)
    assert values, f"no arrays in the result {type(out).__name__}"
    if _all_finite(*inputs):
        for v in values:
            if v.dtype.kind == "f":
                assert np.isfinite(v).all(), f"finite input gave a non-finite result: {v}"


@settings(max_examples=800, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data(), model_name=st.sampled_from(sorted(MODELS)), function=st.sampled_from(DERIVATIVE_FUNCTIONS),
       backend=st.sampled_from([None, None, "reference", "compiled"]))
def test_derivative_calls_raise_featherdyn_errors_or_return_finite_numbers(data: st.DataObject, model_name: str,
                                                                           function: str,
                                                                           backend: str | None) -> None:
    model = _model(model_name)
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    q = data.draw(bent_array(fd.random_configuration(model, rng)), "q")
    v = data.draw(bent_array(rng.normal(size=model.nv)), "v")
    a = data.draw(bent_array(rng.normal(size=model.nv)), "a")
    f_ext = data.draw(bent_array(rng.normal(size=(model.nbodies, 6))), "f_ext")
    frame = data.draw(st.sampled_from([0, len(model.frames) - 1, -1, 2**70, "nope", 1.5, None, "",
                                       model.frames[-1].name]), "frame")
    reference = data.draw(st.sampled_from(REFERENCES), "reference")
    point = data.draw(st.one_of(st.none(), bent_array(rng.normal(size=3) * 0.1)), "point")
    f = getattr(fd, function)
    kw = {"backend": backend}
    calls: dict[str, tuple[Callable[[], Any], tuple[Any, ...]]] = {
        "rnea_derivatives": (lambda: f(model, q, v, a, **kw), (q, v, a)),
        "aba_derivatives": (lambda: f(model, q, v, a, **kw), (q, v, a)),
        "generalized_gravity_derivatives": (lambda: f(model, q, **kw), (q,)),
        "static_torque_derivatives": (lambda: f(model, q, f_ext, **kw), (q, f_ext)),
        "kinematics_derivatives": (lambda: f(model, q, v, a, frame, reference, point, **kw),
                                   (q, v, a) if point is None else (q, v, a, point)),
        "center_of_mass_derivatives": (lambda: f(model, q, v, **kw), (q, v)),
        "centroidal_dynamics_derivatives": (lambda: f(model, q, v, a, **kw), (q, v, a)),
        "rnea_second_derivatives": (lambda: f(model, q, v, a, **kw), (q, v, a)),
        "aba_second_derivatives": (lambda: f(model, q, v, a, **kw), (q, v, a)),
    }
    call, inputs = calls[function]
    _check_derivative(call, *inputs)
