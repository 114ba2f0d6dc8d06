"""Shared helpers of the compiled-core tests: robots, states and the comparison with the reference."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest
from _models import library_robot, library_robot_names

import featherdyn as fd
from featherdyn.api.declarations import DECLARATIONS
from featherdyn.api.declared import _constants
from featherdyn.core import _core
from featherdyn.core._model_view import CoreHandle

#: core == reference to this, relative to the largest entry of the reference result
RTOL = 1e-12
REFS = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)


def assert_rel(actual: np.ndarray, expected: np.ndarray, what: str, rtol: float = RTOL, floor: float = 0.0) -> None:
    """``max |actual − expected| <= rtol × max(max |expected|, floor)``; the failure names the quantity and the worst index.

    ``floor``: the magnitude of the terms a quantity is a sum of, when it can cancel to round-off (J̇ of a
    free-flyer's own frame is zero up to products of velocities and Jacobian entries).
    """
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    if not expected.size:
        return
    scale = max(float(np.max(np.abs(expected))), floor, 1e-300)
    diff = np.abs(actual - expected)
    err = float(np.max(diff))
    if not err <= rtol * scale:
        idx = np.unravel_index(int(np.argmax(diff)), expected.shape)
        pytest.fail(f"{what}: max |core − reference| = {err:.3g} > {rtol:g} × {scale:.3g} at index {idx}")


def assert_aba(actual: np.ndarray, expected: np.ndarray, M: np.ndarray, what: str) -> None:
    """q̈ agrees in the metric of the mass matrix: ``|M (q̈ − q̈_ref)| <= 1e-12 |M| |q̈_ref|``.

    Both ABAs are backward stable, so q̈ itself differs by up to cond(M)·ε (robots with
    tiny link inertias), while ``M q̈`` — the joint forces — agree to rounding.
    """
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    if not expected.size:
        return
    err = float(np.max(np.abs(np.einsum("...ij,...j->...i", M, actual - expected))))
    scale = float(np.max(np.abs(M))) * float(np.max(np.abs(expected)))
    assert err <= RTOL * scale, f"{what}: max |M (q̈ − q̈_ref)| = {err:.3g} > {RTOL:g} × |M| |q̈_ref| = {scale:.3g}"


robot = library_robot
robots = library_robot_names


def state(model: fd.Model, seed: int, size: tuple[int, ...] = ()) -> tuple[np.ndarray, ...]:
    """``(q, v, a, tau, f_ext)`` for batch shape ``size``, deterministic from ``seed``."""
    rng = np.random.default_rng(seed)
    q = np.asarray(fd.random_configuration(model, rng, size=size or None), dtype=np.float64)
    q = q.reshape(size + (model.nq,))
    v = rng.normal(size=size + (model.nv,))
    a = rng.normal(size=size + (model.nv,))
    tau = 5 * rng.normal(size=size + (model.nv,))
    f = rng.normal(size=size + (model.nbodies, 6))
    return q, v, a, tau, f


def frames_of(model: fd.Model) -> list[int]:
    """The first, a middle and the last frame."""
    n = len(model.frames)
    return sorted({0, n // 2, n - 1}) if n else []


_EIGENVALUE = re.compile(r"along the joint axis is \S+ —")


def same_message(core_error: BaseException, reference_error: BaseException) -> bool:
    """The messages agree; for a singular mass matrix, up to the printed eigenvalue of ``D``.

    That eigenvalue is rounding noise (``0`` in one, ``-8.2e-34`` in the other) when a
    subtree has no mass, and both implementations compute ``D`` in their own order.
    """
    a, b = str(core_error), str(reference_error)
    if isinstance(reference_error, fd.errors.SingularMassMatrixError):
        a, b = _EIGENVALUE.sub("along the joint axis is <λ> —", a), _EIGENVALUE.sub("along the joint axis is <λ> —", b)
    return a == b


class Spy:
    """A general function that records its calls and returns a marker."""

    def __init__(self) -> None:
        self.calls: list[tuple[tuple[object, ...], dict[str, object]]] = []

    def __call__(self, *args: object, **kwargs: object) -> str:
        self.calls.append((args, kwargs))
        return "general"


def spied(kind: str) -> tuple[Any, Spy]:
    """The core's public call of the declared algorithm ``kind`` (``_core.declared_call``) with a :class:`Spy` as its
    Python function: what the call declines reaches the spy."""
    spy = Spy()
    record = _constants(DECLARATIONS[kind], None)
    return _core.declared_call(_core.kernels[kind], spy, (CoreHandle, _core.kernels[kind], *REFS, record), None), spy
