"""Derivatives of constrained dynamics and of impulses: the public functions.

::

    ∂λ/∂x = D⁻¹ (J M⁻¹ R₁ − R₂),    ∂q̈/∂x = M⁻¹ (Jᵀ ∂λ/∂x − R₁),    D = J M⁻¹ Jᵀ

``R₁``, ``R₂`` the partials of the constrained dynamics' two equations along x, q̈ and λ held: RNEA's
derivatives with the constraint forces acting on the bodies plus the turn of each force's axes, and the
derivatives of the constrained frames' motion (``fd.kinematics_derivatives``). The formulas and their
derivation are in ``algorithms/constraint_derivatives.py`` and docs/derivatives.md; every piece is a
function the backend computes (the compiled core for float64).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import constraints as _con
from ..algorithms import constraint_derivatives as _alg
from ..algorithms.constraints import selected_rows
from ..constraints import Constraint, LoopConstraint, PointContact, cached_contact_plan
from ..core import declared as _declared
from ..frames import LOCAL, ReferenceFrame
from ..model import Model
from ..rotation import se3_log
from ..spatial.ops import skew_unchecked
from ._backend import core_path
from ._checks import check_state
from .constraints import _impact, _solver, constrained_dynamics, core_contact_plan, impulse_dynamics
from .declarations import (
    crba,
    frame_acceleration,
    frame_jacobian,
    frame_placement,
    kinematics_derivatives,
    mass_matrix_inverse,
    rnea_derivatives,
)

_CONTACTS = _declared.kernel("contact_dynamics_derivatives")  # core/cpp/declarations_constraints.hpp
_IMPULSES = _declared.kernel("impulse_dynamics_derivatives")

__all__ = ["ConstrainedDynamicsDerivatives", "ImpulseDynamicsDerivatives", "constrained_dynamics_derivatives",
           "impulse_dynamics_derivatives"]


def _kw(backend: str | None) -> dict[str, str]:
    """``backend`` as a keyword for the declared functions, only when given (without keywords their calls take
    the core's path in C: api/declared.py)."""
    return {} if backend is None else {"backend": backend}


class ConstrainedDynamicsDerivatives(NamedTuple):
    """The result of :func:`constrained_dynamics_derivatives` (a named tuple, as the other derivatives' records).

    Attributes:
        ddq_dq, ddq_dv, ddq_dtau: `(..., nv, nv)` ∂q̈/∂q (along fd.integrate's tangent), ∂q̈/∂q̇, ∂q̈/∂τ.
        forces_dq, forces_dv, forces_dtau: `(..., m, nv)` the stacked forces' (``lagrange``) derivatives.
        ddq: `(..., nv)` and lagrange `(..., m)`: the constrained dynamics they are the derivatives of.
    """

    ddq_dq: np.ndarray
    ddq_dv: np.ndarray
    ddq_dtau: np.ndarray
    forces_dq: np.ndarray
    forces_dv: np.ndarray
    forces_dtau: np.ndarray
    ddq: np.ndarray
    lagrange: np.ndarray


class ImpulseDynamicsDerivatives(NamedTuple):
    """The result of :func:`impulse_dynamics_derivatives` (a named tuple, as the other derivatives' records).

    Attributes:
        dv_plus_dq, dv_plus_dv: `(..., nv, nv)` ∂v⁺/∂q (along fd.integrate's tangent), ∂v⁺/∂v⁻.
        impulses_dq, impulses_dv: `(..., m, nv)` the stacked impulses' derivatives.
        v_plus: `(..., nv)` and lagrange `(..., m)`: the impact they are the derivatives of.
    """

    dv_plus_dq: np.ndarray
    dv_plus_dv: np.ndarray
    impulses_dq: np.ndarray
    impulses_dv: np.ndarray
    v_plus: np.ndarray
    lagrange: np.ndarray


@dataclass
class _Terms:
    """One constraint's rows J `(..., k, nv)`, its equation's partials ``R₂`` along q and q̇, and its force's:
    the spatial forces on bodies and the correction to RNEA's ∂τ/∂q."""

    J: np.ndarray
    dq: np.ndarray
    dv: np.ndarray | None
    forces: list[tuple[int, np.ndarray]]
    correction: np.ndarray | None


def _map_of(model: Model, q: np.ndarray, fid: int, reference: ReferenceFrame) -> np.ndarray | None:
    """``B`` `(..., 6, 6)`: the reference's map of the frame's LOCAL motions (``None`` for LOCAL)."""
    if reference is LOCAL:
        return None
    X = frame_placement(model, q, fid)
    if reference.value == "world":
        return X.matrix()
    R = X.rotation
    B = np.zeros(R.shape[:-2] + (6, 6), dtype=R.dtype)
    B[..., :3, :3] = B[..., 3:, 3:] = R
    return B


def _on_body(model: Model, fid: int, f_frame: np.ndarray) -> list[tuple[int, np.ndarray]]:
    frame = model.frames[fid]
    if frame.body == -1:
        return []
    place = frame.placement
    return [(frame.body, _alg.body_force(f_frame, place.rotation.astype(f_frame.dtype),
                                         place.translation.astype(f_frame.dtype)))]


def _lam6(lam: np.ndarray, rows: np.ndarray) -> np.ndarray:
    out = np.zeros(lam.shape[:-1] + (6,), dtype=lam.dtype)
    out[..., rows] = lam
    return out


def _contact_terms(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray | None, c: Constraint,
                   lam: np.ndarray, backend: str | None) -> _Terms:
    fid = model.resolve_frame(c.frame)  # type: ignore[union-attr]
    rows, ref = selected_rows(c), c.reference
    k = kinematics_derivatives(model, q, v, np.zeros_like(v) if a is None else a, fid, ref, **_kw(backend))
    if a is None:  # impulses: J v⁺ (+ e J v⁻) along q
        dq, dv = k.dv_dq[..., rows, :], None
    else:
        kd = c.baumgarte[1]
        acc_q, acc_v = (k.dac_dq, k.dac_dv) if isinstance(c, PointContact) else (k.da_dq, k.da_dv)
        dq, dv = (acc_q + kd * k.dv_dq)[..., rows, :], (acc_v + kd * k.dv_dv)[..., rows, :]
    f_a = _alg.frame_force(_lam6(lam, rows), _map_of(model, q, fid, ref))
    corr = None
    if ref is not LOCAL:
        JL = frame_jacobian(model, q, fid, LOCAL, **_kw(backend))
        corr = _alg.force_turn_correction(JL, JL, f_a, ref.value)
    return _Terms(k.dv_dv[..., rows, :], dq, dv, _on_body(model, fid, f_a), corr)


def _loop_terms(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray | None, c: LoopConstraint,
                lam: np.ndarray, backend: str | None) -> _Terms:
    fa, fb = model.resolve_frame(c.frame_a), model.resolve_frame(c.frame_b)
    rows, ref = selected_rows(c), c.reference
    acc = np.zeros_like(v) if a is None else a
    ka, kb = (kinematics_derivatives(model, q, v, acc, f, LOCAL, **_kw(backend)) for f in (fa, fb))
    oMa, oMb = frame_placement(model, q, fa), frame_placement(model, q, fb)
    aMb = oMa.inverse() @ oMb
    aXb = aMb.matrix()
    Ja, Jb = ka.dv_dv, kb.dv_dv
    va, vb = (Ja @ v[..., None])[..., 0], (Jb @ v[..., None])[..., 0]
    accs = None if a is None else [frame_acceleration(model, q, v, a, f, LOCAL, **_kw(backend)).vector
                                   for f in (fa, fb)]
    d = _alg.loop_row_derivatives(Ja, Jb, aXb, va, vb, None if accs is None else accs[0],
                                  None if accs is None else accs[1], (ka.dv_dq, ka.dv_dv), (kb.dv_dq, kb.dv_dv),
                                  (ka.da_dq, ka.da_dv), (kb.da_dq, kb.da_dv))
    rho = Ja - aXb @ Jb
    B = _map_of(model, q, fa, ref)
    r, dr_q, dr_v = d["r"]
    if a is None:  # impulses: the relative velocity along q
        u, du = r, [dr_q]
    else:
        kp, kd = c.baumgarte
        A, dA_q, dA_v = d["A"]
        xi = se3_log(aMb).vector
        u = A + kp * xi + kd * r
        du = [dA_q + kp * _alg.loop_error_derivative(xi, rho) + kd * dr_q, dA_v + kd * dr_v]
        if ref is not LOCAL:  # the reference's rate terms (algorithms/constraints.py: loop_rows)
            ex, dex = _rate_terms(ref, va, r, (ka.dv_dq, ka.dv_dv), (dr_q, dr_v))
            u, du = u + ex, [du[0] + dex[0], du[1] + dex[1]]
    dF = _alg.reference_rows(B, ref.value, u, du, Ja)
    J = rho if B is None else B @ rho
    f_a = _alg.frame_force(_lam6(lam, rows), B)
    f_b = -(np.swapaxes(aXb, -1, -2) @ f_a[..., None])[..., 0]  # −ᵇX*_a f_a, in b's coordinates
    forces = _on_body(model, fa, f_a) + _on_body(model, fb, f_b)
    corr = _alg.force_turn_correction(rho, Ja, f_a, ref.value, aXb @ Jb)
    return _Terms(J[..., rows, :], dF[0][..., rows, :], None if a is None else dF[1][..., rows, :], forces, corr)


def _rate_terms(ref: ReferenceFrame, va: np.ndarray, r: np.ndarray, dva: tuple[np.ndarray, np.ndarray],
                dr: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, list[np.ndarray]]:
    """A loop's γ terms from its reference turning with frame a, and their partials along q and q̇::

        WORLD: v_a × r,  ∂ = −(r ×) ∂v_a + (v_a ×) ∂r;     LWA: [ω_a × r_ω; ω_a × r_v], ∂ likewise
    """
    if ref.value == "world":
        Cr, Cv = _alg.crm_matrix(r), _alg.crm_matrix(va)
        ex = (Cv @ r[..., None])[..., 0]
        return ex, [-(Cr @ dva[i]) + Cv @ dr[i] for i in range(2)]
    w = va[..., :3]
    ex = np.concatenate([np.cross(w, r[..., :3]), np.cross(w, r[..., 3:])], axis=-1)
    W, Rw, Rv = skew_unchecked(w), skew_unchecked(r[..., :3]), skew_unchecked(r[..., 3:])
    out = []
    for i in range(2):
        dw = dva[i][..., :3, :]
        out.append(np.concatenate([-(Rw @ dw) + W @ dr[i][..., :3, :], -(Rv @ dw) + W @ dr[i][..., 3:, :]], axis=-2))
    return ex, out


def _terms(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray | None, items: list[Constraint],
           lam: np.ndarray, backend: str | None) -> tuple[list[_Terms], np.ndarray]:
    """Each constraint's terms, and the forces on the bodies `(..., nb, 6)` (the constraints' alone)."""
    parts = np.split(lam, np.cumsum([c.size for c in items])[:-1], axis=-1)
    terms = [_loop_terms(model, q, v, a, c, p, backend) if isinstance(c, LoopConstraint) else
             _contact_terms(model, q, v, a, c, p, backend) for c, p in zip(items, parts, strict=True)]
    f = np.zeros(q.shape[:-1] + (model.nbodies, 6), dtype=lam.dtype)
    for t in terms:
        for body, fb in t.forces:
            f[..., body, :] += fb
    return terms, f


def _stack(terms: list[_Terms], what: str) -> np.ndarray:
    return np.concatenate([getattr(t, what) for t in terms], axis=-2)


def _corrected(dtau_dq: np.ndarray, terms: list[_Terms]) -> np.ndarray:
    for t in terms:
        if t.correction is not None:
            dtau_dq = dtau_dq + t.correction
    return dtau_dq


def _core(kernel: Any, record: type, model: Model, args: tuple[Any, ...], opts: Any, backend: str | None) -> Any:
    """The record of the kernel's outputs for point and frame contacts: one state, or a stack of them (its batch on
    the thread pool), as the binding takes them (the binding makes the record); ``None`` where it declines
    (dependent contacts, other input: the general path)."""
    core = core_path(model, backend)
    if core is None:
        return None
    try:
        return kernel.fresh(core.cm, args, opts, record)
    except (TypeError, ValueError):  # arguments the binding does not take as they are
        return None


def constrained_dynamics_derivatives(model: Model, q: ArrayLike, v: ArrayLike, tau: ArrayLike,
                                     constraints: Sequence[Constraint] | Constraint, *, f_ext: ArrayLike | None = None,
                                     mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12,
                                     backend: str | None = None) -> ConstrainedDynamicsDerivatives:
    """The derivatives of :func:`constrained_dynamics` (the same constraints, Baumgarte gains, ``mu``)::

        [M  −Jᵀ] [∂q̈/∂x]      [∂F₁/∂x]       F₁ = ID(q, q̇, q̈) − Jᵀλ − τ,
        [J   0 ] [∂λ/∂x ] = − [∂F₂/∂x],      F₂ = J q̈ + γ + K_p e + K_d J q̇       (x ∈ {q, q̇, τ})

    q along fd.integrate's tangent; λ the stacked forces as ``constrained_dynamics(...).lagrange`` (each in
    its constraint's ``reference``, held there). With ``mu > 0`` D's pseudo-inverse: ∂q̈ exact, ∂λ the
    minimum-norm change when the constraints are dependent (Pinocchio's ``computeConstraintDynamicsDerivatives``
    for independent ones).

    Returns:
        :class:`ConstrainedDynamicsDerivatives`: ``ddq_dq``, ``ddq_dv``, ``ddq_dtau`` `(..., nv, nv)`,
        ``forces_dq``, ``forces_dv``, ``forces_dtau`` `(..., m, nv)`, and ``ddq``, ``lagrange``.

    Raises:
        ConstraintError: dependent constraints with ``mu = 0`` (as :func:`constrained_dynamics`).
    """
    found = cached_contact_plan(model, constraints, core_contact_plan)
    if found is not None and found[1] is not None:  # point and frame contacts: contact_derivatives.hpp
        try:
            opts = _solver(found[1], mu, max_iter, tol)
        except (TypeError, ValueError):
            opts = None
        r = None if opts is None else _core(_CONTACTS, ConstrainedDynamicsDerivatives, model, (q, v, tau, f_ext), opts,
                                            backend)
        if r is not None:
            return r
    if _dask.lazy(q, v, tau, f_ext):
        return _dask.call(constrained_dynamics_derivatives, model, {"q": q, "v": v, "tau": tau, "f_ext": f_ext},
                          constraints=constraints, mu=mu, max_iter=max_iter, tol=tol, backend=backend)
    sol = constrained_dynamics(model, q, v, tau, constraints, f_ext=f_ext, mu=mu, max_iter=max_iter, tol=tol,
                               backend=backend)
    items = _con.as_constraints(constraints)
    st = check_state(model, q, v=v, tau=tau)
    q_, v_ = st.q, st.arrays["v"]
    terms, f = _terms(model, q_, v_, sol.ddq, items, sol.lagrange, backend)
    if f_ext is not None:
        f = f + np.asarray(f_ext, dtype=f.dtype)
    dtau_dq, dtau_dv, _ = rnea_derivatives(model, q_, v_, sol.ddq, f, **_kw(backend))
    nv = model.nv
    eye = np.broadcast_to(np.eye(nv, dtype=dtau_dq.dtype), dtau_dq.shape)
    (xq, yq), (xv, yv), (xt, yt) = _alg.kkt_derivatives(
        mass_matrix_inverse(model, q_, **_kw(backend)), _stack(terms, "J"),
        [_corrected(dtau_dq, terms), dtau_dv, -eye], [_stack(terms, "dq"), _stack(terms, "dv"), None],
        pseudo_inverse=float(mu) > 0.0)
    return ConstrainedDynamicsDerivatives(xq, xv, xt, yq, yv, yt, sol.ddq, sol.lagrange)


def impulse_dynamics_derivatives(model: Model, q: ArrayLike, v: ArrayLike,
                                 constraints: Sequence[Constraint] | Constraint, *, restitution: float = 0.0,
                                 mu: float = 0.0, backend: str | None = None) -> ImpulseDynamicsDerivatives:
    """The derivatives of :func:`impulse_dynamics` (the velocity ``v⁺`` and impulses Λ after an impact)::

        F₁ = M(q) (v⁺ − v⁻) − Jᵀ Λ = 0,     F₂ = J (v⁺ + e v⁻) = 0
        [M  −Jᵀ] [∂v⁺/∂x]      [∂F₁/∂x]
        [J   0 ] [∂Λ/∂x ] = − [∂F₂/∂x]       (x ∈ {q, v⁻};  ∂F₁/∂v⁻ = −M,  ∂F₂/∂v⁻ = e J)

    Returns:
        :class:`ImpulseDynamicsDerivatives`: ``dv_plus_dq``, ``dv_plus_dv`` `(..., nv, nv)`, ``impulses_dq``,
        ``impulses_dv`` `(..., m, nv)`, and ``v_plus``, ``lagrange``.

    Raises:
        ConstraintError: dependent constraints with ``mu = 0``; ModelError: restitution outside [0, 1].
    """
    found = cached_contact_plan(model, constraints, core_contact_plan)
    if found is not None and found[1] is not None and isinstance(restitution, (int, float)) \
            and 0.0 <= restitution <= 1.0:  # point and frame contacts: contact_derivatives.hpp
        opts = _impact(found[1], float(restitution))
        r = _core(_IMPULSES, ImpulseDynamicsDerivatives, model, (q, v), opts, backend)
        if r is not None:
            return r
    if _dask.lazy(q, v):
        return _dask.call(impulse_dynamics_derivatives, model, {"q": q, "v": v}, constraints=constraints,
                          restitution=restitution, mu=mu, backend=backend)
    sol = impulse_dynamics(model, q, v, constraints, restitution=restitution, mu=mu, backend=backend)
    items = _con.as_constraints(constraints)
    st = check_state(model, q, v=v)
    q_, vm = st.q, st.arrays["v"]
    e = float(restitution)
    terms, f = _terms(model, q_, sol.v_plus + e * vm, None, items, sol.lagrange, backend)
    dq = rnea_derivatives(model, q_, np.zeros_like(vm), sol.v_plus - vm, f, gravity=False, **_kw(backend))[0]
    M = crba(model, q_, **_kw(backend))
    J = _stack(terms, "J")
    (xq, yq), (xv, yv) = _alg.kkt_derivatives(mass_matrix_inverse(model, q_, **_kw(backend)), J,
                                              [_corrected(dq, terms), -M], [_stack(terms, "dq"), e * J],
                                              pseudo_inverse=float(mu) > 0.0)
    return ImpulseDynamicsDerivatives(xq, xv, yq, yv, sol.v_plus, sol.lagrange)
