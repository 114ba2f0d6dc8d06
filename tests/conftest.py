"""Shared test configuration: the hypothesis profile, batch/dtype parameters,
seeded random spatial values and independent reference formulas.

The reference formulas here are written from the textbook (RBDA ch. 2, the
chapter's §3–§5 and appendix A), one unbatched instance at a time with
``np.cross`` and explicit blocks, so that they share no code with
``featherdyn.spatial_algebra``; :func:`per_batch` loops them over batch axes.
"""

from __future__ import annotations

from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from hypothesis import settings

import featherdyn as fd


def pytest_configure(config: pytest.Config) -> None:
    """FEATHERDYN_TEST_INSTALLED=1 (.ci/run's wheel job): the suite must test an installed featherdyn, not src/."""
    import os
    from pathlib import Path

    if os.environ.get("FEATHERDYN_TEST_INSTALLED") == "1":
        where = Path(fd.__file__).resolve().parts
        if "site-packages" not in where:
            raise pytest.UsageError(f"FEATHERDYN_TEST_INSTALLED=1 but featherdyn is imported from {fd.__file__}")


settings.register_profile("featherdyn", derandomize=True, deadline=None, max_examples=50, print_blob=True)
settings.load_profile("featherdyn")

BATCH_SHAPES = [(), (1,), (3,), (2, 3)]
DTYPES = [np.float64, np.float32]


@pytest.fixture(scope="session", params=BATCH_SHAPES, ids=lambda s: f"batch{s}".replace(" ", ""))
def batch_shape(request: pytest.FixtureRequest) -> tuple[int, ...]:
    """Every batch shape the public functions must broadcast over."""
    return tuple(request.param)


@pytest.fixture(scope="session", params=DTYPES, ids=lambda d: np.dtype(d).name)
def dtype(request: pytest.FixtureRequest) -> np.dtype:
    """float64 and float32 (float32 in must give float32 out)."""
    return np.dtype(request.param)


@pytest.fixture(scope="session")
def pin() -> Any:
    """Pinocchio, or a skip if it is not installed (it is a test dependency)."""
    return pytest.importorskip("pinocchio")


# --------------------------------------------------------------------------
# independent reference formulas (one instance, float64)
# --------------------------------------------------------------------------


def ref_skew(w: Any) -> np.ndarray:
    """``[w]×`` written out: ``ref_skew(w) @ x == np.cross(w, x)``."""
    x, y, z = np.asarray(w, dtype=np.float64)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def ref_crm(v6: Any) -> np.ndarray:
    """Motion cross-product matrix ``[[ω×, 0], [v×, ω×]]`` (chapter A.1)."""
    v6 = np.asarray(v6, dtype=np.float64)
    wx, vx = ref_skew(v6[:3]), ref_skew(v6[3:])
    return np.block([[wx, np.zeros((3, 3))], [vx, wx]])


def ref_crf(v6: Any) -> np.ndarray:
    """Force cross-product matrix ``[[ω×, v×], [0, ω×]]`` written directly (chapter A.2)."""
    v6 = np.asarray(v6, dtype=np.float64)
    wx, vx = ref_skew(v6[:3]), ref_skew(v6[3:])
    return np.block([[wx, vx], [np.zeros((3, 3)), wx]])


def ref_X(R: Any, p: Any) -> np.ndarray:
    """Motion transform ``[[R, 0], [p×R, R]]`` of the pose (R, p) (chapter §3.1)."""
    R = np.asarray(R, dtype=np.float64)
    return np.block([[R, np.zeros((3, 3))], [ref_skew(p) @ R, R]])


def ref_Xstar(R: Any, p: Any) -> np.ndarray:
    """Force transform ``[[R, p×R], [0, R]]`` (chapter §3.3)."""
    R = np.asarray(R, dtype=np.float64)
    return np.block([[R, ref_skew(p) @ R], [np.zeros((3, 3)), R]])


def ref_inertia(m: Any, c: Any, Ic: Any) -> np.ndarray:
    """Spatial inertia about the frame origin, parallel axis in the ``|c|²1 − ccᵀ`` form (chapter A.4)."""
    m = float(m)
    c = np.asarray(c, dtype=np.float64)
    Ic = np.asarray(Ic, dtype=np.float64)
    ibar = Ic + m * (c @ c * np.eye(3) - np.outer(c, c))
    return np.block([[ibar, m * ref_skew(c)], [m * ref_skew(c).T, m * np.eye(3)]])


