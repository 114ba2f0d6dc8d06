"""Constrained dynamics, impulses and operational space: the public functions.

::

    M q̈ + h = τ + Jᵀ λ,        J q̈ + γ = −K_p e − K_d J v

Each function checks its input, picks the backend and calls the reference
(``algorithms/constraints.py``: the rows J, γ, e from the forward kinematics,
the KKT solve on M's tree-sparse LᵀL factor, the proximal iterations of
Carpentier, Budhiraja & Mansard, RSS 2021, when ``mu > 0``) or the compiled
core (``core/cpp/contacts.hpp``: a set of contacts' rows and solve in one call,
from the plan cached on the model; ``ltl.hpp``: the solve of rows built here).
The constraint values and their plans are in ``featherdyn/constraints.py``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import constraints as _con
from .. import core as _compiled
from ..algorithms import constraints as _alg
from ..constraints import Constraint, ContactPlan, cached_contact_plan, cached_frames_plan
from ..core import declared as _declared
from ..errors import ConstraintError, FeatherdynError, ModelError
from ..frames import LOCAL_WORLD_ALIGNED, ReferenceFrame
from ..model import Model
from ..tolerances import DELASSUS_PIVOT_RTOL
from ._backend import CORE, core_path, select_backend
from ._checks import State, as_dtype, check_state, quiet
from .dynamics import generalized_gravity
from .kinematics import kinematics_of

_NEW = object.__new__
_SET = object.__setattr__
_CONTACTS = _declared.kernel("contact_dynamics")  # the declared kernels (core/cpp/declarations_constraints.hpp)
_FRAMES = _declared.kernel("operational_space_inertia")
_IMPULSES = _declared.kernel("impulse_dynamics")

__all__ = ["ConstrainedDynamics", "ImpulseDynamics", "OperationalSpace", "constraint_jacobian", "constraint_drift",
           "delassus", "constrained_dynamics", "impulse_dynamics", "operational_space_inertia", "operational_space"]


def _jacobian(model: Model, st: State, backend: str | None) -> _alg.FrameJacobian:
    """The frames' Jacobians by the core when the backend is the compiled one (the reference forms them from the
    forward kinematics, joint by joint)."""
    if select_backend(backend, st.dtype) != "compiled":
        return None
    return lambda fid, ref: as_dtype(_declared.run("frame_jacobian", model, st.batch, [st.q],
                                                   options={"frame": fid, "reference": ref.code})[0], st.dtype)


def _rows(model: Model, st: State, qd: np.ndarray | None, items: list[Constraint], backend: str | None
          ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """``(J, γ, c)`` of a checked state: the reference's rows on the backend's forward kinematics (at q̈ = 0)."""
    _con.check_bodies(model, items)
    kin = kinematics_of(model, st, qd, None if qd is None else np.zeros_like(qd), backend)
    return quiet(_alg.constraint_rows, model, kin, items, qd, _jacobian(model, st, backend))


def constraint_jacobian(model: Model, q: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
                        backend: str | None = None) -> np.ndarray:
    """The constraints' rows stacked, ``J`` `(..., m, nv)` (point contact: 3 rows, frame contact: 6, loop: its axes)::

        point: the linear rows of the frame Jacobian in ``reference``;  frame: the frame Jacobian;
        loop: the chosen rows of J_a − ᵃX_b J_b (in a's frame, then ``reference``)
    """
    if _dask.lazy(q):
        return _dask.call(constraint_jacobian, model, {"q": q}, constraints=constraints, backend=backend)
    items = _con.as_constraints(constraints)
    return _rows(model, check_state(model, q), None, items, backend)[0]


def constraint_drift(model: Model, q: ArrayLike, v: ArrayLike, constraints: Sequence[Constraint] | Constraint, *,
                     backend: str | None = None) -> np.ndarray:
    """``γ = J̇ q̇`` `(..., m)`: the constrained quantities' acceleration at q̈ = 0::

        point: the classical acceleration of the frame's origin;  frame: its spatial acceleration;
        loop: d/dt (v_a − ᵃX_b v_b) at q̈ = 0 — all in ``reference``
    """
    if _dask.lazy(q, v):
        return _dask.call(constraint_drift, model, {"q": q, "v": v}, constraints=constraints, backend=backend)
    items = _con.as_constraints(constraints)
    st = check_state(model, q, v=v)
    gamma = _rows(model, st, st.arrays["v"], items, backend)[1]
    assert gamma is not None
    return gamma


def _delassus(model: Model, q: np.ndarray, J: np.ndarray, backend: str | None) -> np.ndarray:
    """``J M⁻¹ Jᵀ`` by the backend's LᵀL factor."""
    if select_backend(backend, np.result_type(q, J)) == "compiled":
        return _compiled.delassus(model, q, J)
    return _alg.delassus(model, quiet(_alg.mass_factor, model, q), J)


def _mass_solve(model: Model, q: np.ndarray, b: np.ndarray, backend: str | None) -> np.ndarray:
    """``M⁻¹ b`` by the backend's LᵀL factor."""
    if select_backend(backend, np.result_type(q, b)) == "compiled":
        return _compiled.mass_solve(model, q, b)
    return _alg.mass_solve(model, quiet(_alg.mass_factor, model, q), b)


def _solve(model: Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray, J: np.ndarray, c: np.ndarray,
           f_ext: ArrayLike | None, mu: float, max_iter: int, tol: float, backend: str | None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, residual)`` of ``M q̈ + h = τ + Jᵀ λ``, ``J q̈ = c`` by the backend (the same algorithm)."""
    if select_backend(backend, np.result_type(q, v, tau, J, c)) == "compiled":
        return _compiled.constrained_solve(model, q, v, tau, J, c, f_ext, mu=mu, max_iter=max_iter, tol=tol)
    from .dynamics import rnea

    h = rnea(model, q, v, np.zeros_like(v), f_ext, backend="reference")
    sol = _alg.kkt_solve(model, quiet(_alg.mass_factor, model, q), tau - h, J, c, mu=float(mu), max_iter=int(max_iter),
                         tol=float(tol), singular_tol=DELASSUS_PIVOT_RTOL)
    ConstraintError.check_iterations(sol.iterations, J.shape[-2], max_iter, tol)
    return sol.qdd, sol.lam, sol.residual


_DEFAULT_SOLVER = (0.0, 50, 1e-12)  # (mu, max_iter, tol) as the public functions default them


def core_contact_plan(model: Model, plan: ContactPlan) -> tuple[Any, Any] | None:
    """The core's ``ContactPlan`` of ``plan`` (its specs checked once, so that a one-state call converts no array)
    and the ``Options`` of a solve with it at the default settings (made once too), or ``None`` when the core
    cannot take the model."""
    if CORE is None:
        return None
    try:
        core_plan = CORE.ContactPlan(_compiled._view(model).cm, plan.specs)
    except (TypeError, ValueError, FeatherdynError):
        return None
    return core_plan, _declared.call_options(plan=core_plan, singular_tol=DELASSUS_PIVOT_RTOL)


def _solver(compiled: tuple[Any, Any], mu: Any, max_iter: Any = 50, tol: Any = 1e-12) -> Any:
    """The core's ``Options`` of a solve with a compiled plan: its own at the default settings, else made here
    (``TypeError`` or ``ValueError`` for settings that are not numbers; settings out of range make the kernel
    decline: the general path words both)."""
    core_plan, default = compiled
    if (mu, max_iter, tol) == _DEFAULT_SOLVER:
        return default
    return _declared.call_options(plan=core_plan, mu=mu, max_iter=max_iter, tol=tol, singular_tol=DELASSUS_PIVOT_RTOL)


def _impact(compiled: tuple[Any, Any], e: float) -> Any:
    """The core's ``Options`` of an impact with a compiled plan and restitution ``e`` (the plan's own for e = 0)."""
    core_plan, default = compiled
    return default if e == 0.0 else _declared.call_options(plan=core_plan, restitution=e,
                                                            singular_tol=DELASSUS_PIVOT_RTOL)


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
    return np.split(lam, np.cumsum([c.size for c in items])[:-1], axis=-1)


def _contact_result(qdd: np.ndarray, lam: np.ndarray, info: np.ndarray, plan: ContactPlan) -> ConstrainedDynamics | None:
    """The result of a solve the core finished, one state `(nv,)` or a stack of them `(..., nv)` (``None`` when a
    state's rows were dependent or did not converge: the general path raises)."""
    if not (info[0] > 0.0 if info.ndim == 1 else (info[..., 0] > 0.0).all()):  # (one state: 1.7 µs less)
        return None
    out = _NEW(ConstrainedDynamics)  # (a frozen dataclass's __init__ costs more than the solve's rows)
    _SET(out, "ddq", qdd)
    _SET(out, "forces", [lam[..., s] for s in plan.slices])
    _SET(out, "lagrange", lam)
    _SET(out, "residual", info[..., 1])
    return out


def constrained_dynamics(model: Model, q: ArrayLike, v: ArrayLike, tau: ArrayLike,
                         constraints: Sequence[Constraint] | Constraint, *, f_ext: ArrayLike | None = None,
                         mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12,
                         backend: str | None = None) -> ConstrainedDynamics:
    """Forward dynamics under constraints (``algorithms/constraints.py``; the core's ``contacts.hpp`` and
    ``ltl.hpp`` for float64)::

        M q̈ + h = τ + Jᵀ λ,     J q̈ + γ = −K_p e − K_d J v

    solved on M's tree-sparse factor by the Schur complement (q̈_f = M⁻¹(τ − h), (J M⁻¹ Jᵀ) λ = c − J q̈_f).
    Forces act on the robot, in each constraint's ``reference`` (a loop's: from body b on body a).
    ``mu > 0``: proximal iterations, the minimum-norm forces when constraints are dependent.

    Raises:
        ConstraintError: dependent constraints with ``mu = 0`` (the message suggests ``mu``).
    """
    core = core_path(model, backend)
    if core is not None:
        found = cached_contact_plan(model, constraints, core_contact_plan)
        if found is not None and found[1] is not None:
            plan = found[0]
            try:  # one state, or a stack of them, as the kernel takes them (a stack on its batch: SIMD groups)
                opts = _solver(found[1], mu, max_iter, tol)
                r = _CONTACTS.fresh(core.cm, (q, v, tau, f_ext), opts)
                done = None if r is None else _contact_result(r[0], r[1], r[2], plan)
                if done is not None:
                    return done
            except (TypeError, ValueError):  # arguments the binding does not take as they are: the general path
                pass
    mu, max_iter, tol = _con.solver_settings(mu, max_iter, tol)
    if _dask.lazy(q, v, tau, f_ext):
        return _dask.call(constrained_dynamics, model, {"q": q, "v": v, "tau": tau, "f_ext": f_ext},
                          constraints=constraints, mu=mu, max_iter=max_iter, tol=tol, backend=backend)
    items = _con.as_constraints(constraints)
    st = check_state(model, q, v=v, tau=tau)
    qd = st.arrays["v"]
    found = cached_contact_plan(model, constraints, core_contact_plan)
    if found is not None and select_backend(backend, st.dtype) == "compiled":
        ddq, lam, its, res = _compiled.contact_dynamics(model, st.q, qd, st.arrays["tau"], found[0].specs, f_ext,
                                                        mu=mu, max_iter=max_iter, tol=tol)
        ConstraintError.check_iterations(its, lam.shape[-1], max_iter, tol)
        return ConstrainedDynamics(ddq, _split(lam, items), lam, res)
    J, _, c = _rows(model, st, qd, items, backend)
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
    """The velocity just after an impact with the constraints (``algorithms/constraints.py: impulse_system``)::

        M (v⁺ − v⁻) = Jᵀ Λ,     J v⁺ = −e J v⁻      (e: the restitution coefficient, 0 ≤ e ≤ 1)

    For point and frame contacts the core's kernel (``core/cpp/contacts.hpp``, the constrained dynamics' KKT solve
    with ``τ − h = 0``: ``Λ = −(1 + e) D⁻¹ J v⁻``, ``v⁺ = v⁻ + M⁻¹ Jᵀ Λ`` on M's tree-sparse factor, one state or a
    stack of them) gives the exact solve (:func:`impulse_dynamics_derivatives`' ``v_plus`` agrees to round-off);
    ``mu > 0`` matters when the contacts are dependent (the proximal iterations' minimum-norm impulses), and loops
    take the general path.
    """
    try:
        e = float(restitution)
    except (TypeError, ValueError):
        e = float("nan")
    if not (0.0 <= e <= 1.0):
        raise ModelError(f"restitution: expected a number in [0, 1], got {restitution!r}")
    mu = _con.solver_settings(mu, 1, 1.0)[0]
    core = core_path(model, backend)
    found = None if core is None else cached_contact_plan(model, constraints, core_contact_plan)
    if found is not None and found[1] is not None:  # point and frame contacts: the core's kernel, as the derivatives'
        opts = _impact(found[1], e)
        try:  # one state, or a stack of them, as the kernel takes them; dependent contacts: the general path
            r = _IMPULSES.fresh(core.cm, (q, v), opts)
        except (TypeError, ValueError):
            r = None
        if r is not None:
            out = _NEW(ImpulseDynamics)  # (as _contact_result makes its record)
            _SET(out, "v_plus", r[0])
            _SET(out, "impulses", [r[1][..., s] for s in found[0].slices])
            _SET(out, "lagrange", r[1])
            return out
    if _dask.lazy(q, v):  # (after the core, which declines dask arrays: as constrained_dynamics)
        return _dask.call(impulse_dynamics, model, {"q": q, "v": v}, constraints=constraints,
                          restitution=restitution, mu=mu, backend=backend)
    items = _con.as_constraints(constraints)
    st = check_state(model, q, v=v)
    vm = st.arrays["v"]
    J = _rows(model, st, None, items, backend)[0]
    from .dynamics import crba

    tau, c = _alg.impulse_system(crba(model, st.q, backend=backend), generalized_gravity(model, st.q, backend=backend),
                                 J, vm, float(restitution))
    v_plus, lam, _ = _solve(model, st.q, np.zeros_like(vm), tau, J, c, None, mu, 50, 1e-12, backend)
    return ImpulseDynamics(v_plus, _split(lam, items), lam)


def operational_space_inertia(model: Model, q: ArrayLike, frames: Sequence[str | int] | str | int,
                              reference: ReferenceFrame | str = LOCAL_WORLD_ALIGNED, *, mu: float = 0.0,
                              backend: str | None = None) -> np.ndarray:
    """``Λ = (J M⁻¹ Jᵀ + μ 1)⁻¹`` `(..., 6k, 6k)` for the stacked frame Jacobians (``[ω; v]`` blocks)::

        J M⁻¹ Jᵀ from M's tree-sparse factor (M is never inverted); μ > 0 regularises a singular J
    """
    core = core_path(model, backend)
    found = None if core is None else cached_frames_plan(model, frames, reference, core_contact_plan)
    if core is not None and found is not None and found[1] is not None:
        try:  # one state, or a stack of them, as the kernel takes them (a stack on its batch: SIMD groups)
            opts = _solver(found[1], mu)
            r = _FRAMES.fresh(core.cm, (q,), opts)
            if r is not None:
                return r
        except (TypeError, ValueError):  # arguments the binding does not take as they are: the general path
            pass
    mu = _con.solver_settings(mu, 1, 1.0)[0]
    if _dask.lazy(q):
        return _dask.call(operational_space_inertia, model, {"q": q}, frames=frames, reference=reference, mu=mu,
                          backend=backend)
    st = check_state(model, q)
    fids, ref = _con.resolve_frames(model, frames, reference)
    if found is not None and found[1] is not None and select_backend(backend, st.dtype) == "compiled":
        return as_dtype(_declared.run("operational_space_inertia", model, st.batch, [np.asarray(st.q, np.float64)],
                                      options={"plan": found[1][0], "mu": mu, "singular_tol": DELASSUS_PIVOT_RTOL})[0],
                        st.dtype)
    J = quiet(_alg.frames_jacobian, model, kinematics_of(model, st, None, None, backend), fids, ref,
              _jacobian(model, st, backend))
    D = _delassus(model, st.q, J, backend) + float(mu) * np.eye(J.shape[-2], dtype=J.dtype)
    if D.dtype.kind == "f" and not np.all(_alg.dense_cholesky(D, DELASSUS_PIVOT_RTOL)[1]):  # the core's rule
        raise ConstraintError.singular_frames(D.shape[-1])
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
    """The operational-space quantities of the stacked frames (Khatib 1987; ``algorithms/constraints.py``)::

        Λ = (J M⁻¹ Jᵀ)⁻¹,   J̄ = M⁻¹ Jᵀ Λ,   μ = Λ (J M⁻¹ h − J̇ v),   p = J̄ᵀ g
    """
    if _dask.lazy(q, v):
        return _dask.call(operational_space, model, {"q": q, "v": v}, frames=frames, reference=reference,
                          backend=backend)
    from .dynamics import nonlinear_effects
    from .kinematics import frame_jacobian_time_variation

    st = check_state(model, q, v=v)
    qd = st.arrays["v"]
    fids, ref = _con.resolve_frames(model, frames, reference)
    J = quiet(_alg.frames_jacobian, model, kinematics_of(model, st, None, None, backend), fids, ref,
              _jacobian(model, st, backend))
    D = _delassus(model, st.q, J, backend)
    Minv_Jt = np.stack([_mass_solve(model, st.q, J[..., r, :], backend) for r in range(J.shape[-2])], axis=-1)
    Jdot_v = np.concatenate([(frame_jacobian_time_variation(model, st.q, qd, f, ref, backend=backend)
                              @ qd[..., None])[..., 0] for f in fids], axis=-1)
    Minv_h = _mass_solve(model, st.q, nonlinear_effects(model, st.q, qd, backend=backend), backend)
    Lambda, J_bar, mu, p = _alg.operational_space(D, Minv_Jt, J, Minv_h, Jdot_v,
                                                  generalized_gravity(model, st.q, backend=backend))
    return OperationalSpace(Lambda, D, J, J_bar, mu, p)
