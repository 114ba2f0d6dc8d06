"""Constrained dynamics, impulses and operational space (public; the constraints' definitions in ``featherdyn.constraints``).

::

    M q̈ + h = τ + Jᵀ λ,        J q̈ + γ = −K_p e − K_d J v

The constraint rows J, the drift γ (``J̇ q̇``: the constrained quantity's
acceleration at q̈ = 0) and the error e come from the frame functions
(``fd.frame_jacobian``, ``fd.frame_acceleration``, ...); the linear algebra
runs in the compiled core on M's tree-sparse LᵀL factor (``core/cpp/ltl.hpp``:
the Schur complement ``J M⁻¹ Jᵀ``, never forming M⁻¹), with the proximal
iterations of Carpentier, Budhiraja & Mansard (RSS 2021) for dependent rows
when ``mu > 0``.
"""

from __future__ import annotations

import functools
import operator
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import core as _compiled
from ..algorithms import constraints as _constrained
from ..constraints import Constraint, FrameContact, LoopConstraint, PointContact
from ..errors import ConstraintError, FeatherdynError, ModelError, ShapeError
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, ReferenceFrame, as_reference_frame
from ..model import Model
from ..rotation import se3_log
from ..tolerances import DELASSUS_PIVOT_RTOL
from ._backend import CORE, OK, core_path, select_backend
from ._checks import check_state
from .dynamics import generalized_gravity
from .kinematics import (
    frame_acceleration,
    frame_classical_acceleration,
    frame_jacobian,
    frame_placement,
    frame_velocity,
)

_EMPTY = np.empty
_NEW = object.__new__
_SET = object.__setattr__

__all__ = ["ConstrainedDynamics", "ImpulseDynamics", "OperationalSpace", "constraint_jacobian", "constraint_drift",
           "delassus", "constrained_dynamics", "impulse_dynamics", "operational_space_inertia", "operational_space"]


def _constraints(constraints: Sequence[Constraint] | Constraint) -> list[Constraint]:
    items = [constraints] if isinstance(constraints, (PointContact, FrameContact, LoopConstraint)) else \
        list(constraints)
    for c in items:
        if not isinstance(c, (PointContact, FrameContact, LoopConstraint)):
            raise ModelError(f"constraints: expected fd.PointContact, fd.FrameContact or fd.LoopConstraint, got "
                             f"{type(c).__name__}")
    if not items:
        raise ModelError("constraints: expected at least one constraint")
    return items


def _rows(c: Constraint) -> np.ndarray:
    if isinstance(c, PointContact):
        return np.arange(3, 6)
    if isinstance(c, FrameContact):
        return np.arange(6)
    return np.flatnonzero(np.array(c.axes))


def _crm(s: np.ndarray, m: np.ndarray) -> np.ndarray:
    ws, vs, wm, vm = s[..., :3], s[..., 3:], m[..., :3], m[..., 3:]
    return np.concatenate([np.cross(ws, wm), np.cross(ws, vm) + np.cross(vs, wm)], axis=-1)