def per_batch(fn: Callable[..., Any], *args: tuple[Any, int]) -> np.ndarray:
    """Apply an unbatched ``fn`` over the broadcast batch axes of ``args``.

    Each argument is ``(array, trailing_ndim)``; the result is stacked in
    float64 with the batch shape leading. This is the "loop" of batch == loop.
    """
    arrays = [np.asarray(a, dtype=np.float64) for a, _ in args]
    batch = np.broadcast_shapes(*[a.shape[: a.ndim - k] for a, (_, k) in zip(arrays, args, strict=True)])
    full = [np.broadcast_to(a, batch + a.shape[a.ndim - k :]) for a, (_, k) in zip(arrays, args, strict=True)]
    outs = [np.asarray(fn(*[f[idx] for f in full]), dtype=np.float64) for idx in np.ndindex(*batch)]
    return np.stack(outs).reshape(batch + outs[0].shape)


@pytest.fixture(scope="session")
def ref() -> SimpleNamespace:
    """The independent reference formulas above, as a namespace."""
    return SimpleNamespace(
        skew=ref_skew, crm=ref_crm, crf=ref_crf, X=ref_X, Xstar=ref_Xstar, inertia=ref_inertia, per_batch=per_batch
    )


# --------------------------------------------------------------------------
# seeded random spatial values
# --------------------------------------------------------------------------


class SpatialSamples:
    """Random spatial values from a seeded generator, built from float64 draws then cast to ``dtype``.

    Rotations come from normalised Gaussian quaternions (uniform on SO(3));
    inertias are physical (positive mass, principal moments satisfying the
    triangle inequality, rotated principal axes).
    """

    def __init__(self, seed: int = 0) -> None:
        self.rng = np.random.default_rng(seed)

    def array(self, shape: tuple[int, ...], trailing: tuple[int, ...], dtype: Any = np.float64, scale: float = 1.0) -> np.ndarray:
        return (scale * self.rng.uniform(-1.0, 1.0, tuple(shape) + tuple(trailing))).astype(dtype)

    def rotation(self, shape: tuple[int, ...] = (), dtype: Any = np.float64) -> np.ndarray:
        q = self.rng.normal(size=tuple(shape) + (4,))
        q /= np.linalg.norm(q, axis=-1, keepdims=True)
        x, y, z, w = np.moveaxis(q, -1, 0)
        R = np.stack(
            [
                np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=-1),
                np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=-1),
                np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=-1),
            ],
            axis=-2,
        )
        return R.astype(dtype)

    def motion(self, shape: tuple[int, ...] = (), dtype: Any = np.float64, **tags: Any) -> fd.SpatialMotion:
        return fd.SpatialMotion.from_vector(self.array(shape, (6,), dtype), **tags)

    def force(self, shape: tuple[int, ...] = (), dtype: Any = np.float64, frame: Any = None) -> fd.SpatialForce:
        return fd.SpatialForce.from_vector(self.array(shape, (6,), dtype), frame)

    def transform(self, shape: tuple[int, ...] = (), dtype: Any = np.float64, **tags: Any) -> fd.PluckerTransform:
        return fd.PluckerTransform(self.rotation(shape, dtype), self.array(shape, (3,), dtype), **tags)

    def inertia_params(self, shape: tuple[int, ...] = (), dtype: Any = np.float64) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        shape = tuple(shape)
        m = self.rng.uniform(0.5, 3.0, shape)
        c = self.rng.uniform(-0.5, 0.5, shape + (3,))
        a = self.rng.uniform(0.05, 0.5, shape)
        b = self.rng.uniform(0.05, 0.5, shape)
        # the third principal moment strictly inside |a − b| < c < a + b
        t = self.rng.uniform(0.1, 0.9, shape)
        third = np.abs(a - b) + t * (a + b - np.abs(a - b))
        moments = np.stack([a, b, third], axis=-1)
        Q = self.rotation(shape)
        Ic = Q @ (moments[..., :, None] * np.eye(3)) @ np.swapaxes(Q, -1, -2)
        Ic = (Ic + np.swapaxes(Ic, -1, -2)) / 2
        return m.astype(dtype), c.astype(dtype), Ic.astype(dtype)

    def inertia(self, shape: tuple[int, ...] = (), dtype: Any = np.float64, frame: Any = None) -> fd.SpatialInertia:
        return fd.SpatialInertia(*self.inertia_params(shape, dtype), frame=frame)


@pytest.fixture
def samples() -> SpatialSamples:
    """A freshly seeded :class:`SpatialSamples` per test (deterministic)."""
    return SpatialSamples(20240611)


@pytest.fixture(scope="session")
def make_samples() -> type[SpatialSamples]:
    """The :class:`SpatialSamples` class, for hypothesis tests that draw the seed."""
    return SpatialSamples
