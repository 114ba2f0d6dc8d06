"""Every spelling NumPy accepts for float64, and arrays that are float64 underneath, through every public call.

A one-state call takes an exact ``numpy.ndarray`` of native float64 as it is (the core reads it through
NumPy's C API: ``PyArray_TYPE == NPY_DOUBLE`` and not byte-swapped, however the dtype was spelled); anything
else — byte-swapped, long double, a subclass, a memory map, a read-only or strided view — is converted by the
Python path. Either way the result is the float64 result (bit for bit where the values are float64), and
nothing raises a binding's ``TypeError`` (the issue: ``'<f8'`` rows read back from a Zarr store were refused
with nanobind's "incompatible function arguments").
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.errors import DTypeError

NATIVE = "<" if sys.byteorder == "little" else ">"
SWAPPED = ">" if NATIVE == "<" else "<"


class Tagged(np.ndarray):
    """An ndarray subclass (as a user's unit-carrying array might be)."""


def _spellings(x: np.ndarray, tmp: Path) -> list[tuple[str, np.ndarray, bool]]:
    """``(label, array, taken)``: the array holds x's values; ``taken``: the result is x's float64 result (else the
    call refuses it with a featherdyn DTypeError: extended precision is not computed in float64 silently)."""
    mm = np.memmap(tmp / "x.dat", dtype=np.float64, mode="w+", shape=x.shape)
    mm[...] = x
    ro = x.copy()
    ro.setflags(write=False)
    strided = np.repeat(x, 2)[::2]
    return [
        ("'d'", x.astype("d"), True),
        ("'=f8'", x.astype("=f8"), True),
        (f"'{NATIVE}f8'", x.astype(f"{NATIVE}f8"), True),
        ("np.float64", x.astype(np.float64), True),
        ("newbyteorder('=')", x.astype(np.dtype("f8").newbyteorder("=")), True),
        (f"'{SWAPPED}f8' (swapped)", x.astype(f"{SWAPPED}f8"), True),
        ("subclass", x.copy().view(Tagged), True),
        ("memmap", mm, True),
        ("read-only", ro, True),
        ("strided", strided, True),
        ("longdouble", x.astype(np.longdouble), False),
    ]


def _calls(model: fd.Model) -> list[tuple[str, Callable[..., Any]]]:
    frame = model.frames[-1].name
    cm = fd.compile(model, warmup=False)
    return [
        ("rnea", lambda q, v: fd.rnea(model, q, v, v)),
        ("nonlinear_effects", lambda q, v: fd.nonlinear_effects(model, q, v)),
        ("generalized_gravity", lambda q, v: fd.generalized_gravity(model, q)),
        ("crba", lambda q, v: fd.crba(model, q)),
        ("aba", lambda q, v: fd.aba(model, q, v, v)),
        ("frame_jacobian", lambda q, v: fd.frame_jacobian(model, q, frame, fd.WORLD)),
        ("frame_placement", lambda q, v: fd.frame_placement(model, q, frame).matrix()),
        ("forward_kinematics", lambda q, v: fd.forward_kinematics(model, q, v).velocities.vector),
        ("rnea_derivatives", lambda q, v: np.stack(fd.rnea_derivatives(model, q, v, v))),
        ("aba_derivatives", lambda q, v: np.stack(fd.aba_derivatives(model, q, v, v))),
        ("mass_matrix_inverse", lambda q, v: fd.mass_matrix_inverse(model, q)),
        ("generalized_gravity_derivatives", lambda q, v: fd.generalized_gravity_derivatives(model, q)),
        ("cm.rnea", lambda q, v: cm.rnea(q, v, v)),
        ("cm.aba", lambda q, v: cm.aba(q, v, v)),
        ("cm.crba", lambda q, v: cm.crba(q)),
        ("cm.frame_jacobian", lambda q, v: cm.frame_jacobian(q, frame, fd.LOCAL)),
        ("cm.generalized_gravity_derivatives", lambda q, v: cm.generalized_gravity_derivatives(q)),
    ]


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True)])
def test_every_float64_spelling_gives_the_float64_result(name: str, floating: bool, tmp_path: Path) -> None:
    model = library_robot(name, floating)
    assert model is not None
    rng = np.random.default_rng(9)
    q = fd.random_configuration(model, rng)
    v = rng.normal(size=model.nv)
    for call_name, call in _calls(model):
        expected = call(q, v)
        (tmp_path / "q").mkdir(exist_ok=True)
        (tmp_path / "v").mkdir(exist_ok=True)
        for (label, qs, exact), (_, vs, _) in zip(_spellings(q, tmp_path / "q"), _spellings(v, tmp_path / "v"),
                                                   strict=True):
            where = f"{call_name} with {label}"
            if not exact:
                with pytest.raises(DTypeError, match="extended precision"):
                    call(qs, vs)
                continue
            assert np.array_equal(np.asarray(call(qs, vs), dtype=np.float64), expected), where


def test_lengths_are_checked_before_values() -> None:
    """A zero-stride view of 2⁴⁰ entries as ``q`` (or ``f_ext``) is a wrong length: a ShapeError at once, not the
    MemoryError of scanning a terabyte for finiteness (hostile input, round 3)."""
    from numpy.lib.stride_tricks import as_strided

    from featherdyn.errors import ShapeError

    model = library_robot("panda", False)
    assert model is not None
    huge = as_strided(np.zeros(1), shape=(2**40,), strides=(0,))
    v = np.zeros(model.nv)
    for call in (lambda: fd.rnea(model, huge, v, v), lambda: fd.crba(model, huge),
                 lambda: fd.generalized_gravity_derivatives(model, huge),
                 lambda: fd.compile(model, warmup=False).generalized_gravity_derivatives(huge),
                 lambda: fd.compile(model, warmup=False).rnea(huge, v, v),
                 lambda: fd.compile(model, warmup=False).crba(huge),
                 lambda: fd.compile(model, warmup=False).frame_jacobian(huge, model.frames[-1].name)):
        with pytest.raises(ShapeError, match="q"):
            call()
    huge_f = as_strided(np.zeros(1), shape=(2**36, 6), strides=(0, 0))
    with pytest.raises(ShapeError, match="f_ext"):
        fd.rnea(model, fd.neutral(model), v, v, huge_f)
    with pytest.raises(ShapeError, match="f_ext"):
        fd.static_torque_derivatives(model, fd.neutral(model), huge_f)