def _motion_matrix(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The motion transform ``[[R, 0], [p×R, R]]`` `(..., 6, 6)` of a pose (R, p)."""
    z = np.zeros(p.shape[:-1], dtype=p.dtype)
    P = np.stack([np.stack([z, -p[..., 2], p[..., 1]], -1), np.stack([p[..., 2], z, -p[..., 0]], -1),
                  np.stack([-p[..., 1], p[..., 0], z], -1)], -2)
    out = np.zeros(R.shape[:-2] + (6, 6), dtype=np.result_type(R, p))
    out[..., :3, :3] = R
    out[..., 3:, 3:] = R
    out[..., 3:, :3] = P @ R
    return out


def _one(model: Model, q: np.ndarray, v: np.ndarray | None, c: Constraint, backend: str | None
         ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """``(J, γ, e)`` of one constraint, all rows (selected later): J `(..., 6, nv)`, γ and e `(..., 6)`."""
    ref = c.reference
    if isinstance(c, (PointContact, FrameContact)):
        J = frame_jacobian(model, q, c.frame, ref, backend=backend)
        if v is None:
            return J, None, None
        zero = np.zeros_like(v)
        acc = frame_classical_acceleration if isinstance(c, PointContact) else frame_acceleration
        return J, acc(model, q, v, zero, c.frame, ref, backend=backend).vector, np.zeros(J.shape[:-1], dtype=J.dtype)
    Ja, Jb = frame_jacobian(model, q, c.frame_a, LOCAL, backend=backend), frame_jacobian(model, q, c.frame_b, LOCAL, backend=backend)
    Ma, Mb = frame_placement(model, q, c.frame_a, backend=backend), frame_placement(model, q, c.frame_b, backend=backend)
    aMb = Ma.inverse() @ Mb
    X = _motion_matrix(aMb.rotation, aMb.translation)
    J_rel = Ja - X @ Jb
    if ref is WORLD:
        B = _motion_matrix(Ma.rotation, Ma.translation)
    elif ref is LOCAL_WORLD_ALIGNED:
        B = _motion_matrix(Ma.rotation, np.zeros_like(Ma.translation))
    else:
        B = None
    J = J_rel if B is None else B @ J_rel
    if v is None:
        return J, None, None
    zero = np.zeros_like(v)
    va = frame_velocity(model, q, v, c.frame_a, LOCAL, backend=backend).vector
    Xvb = (X @ frame_velocity(model, q, v, c.frame_b, LOCAL, backend=backend).vector[..., None])[..., 0]
    r = va - Xvb
    aa = frame_acceleration(model, q, v, zero, c.frame_a, LOCAL, backend=backend).vector
    ab = (X @ frame_acceleration(model, q, v, zero, c.frame_b, LOCAL, backend=backend).vector[..., None])[..., 0]
    gamma = aa - ab + _crm(r, Xvb)  # d/dt (v_a − ᵃX_b v_b) at q̈ = 0, with d(ᵃX_b)/dt = −(r ×) ᵃX_b
    e = se3_log(aMb).vector
    if ref is WORLD:
        gamma = gamma + _crm(va, r)  # d/dt (⁰X_a y) = ⁰X_a (ẏ + v_a × y)
    elif ref is LOCAL_WORLD_ALIGNED:
        w = va[..., :3]
        gamma = gamma + np.concatenate([np.cross(w, r[..., :3]), np.cross(w, r[..., 3:])], axis=-1)
    if B is not None:
        gamma = (B @ gamma[..., None])[..., 0]
        e = (B @ e[..., None])[..., 0]
    return J, gamma, e


def _check_bodies(model: Model, items: list[Constraint]) -> None:
    """Refuse constraints without rows to act on: a contact on a frame fixed to the world, a loop within one body."""
    def body(frame: str | int) -> int:
        return model.frames[model.resolve_frame(frame)].body

    for c in items:
        if isinstance(c, (PointContact, FrameContact)) and body(c.frame) == -1:
            raise ConstraintError(f"{type(c).__name__}({c.frame!r}): the frame is fixed to the world, so the contact "
                                  "has nothing to hold (its rows are zero); constrain a frame of a moving body")
        if isinstance(c, LoopConstraint) and body(c.frame_a) == body(c.frame_b):
            where = "the world" if body(c.frame_a) == -1 else f"body {model.body_names[body(c.frame_a)]!r}"
            raise ConstraintError(f"LoopConstraint({c.frame_a!r}, {c.frame_b!r}): both frames are fixed to {where}, "
                                  "so the loop has nothing to close (its rows are zero)")


def _stack(model: Model, q: np.ndarray, v: np.ndarray | None, items: list[Constraint], backend: str | None = None
           ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    _check_bodies(model, items)
    Js, gs, cs = [], [], []
    for c in items:
        J, gamma, e = _one(model, q, v, c, backend)
        rows = _rows(c)
        Js.append(J[..., rows, :])
        if gamma is not None and e is not None and v is not None:
            kp, kd = c.baumgarte
            gs.append(gamma[..., rows])
            Jv = (J[..., rows, :] @ v[..., None])[..., 0]
            cs.append(-gamma[..., rows] - kp * e[..., rows] - kd * Jv)
    J = np.concatenate(Js, axis=-2)
    if v is None:
        return J, None, None
    return J, np.concatenate(gs, axis=-1), np.concatenate(cs, axis=-1)


def constraint_jacobian(model: Model, q: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
                        backend: str | None = None) -> np.ndarray:
    """The constraints' rows stacked, ``J`` `(..., m, nv)` (point contact: 3 rows, frame contact: 6, loop: its axes)::

        point: the linear rows of the frame Jacobian in ``reference``;  frame: the frame Jacobian;
        loop: the chosen rows of J_a − ᵃX_b J_b (in a's frame, then ``reference``)
    """
    if _dask.lazy(q):
        return _dask.call(constraint_jacobian, model, {"q": q}, constraints=constraints, backend=backend)
    items = _constraints(constraints)
    st = check_state(model, q)
    return _stack(model, st.q, None, items, backend)[0]


def constraint_drift(model: Model, q: ArrayLike, v: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
                     backend: str | None = None) -> np.ndarray:
    """``γ = J̇ q̇`` `(..., m)`: the constrained quantities' acceleration at q̈ = 0::

        point: the classical acceleration of the frame's origin;  frame: its spatial acceleration;
        loop: d/dt (v_a − ᵃX_b v_b) at q̈ = 0 — all in ``reference``
    """
    if _dask.lazy(q, v):
        return _dask.call(constraint_drift, model, {"q": q, "v": v}, constraints=constraints, backend=backend)
    items = _constraints(constraints)
    st = check_state(model, q, v=v)
    gamma = _stack(model, st.q, st.arrays["v"], items, backend)[1]
    assert gamma is not None
    return gamma


def _factor(model: Model, q: np.ndarray) -> np.ndarray:
    """The reference's ``L`` with ``M(q) = Lᵀ L``; a singular M raises ``fd.aba``'s error for its first bad state."""
    from .dynamics import aba, crba

    L, bad = _constrained.ltl_factor(model, crba(model, q, backend="reference"))
    if np.any(bad >= 0):
        row = q[np.unravel_index(int(np.flatnonzero(bad.ravel() >= 0)[0]), bad.shape)] if bad.ndim else q
        zero = np.zeros(model.nv, dtype=row.dtype)
        aba(model, row, zero, zero, gravity=False, backend="reference")  # raises SingularMassMatrixError
    return L


def _delassus(model: Model, q: np.ndarray, J: np.ndarray, backend: str | None) -> np.ndarray:
    """``J M⁻¹ Jᵀ`` by the backend's LᵀL factor."""
    if select_backend(backend, np.result_type(q, J)) == "compiled":
        return _compiled.delassus(model, q, J)
    return _constrained.delassus(model, _factor(model, q), J)


def _mass_solve(model: Model, q: np.ndarray, b: np.ndarray, backend: str | None) -> np.ndarray:
    """``M⁻¹ b`` by the backend's LᵀL factor."""
    if select_backend(backend, np.result_type(q, b)) == "compiled":
        return _compiled.mass_solve(model, q, b)
    return _constrained.mass_solve(model, _factor(model, q), b)


def _solve(model: Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray, J: np.ndarray, c: np.ndarray,
           f_ext: ArrayLike | None, mu: float, max_iter: int, tol: float, backend: str | None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, residual)`` of ``M q̈ + h = τ + Jᵀ λ``, ``J q̈ = c`` by the backend (the same algorithm)."""
    if select_backend(backend, np.result_type(q, v, tau, J, c)) == "compiled":
        return _compiled.constrained_solve(model, q, v, tau, J, c, f_ext, mu=mu, max_iter=max_iter, tol=tol)
    from .dynamics import rnea

    h = rnea(model, q, v, np.zeros_like(v), f_ext, backend="reference")
    sol = _constrained.kkt_solve(model, _factor(model, q), tau - h, J, c, mu=float(mu), max_iter=int(max_iter),
                                 tol=float(tol), singular_tol=DELASSUS_PIVOT_RTOL)
    _raise_iterations(sol.iterations, J.shape[-2], max_iter, tol)
    return sol.qdd, sol.lam, sol.residual


_INF = float("inf")


def _solver_args(mu: object, max_iter: object, tol: object) -> tuple[float, int, float]:
    """``mu`` a finite number ≥ 0, ``max_iter`` an integer ≥ 1, ``tol`` a finite number > 0, or a ConstraintError."""
    try:
        m, t = float(mu), float(tol)  # type: ignore[arg-type]
        k = operator.index(max_iter)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ConstraintError(f"mu, max_iter, tol: expected numbers (max_iter an integer), got {mu!r}, {max_iter!r}, "
                              f"{tol!r}") from None
    if not 0.0 <= m < _INF:
        raise ConstraintError(f"mu: expected a finite number >= 0 (the proximal regularisation), got {mu!r}")
    if k < 1:
        raise ConstraintError(f"max_iter: expected an integer >= 1, got {max_iter!r}")
    if not 0.0 < t < _INF:
        raise ConstraintError(f"tol: expected a finite number > 0, got {tol!r}")
    return m, k, t


def _raise_iterations(iterations: np.ndarray, m: int, max_iter: int, tol: float) -> None:
    """The solve's failures: ``−1`` dependent rows (with ``mu = 0``), ``−2`` proximal iterations not converged."""
    if np.any(iterations == -1):
        raise ConstraintError.dependent(m)
    if np.any(iterations == -2):
        raise ConstraintError.not_converged(max_iter, tol)


_REF_CODE = {LOCAL: 0, WORLD: 1, LOCAL_WORLD_ALIGNED: 2}


#: a contact plan: the slices of λ per constraint, the core's specs `(nc, 4)` (rows, frame, reference code, K_d),
#: m, and the core's checked copy of the specs for the one-state call (``None`` when the core cannot take the model)
_ContactPlan = tuple[list[slice], np.ndarray, int, Any]


def _core_plan(model: Model, specs: np.ndarray) -> Any:
    """The core's ``ContactPlan`` of ``specs`` (checked once, so a one-state call converts no specs array), or
    ``None`` when the core cannot take the model."""
    if CORE is None:
        return None
    try:
        return CORE.ContactPlan(_compiled._view(model).cm, specs)
    except (TypeError, ValueError, FeatherdynError):
        return None


@functools.lru_cache(maxsize=256)
def _contact_plan_cached(model: Model, key: tuple[Constraint, ...]) -> _ContactPlan | None:
    items = _constraints(list(key))
    contacts = [c for c in items if isinstance(c, (PointContact, FrameContact))]
    if len(contacts) != len(items):
        return None
    _check_bodies(model, items)
    specs = np.array([[c.size, model.resolve_frame(c.frame), _REF_CODE[c.reference], c.baumgarte[1]]
                      for c in contacts], dtype=np.float64)
    ends = np.cumsum(specs[:, 0]).astype(int).tolist()
    return [slice(e - c.size, e) for e, c in zip(ends, contacts, strict=True)], specs, ends[-1], \
        _core_plan(model, specs)


@functools.lru_cache(maxsize=256)
def _frames_plan_cached(model: Model, frames: tuple[str | int, ...], reference: ReferenceFrame
                        ) -> tuple[Any, tuple[int, int]] | None:
    if not frames:
        return None
    specs = np.array([[6, model.resolve_frame(f), _REF_CODE[reference], 0.0] for f in frames], dtype=np.float64)
    plan = _core_plan(model, specs)
    return None if plan is None else (plan, (6 * len(frames), 6 * len(frames)))


def _same_items(a: list[Any], b: list[Any]) -> bool:
    """``a == b`` for two lists (item by item, identity first), ``False`` when an item's ``==`` is not a truth
    value (an array where a constraint or a frame belongs: the general path words that)."""
    try:
        return a == b
    except (TypeError, ValueError):
        return False


#: the last frames plan: (model, a copy of the frames list or the tuple or name itself, the reference, the plan)
_LAST_FRAMES: tuple[Any, Any, Any, Any] = (None, None, None, None)


def _frames_plan(model: Model, frames: Sequence[str | int] | str | int, reference: ReferenceFrame | str
                 ) -> tuple[Any, tuple[int, int]] | None:
    """The core's plan of the frames (6 rows each) and the shape of Λ, cached; ``None`` when the general path
    must word an error (no frames, an unknown frame or reference, unhashable input) or the core cannot take
    the model."""
    global _LAST_FRAMES
    last_model, last_frames, last_reference, plan = _LAST_FRAMES
    if last_model is model and reference is last_reference and (frames is last_frames or (
            type(frames) is list and type(last_frames) is list and _same_items(frames, last_frames))):
        return plan
    try:
        key = (frames,) if isinstance(frames, (str, int)) else tuple(frames)
        plan = _frames_plan_cached(model, key, as_reference_frame(reference))
    except (TypeError, ValueError, FeatherdynError):
        return None
    if type(frames) in (list, tuple, str, int):
        _LAST_FRAMES = (model, frames.copy() if type(frames) is list else frames, reference, plan)
    return plan


#: the last plan: (model, a copy of the constraints list or the tuple itself, the plan), one tuple replaced whole
#: (thread-safe reads). Constraints are frozen values, so equal items mean the same plan; a list compares item by
#: item by identity first (C speed), so a control loop that passes the same list pays a few pointer compares
_LAST_PLAN: tuple[Any, Any, Any] = (None, None, None)


def _contact_plan(model: Model, constraints: Sequence[Constraint] | Constraint) -> _ContactPlan | None:
    """``(slices of λ, specs (nc, 4), m, the core's plan)`` when every constraint is a point or frame contact
    (``contacts.hpp`` computes their rows in the core), else ``None``; cached per model and constraint tuple."""
    global _LAST_PLAN
    last_model, last_items, plan = _LAST_PLAN
    if last_model is model and (constraints is last_items or (
            type(constraints) is list and type(last_items) is list and _same_items(constraints, last_items))):
        return plan
    plan = _contact_plan_lookup(model, constraints)
    if type(constraints) is list:
        _LAST_PLAN = (model, constraints.copy(), plan)
    elif type(constraints) is tuple:
        _LAST_PLAN = (model, constraints, plan)
    return plan


def _contact_plan_lookup(model: Model, constraints: Sequence[Constraint] | Constraint) -> _ContactPlan | None:
    key = constraints if isinstance(constraints, tuple) else (constraints,) if isinstance(
        constraints, (PointContact, FrameContact, LoopConstraint)) else tuple(constraints)
    try:
        return _contact_plan_cached(model, key)
    except TypeError:  # an unhashable item: not a constraint (the general path words the error)
        return None


def delassus(model: Model, q: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
             backend: str | None = None) -> np.ndarray:
    """``J M⁻¹ Jᵀ`` `(..., m, m)` from M's tree-sparse factor, without forming M⁻¹::

        J M⁻¹ Jᵀ = Y Yᵀ,   Y = J L⁻¹,   M = Lᵀ L
    """
    if _dask.lazy(q):
        return _dask.call(delassus, model, {"q": q}, constraints=constraints, backend=backend)
    J = constraint_jacobian(model, q, constraints, backend=backend)
    return _delassus(model, check_state(model, q).q, J, backend)


@dataclass(frozen=True, slots=True)
class ConstrainedDynamics:
    """The result of :func:`constrained_dynamics`.

    Attributes:
        ddq: `(..., nv)`.
        forces: one array per constraint: `(..., 3)` force, `(..., 6)` wrench ``[n; f]``, `(..., k)` for a loop.
        lagrange: `(..., m)` all of them stacked.
        residual: `(...)` ``max |J q̈ − c|`` with ``c = −γ − K_p e − K_d J v``.
    """

    ddq: np.ndarray
    forces: list[np.ndarray]
    lagrange: np.ndarray
    residual: np.ndarray


def _split(lam: np.ndarray, items: list[Constraint]) -> list[np.ndarray]:
    out, pos = [], 0
    for c in items:
        out.append(lam[..., pos: pos + c.size])
        pos += c.size
    return out


def _contact_rows_batch(core: Any, q: np.ndarray, v: Any, tau: Any, plan: _ContactPlan, mu: float, max_iter: int,
                        tol: float) -> ConstrainedDynamics | None:
    """A batch of rows `(N, nq)`, `(N | 1, nv)` ×2 handed to the core as it is (its checks run per row inside, and
    its groups of states run on SIMD packs); ``None`` when the binding refuses an argument or any row fails (a bad
    state, a singular M, dependent contacts, no convergence): the general path then checks and words the error."""
    slices, specs, m, _ = plan
    n = q.shape[0]
    qdd, lam, info = _EMPTY((n, core.nv)), _EMPTY((n, m)), _EMPTY((n, 2))
    try:
        if not (0.0 <= mu < _INF and max_iter >= 1 and 0.0 < tol < _INF) or CORE.contact_dynamics_batch(
                core.cm, q, v, tau, None, specs, mu, max_iter, tol, DELASSUS_PIVOT_RTOL, qdd, lam, info)[1] != OK:
            return None
    except TypeError:
        return None
    if not (info[:, 0] > 0.0).all():
        return None
    out = _NEW(ConstrainedDynamics)
    _SET(out, "ddq", qdd)
    _SET(out, "forces", [lam[:, s] for s in slices])
    _SET(out, "lagrange", lam)
    _SET(out, "residual", info[:, 1])
    return out


def constrained_dynamics(model: Model, q: ArrayLike, v: ArrayLike, tau: ArrayLike,
                         constraints: Sequence[Constraint] | Constraint, *, f_ext: ArrayLike | None = None,
                         mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12,
                         backend: str | None = None) -> ConstrainedDynamics:
    """Forward dynamics under constraints (``algorithms/constrained.py``; the core's ``ltl.hpp`` for float64)::

        M q̈ + h = τ + Jᵀ λ,     J q̈ + γ = −K_p e − K_d J v

    solved on M's tree-sparse factor by the Schur complement (q̈_f = M⁻¹(τ − h), (J M⁻¹ Jᵀ) λ = c − J q̈_f).
    Forces act on the robot, in each constraint's ``reference`` (a loop's: from body b on body a).
    ``mu > 0``: proximal iterations, the minimum-norm forces when constraints are dependent.

    Raises:
        ConstraintError: dependent constraints with ``mu = 0`` (the message suggests ``mu``).
    """
    core = core_path(model, backend)
    if core is not None:
        plan = _contact_plan(model, constraints)
        if plan is not None and plan[3] is not None:
            slices, _, m, core_plan = plan
            qdd, lam, info = _EMPTY(core.nv), _EMPTY(m), _EMPTY(2)
            try:  # (solver arguments out of range, or not numbers: the general path words the error)
                if 0.0 <= mu < _INF and max_iter >= 1 and 0.0 < tol < _INF and CORE.contact_dynamics(
                        core.cm, q, v, tau, f_ext, core_plan, mu, max_iter, tol, DELASSUS_PIVOT_RTOL, qdd, lam,
                        info) == OK and info[0] > 0:
                    out = _NEW(ConstrainedDynamics)  # (a frozen dataclass's __init__ costs more than the solve's rows)
                    _SET(out, "ddq", qdd)
                    _SET(out, "forces", [lam[s] for s in slices])
                    _SET(out, "lagrange", lam)
                    _SET(out, "residual", info[1])
                    return out
            except TypeError:  # arguments the binding does not take as they are: the general path converts
                pass
            if type(q) is np.ndarray and q.ndim == 2 and f_ext is None:
                batch = _contact_rows_batch(core, q, v, tau, plan, mu, max_iter, tol)
                if batch is not None:
                    return batch
    mu, max_iter, tol = _solver_args(mu, max_iter, tol)
    if _dask.lazy(q, v, tau, f_ext):
        return _dask.call(constrained_dynamics, model, {"q": q, "v": v, "tau": tau, "f_ext": f_ext},
                          constraints=constraints, mu=mu, max_iter=max_iter, tol=tol, backend=backend)
    items = _constraints(constraints)
    st = check_state(model, q, v=v, tau=tau)
    qd = st.arrays["v"]
    plan = _contact_plan(model, constraints)
    if plan is not None and select_backend(backend, st.dtype) == "compiled":
        specs = plan[1]
        ddq, lam, its, res = _compiled.contact_dynamics(model, st.q, qd, st.arrays["tau"], specs, f_ext, mu=mu,
                                                        max_iter=max_iter, tol=tol)
        _raise_iterations(its, lam.shape[-1], max_iter, tol)
        return ConstrainedDynamics(ddq, _split(lam, items), lam, res)
    J, _, c = _stack(model, st.q, qd, items, backend)
    assert c is not None
    ddq, lam, res = _solve(model, st.q, qd, st.arrays["tau"], J, c, f_ext, mu, max_iter, tol, backend)
    return ConstrainedDynamics(ddq, _split(lam, items), lam, res)


@dataclass(frozen=True)
class ImpulseDynamics:
    """The result of :func:`impulse_dynamics`: ``v_plus`` `(..., nv)`, ``impulses`` (one per constraint),
    ``lagrange`` `(..., m)` stacked."""

    v_plus: np.ndarray
    impulses: list[np.ndarray]
    lagrange: np.ndarray


def impulse_dynamics(model: Model, q: ArrayLike, v: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
                     restitution: float = 0.0, mu: float = 0.0, backend: str | None = None) -> ImpulseDynamics:
    """The velocity just after an impact with the constraints::

        M (v⁺ − v⁻) = Jᵀ Λ,     J v⁺ = −e J v⁻      (e: the restitution coefficient, 0 ≤ e ≤ 1)
    """
    if _dask.lazy(q, v):
        return _dask.call(impulse_dynamics, model, {"q": q, "v": v}, constraints=constraints,
                          restitution=restitution, mu=mu, backend=backend)
    if not (0.0 <= float(restitution) <= 1.0):
        raise ModelError(f"restitution: expected a number in [0, 1], got {restitution!r}")
    mu = _solver_args(mu, 1, 1.0)[0]
    items = _constraints(constraints)
    st = check_state(model, q, v=v)
    vm = st.arrays["v"]
    J = _stack(model, st.q, None, items, backend)[0]
    c = -float(restitution) * (J @ vm[..., None])[..., 0]
    # the same linear system as constrained_dynamics with q̈ := v⁺ and τ − h := M v⁻ (at zero velocity,
    # h is the gravity g(q), which τ = M v⁻ + g(q) cancels)
    from .dynamics import crba

    rhs = (crba(model, st.q, backend=backend) @ vm[..., None])[..., 0] + \
        generalized_gravity(model, st.q, backend=backend)
    v_plus, lam, _ = _solve(model, st.q, np.zeros_like(vm), rhs, J, c, None, mu, 50, 1e-12, backend)
    return ImpulseDynamics(v_plus, _split(lam, items), lam)


def _frames_jacobian(model: Model, q: np.ndarray, frames: Sequence[str | int] | str | int,
                     reference: ReferenceFrame | str, backend: str | None) -> np.ndarray:
    names = [frames] if isinstance(frames, (str, int)) else list(frames)
    if not names:
        raise ShapeError("frames: expected at least one frame")
    ref = as_reference_frame(reference)
    return np.concatenate([frame_jacobian(model, q, f, ref, backend=backend) for f in names], axis=-2)


def operational_space_inertia(model: Model, q: ArrayLike, frames: Sequence[str | int] | str | int,
                              reference: ReferenceFrame | str = LOCAL_WORLD_ALIGNED, *, mu: float = 0.0,
                              backend: str | None = None) -> np.ndarray:
    """``Λ = (J M⁻¹ Jᵀ + μ 1)⁻¹`` `(..., 6k, 6k)` for the stacked frame Jacobians (``[ω; v]`` blocks)::

        J M⁻¹ Jᵀ from M's tree-sparse factor (M is never inverted); μ > 0 regularises a singular J
    """
    core = core_path(model, backend)
    if core is not None:
        fplan = _frames_plan(model, frames, reference)
        if fplan is not None:
            out = _EMPTY(fplan[1])
            try:
                if 0.0 <= mu < _INF and CORE.operational_space_inertia(core.cm, q, fplan[0], mu, DELASSUS_PIVOT_RTOL,
                                                                       out) == OK:
                    return out
            except TypeError:  # arguments the binding does not take as they are: the general path converts
                pass
            if type(q) is np.ndarray and q.ndim == 2:  # rows (N, nq): the core's batch, on SIMD packs
                out = _EMPTY((q.shape[0], *fplan[1]))
                try:
                    if 0.0 <= mu < _INF and CORE.operational_space_inertia_batch(
                            core.cm, q, fplan[0], mu, DELASSUS_PIVOT_RTOL, out)[1] == OK:
                        return out
                except TypeError:
                    pass
    mu = _solver_args(mu, 1, 1.0)[0]
    if _dask.lazy(q):
        return _dask.call(operational_space_inertia, model, {"q": q}, frames=frames, reference=reference, mu=mu,
                          backend=backend)
    st = check_state(model, q)
    J = _frames_jacobian(model, st.q, frames, reference, backend)
    D = _delassus(model, st.q, J, backend) + float(mu) * np.eye(J.shape[-2], dtype=J.dtype)
    return np.linalg.inv(D)


@dataclass(frozen=True)
class OperationalSpace:
    """``Lambda`` Λ, ``Lambda_inv`` J M⁻¹ Jᵀ, ``J``, ``J_bar`` = M⁻¹ Jᵀ Λ (`(..., nv, 6k)`), ``mu`` = Λ (J M⁻¹ h − J̇ v),
    ``p`` = J̄ᵀ g — task-space quantities of :func:`operational_space`."""

    Lambda: np.ndarray
    Lambda_inv: np.ndarray
    J: np.ndarray
    J_bar: np.ndarray
    mu: np.ndarray
    p: np.ndarray


def operational_space(model: Model, q: ArrayLike, v: ArrayLike, frames: Sequence[str | int] | str | int,
                      reference: ReferenceFrame | str = LOCAL_WORLD_ALIGNED, *,
                      backend: str | None = None) -> OperationalSpace:
    """The operational-space quantities of the stacked frames (Khatib 1987)::

        Λ = (J M⁻¹ Jᵀ)⁻¹,   J̄ = M⁻¹ Jᵀ Λ,   μ = Λ (J M⁻¹ h − J̇ v),   p = J̄ᵀ g
    """
    if _dask.lazy(q, v):
        return _dask.call(operational_space, model, {"q": q, "v": v}, frames=frames, reference=reference,
                          backend=backend)
    from .dynamics import nonlinear_effects
    from .kinematics import frame_jacobian_time_variation

    st = check_state(model, q, v=v)
    qd = st.arrays["v"]
    names = [frames] if isinstance(frames, (str, int)) else list(frames)
    ref = as_reference_frame(reference)
    J = _frames_jacobian(model, st.q, names, ref, backend)
    Lambda_inv = _delassus(model, st.q, J, backend)
    Lambda = np.linalg.inv(Lambda_inv)
    MinvJt = np.stack([_mass_solve(model, st.q, J[..., r, :], backend) for r in range(J.shape[-2])], axis=-1)
    J_bar = MinvJt @ Lambda
    h = nonlinear_effects(model, st.q, qd, backend=backend)
    Jdot_v = np.concatenate([(frame_jacobian_time_variation(model, st.q, qd, f, ref, backend=backend)
                              @ qd[..., None])[..., 0] for f in names], axis=-1)
    Minv_h = _mass_solve(model, st.q, h, backend)
    mu = (Lambda @ ((J @ Minv_h[..., None])[..., 0] - Jdot_v)[..., None])[..., 0]
    p = (np.swapaxes(J_bar, -1, -2) @ generalized_gravity(model, st.q, backend=backend)[..., None])[..., 0]
    return OperationalSpace(Lambda, Lambda_inv, J, J_bar, mu, p)
