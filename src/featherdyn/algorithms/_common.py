"""Shared pieces of the reference algorithms (private): input checks, per-model data, reference frames.

Every algorithm starts with :func:`check_state`, which validates ``q``, ``v``,
``a``/``τ`` against the model (trailing length, finiteness, unit quaternions)
and finds the common batch shape and dtype, and then uses :class:`TreeData`,
the model's constant data (joint placements, inertias, motion subspaces,
gravity) cast to that dtype.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_array, result_dtype
from ..engine import _fast
from ..errors import FeatherdynError, QuaternionNormError, ShapeError
from ..joints import FreeFlyerJoint, SphericalJoint
from ..model import Model
from ..spatial_algebra import PluckerTransform, SpatialInertia, SpatialMotion
from ..tolerances import QUATERNION_NORM

__all__ = ["ReferenceFrame", "LOCAL", "WORLD", "LOCAL_WORLD_ALIGNED", "check_state", "TreeData", "select_backend"]

class ReferenceFrame(enum.Enum):
    """Where frame velocities, accelerations and Jacobians are expressed (Pinocchio's meanings).

    * ``LOCAL``: in the frame itself, reference point its origin.
    * ``WORLD``: in world axes, reference point the world origin (spatial
      velocity in Featherstone's sense).
    * ``LOCAL_WORLD_ALIGNED``: reference point the frame origin, world axes
      (the linear part is the frame origin's velocity in world coordinates).
    """

    LOCAL = "local"
    WORLD = "world"
    LOCAL_WORLD_ALIGNED = "local_world_aligned"


LOCAL = ReferenceFrame.LOCAL
WORLD = ReferenceFrame.WORLD
LOCAL_WORLD_ALIGNED = ReferenceFrame.LOCAL_WORLD_ALIGNED


class BackendError(FeatherdynError, ValueError):
    """An unknown or unavailable ``backend=`` was requested."""


def select_backend(backend: str | None, dtype: np.dtype) -> str:
    """Resolve ``backend=`` to ``"reference"`` or ``"compiled"``.

    ``None`` picks the compiled engine (:mod:`featherdyn.engine`) for float64
    input when Numba is installed, and the reference otherwise (float32, SymPy
    object arrays); :func:`featherdyn.set_default_backend` changes that default
    (``$FEATHERDYN_BACKEND=reference`` when featherdyn is imported makes the
    reference the default). ``"compiled"`` forces the engine: input is converted to float64
    (an error if it cannot be) and the result cast back to float32 for
    float32 input.
    """
    if backend is None:
        if dtype == np.float64 and _fast.ON and _engine_available():
            return "compiled"
        return "reference"
    if backend == "reference":
        return "reference"
    if backend == "compiled":
        if not _engine_available():
            raise BackendError("backend='compiled' needs Numba (pip install numba); use backend='reference'")
        return "compiled"
    raise BackendError(f"backend: expected None, 'reference' or 'compiled', got {backend!r}")


def _engine_available() -> bool:
    from ..engine import available

    return available()


def as_reference_frame(reference: Any) -> ReferenceFrame:
    if isinstance(reference, ReferenceFrame):
        return reference
    if isinstance(reference, str):
        try:
            return ReferenceFrame(reference.lower())
        except ValueError:
            pass
    raise ShapeError(f"reference: expected fd.LOCAL, fd.WORLD or fd.LOCAL_WORLD_ALIGNED, got {reference!r}")


@dataclass(frozen=True)
class State:
    """Validated inputs: arrays with a common batch shape and dtype."""

    batch: tuple[int, ...]
    dtype: np.dtype
    q: np.ndarray
    arrays: dict[str, np.ndarray]


def check_state(model: Model, q: Any, check_finite: bool = True, **vectors: Any) -> State:
    """Validate ``q`` `(..., nq)` and every named vector `(..., nv)` (``None`` entries are skipped).

    Raises :class:`ShapeError` naming the argument and the expected trailing
    dimension, :class:`NonFiniteError`, or :class:`QuaternionNormError` naming
    the joint whose quaternion is off unit norm by more than 1e-6.
    """
    if not isinstance(model, Model):
        raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    qq = _vec(q, "q", model.nq, "nq", check_finite)
    arrays = {}
    for name, val in vectors.items():
        if val is not None:
            arrays[name] = _vec(val, name, model.nv, "nv", check_finite)
    all_arrays = [qq, *arrays.values()]
    batches = {a.shape[:-1] for a in all_arrays}
    try:
        batch = batches.pop() if len(batches) == 1 else np.broadcast_shapes(*(a.shape[:-1] for a in all_arrays))
    except ValueError:
        shapes = ", ".join(f"{n}: {a.shape}" for n, a in [("q", qq), *arrays.items()])
        raise ShapeError(f"batch shapes do not broadcast ({shapes})") from None
    dtype = result_dtype(*all_arrays)
    if dtype.kind != "O":
        _check_quaternions(model, qq)
    return State(batch, dtype, qq, arrays)


def _vec(x: Any, name: str, n: int, what: str, check_finite: bool) -> np.ndarray:
    arr = as_array(x, name, check_finite=check_finite)
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise ShapeError(f"{name}: expected trailing dimension {what}={n}, got shape {tuple(arr.shape)}")
    return arr


def _check_quaternions(model: Model, q: np.ndarray) -> None:
    for i, joint in enumerate(model.joints):
        if isinstance(joint, SphericalJoint):
            quat = q[..., model.idx_q[i] : model.idx_q[i] + 4]
        elif isinstance(joint, FreeFlyerJoint):
            quat = q[..., model.idx_q[i] + 3 : model.idx_q[i] + 7]
        else:
            continue
        tol = QUATERNION_NORM.of(q.dtype)
        err = np.abs(np.sqrt(np.sum(quat * quat, axis=-1)) - 1)
        if np.any(err > tol):
            worst = float(np.max(err))
            raise QuaternionNormError(
                f"q: the quaternion of joint {model.joint_names[i]!r} (q[{model.idx_q[i]}:{model.idx_q[i] + joint.nq}]) "
                f"is off unit norm by {worst:.3g} > {tol:g}; featherdyn quaternions are (x, y, z, w) — "
                "normalise with fd.normalize(model, q)"
            )


class TreeData:
    """The model's constant data cast to one dtype, in the chapter's symbols.

    Attributes:
        parents: ``λ(i)``.
        Xtree: joint placements (poses of joint frames in parent bodies), one per body.
        I: body inertias, one :class:`SpatialInertia` per body (body frame).
        S: motion subspaces `(6, nv_i)`.
        a0: the base acceleration ``−g`` as a spatial motion (the RNEA gravity trick).
    """

    def __init__(self, model: Model, dtype: np.dtype) -> None:
        self.model = model
        self.dtype = dtype
        self.parents = model.parents
        self.nb = model.nbodies

        def cast(a: np.ndarray) -> np.ndarray:
            return np.asarray(a).astype(dtype)

        pl, inertias = model.joint_placements, model.inertias
        self.Xtree = [PluckerTransform._wrap(cast(pl.rotation[i]), cast(pl.translation[i]), None, None)
                      for i in range(self.nb)]
        self.I = [SpatialInertia._wrap(cast(inertias.mass[i]), cast(inertias.com[i]), cast(inertias.inertia_com[i]),
                                       None) for i in range(self.nb)]
        self.S = [cast(j.S) for j in model.joints]
        g = cast(model.gravity)
        self.a0 = SpatialMotion._wrap(np.concatenate([np.zeros(3, dtype=dtype), -g]), None)

    def q_i(self, q: np.ndarray, i: int) -> np.ndarray:
        m = self.model
        return q[..., m.idx_q[i] : m.idx_q[i] + m.nqs[i]]

    def v_i(self, v: np.ndarray, i: int) -> np.ndarray:
        m = self.model
        return v[..., m.idx_v[i] : m.idx_v[i] + m.nvs[i]]

    def pose_in_parent(self, q: np.ndarray, i: int) -> PluckerTransform:
        """``ᵖM_i(q)``: the pose of body ``i`` in its parent = ``Xtree[i] @ joint.pose(q_i)``."""
        XJ = self.model.joints[i].pose(self.q_i(q, i))
        XJ = PluckerTransform._wrap(XJ.rotation.astype(self.dtype), XJ.translation.astype(self.dtype), None, None)
        return self.Xtree[i] @ XJ

    def vJ(self, qd: np.ndarray, i: int) -> SpatialMotion:
        """Joint velocity (or any joint-space rate) ``S_i q̇_i`` as a motion in body ``i``."""
        return SpatialMotion._wrap(self.v_i(qd, i) @ self.S[i].T, None)


def stack_motions(ms: list[SpatialMotion], batch: tuple[int, ...], dtype: np.dtype) -> SpatialMotion:
    """Stack per-body motions into one `(..., nb, 6)` motion (body axis last among batch axes)."""
    if not ms:
        return SpatialMotion._wrap(np.zeros(batch + (0, 6), dtype=dtype), None)
    return SpatialMotion._wrap(np.stack([np.broadcast_to(m.vector, batch + (6,)) for m in ms], axis=-2), None)


def stack_transforms(xs: list[PluckerTransform], batch: tuple[int, ...], dtype: np.dtype) -> PluckerTransform:
    """Stack per-body transforms into one with batch shape `(..., nb)`."""
    if not xs:
        return PluckerTransform._wrap(np.zeros(batch + (0, 3, 3), dtype), np.zeros(batch + (0, 3), dtype), None, None)
    rot = np.stack([np.broadcast_to(x.rotation, batch + (3, 3)) for x in xs], axis=-3)
    p = np.stack([np.broadcast_to(x.translation, batch + (3,)) for x in xs], axis=-2)
    return PluckerTransform._wrap(rot, p, None, None)


def expand(X: PluckerTransform) -> PluckerTransform:
    """Add a trailing batch axis to ``X`` (to act on a set of columns `(..., k, 6)`)."""
    return PluckerTransform._wrap(X.rotation[..., None, :, :], X.translation[..., None, :], X.source, X.target)


def expand_inertia(I: SpatialInertia) -> SpatialInertia:
    """Add a trailing batch axis to ``I`` (to act on a set of columns `(..., k, 6)`)."""
    return SpatialInertia._wrap(I.mass[..., None], I.com[..., None, :], I.inertia_com[..., None, :, :], I.frame)


def zeros(batch: tuple[int, ...], shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    if dtype.kind == "O":
        out = np.empty(batch + shape, dtype=object)
        out.fill(0)
        return out
    return np.zeros(batch + shape, dtype=dtype)
