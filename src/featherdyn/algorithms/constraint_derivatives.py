"""Derivatives of constrained dynamics and of impulses (reference; docs/derivatives.md, "Constrained dynamics").

The constrained dynamics (``algorithms/constraints.py``) is the root of::

    F₁ = ID(q, q̇, q̈) − Jᵀ λ − τ = 0,       F₂ = J q̈ + γ + K_p e + K_d J q̇ = 0

in ``(q̈, λ)``. Differentiating along x ∈ {q (fd.integrate's tangent), q̇, τ} with ``R₁ = ∂F₁/∂x``,
``R₂ = ∂F₂/∂x`` (q̈ and λ held)::

    [M  −Jᵀ] [∂q̈/∂x]      [R₁]          ∂λ/∂x = D⁻¹ (J M⁻¹ R₁ − R₂),    D = J M⁻¹ Jᵀ
    [J   0 ] [∂λ/∂x ] = − [R₂]    ⇒     ∂q̈/∂x = M⁻¹ (Jᵀ ∂λ/∂x − R₁)                (:func:`kkt_derivatives`)

* ``R₁`` along q: the forces Jᵀλ act on the bodies as external forces ``f_b`` (in each body's frame), so
  ``ID − Jᵀ λ = RNEA(q, q̇, q̈, f_ext + f_b)`` and RNEA's derivative with ``f_b`` held in the bodies gives all
  of it but the turn of λ's own axes: a constraint's force is held in its ``reference``, not in the body. With
  ``f_a = Bᵀ λ₆`` the force in the frame's coordinates (``B`` = 1 in LOCAL, ``blkdiag(⁰R_a, ⁰R_a)`` in
  LOCAL_WORLD_ALIGNED, ``⁰X_a`` in WORLD; λ₆ the force on the constrained axes, zero elsewhere) and ``ᶠJ_k``
  the frame's LOCAL Jacobian column k, ``∂f_a/∂q_k = G(f_a) ᶠJ_k`` (:func:`force_turn`)::

      LOCAL: G = 0,    LWA: G = [[n]×, 0; [f]×, 0],    WORLD: G = [[n]×, [f]×; [f]×, 0]   (= −(· ×* f_a))

  and a loop's force on b, ``−ᵇX*_a f_a``, turns with ``ᵃX_b`` too (``∂ᵃX_b/∂q_k = −(ρ_k ×) ᵃX_b``, ρ the
  loop's LOCAL rows ``ᵃJ − ᵃX_b ᵇJ``). The correction added to RNEA's ``∂τ/∂q`` (:func:`force_turn_correction`)::

      − ρᵀ G_ref(f_a) ᵃJ − (ᵃX_b ᵇJ)ᵀ G_WORLD(f_a) ρ          (contacts: ρ = ᵃJ, no second term)

* ``R₂``: ``J q̈ + γ`` is the frame's acceleration (classical for a point contact) at ``q̈`` in ``reference``
  and ``J q̇`` its velocity (``fd.kinematics_derivatives``); a loop's are composed from the two frames' LOCAL
  ones (:func:`loop_row_derivatives`).

**Impulses** (``M (v⁺ − v⁻) = Jᵀ Λ``, ``J v⁺ = −e J v⁻``): ``F₁ = M(q)(v⁺ − v⁻) − JᵀΛ``, ``F₂ = J (v⁺ + e v⁻)``;
the same solve with ``R₁`` along q from RNEA at zero velocity without gravity (``M w − Jᵀ Λ``, w = v⁺ − v⁻),
``R₁ = −M``, ``R₂ = e J`` along v⁻.

With ``mu > 0`` (dependent rows allowed) ``D⁻¹`` is ``D``'s pseudo-inverse: ``∂q̈`` is then exact (J's range
is what Jᵀ ∂λ sees) and ``∂λ`` the minimum-norm change. Everything batches over leading axes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..spatial.lie import se3_right_jacobian_inverse
from ..spatial.ops import cross3, skew_unchecked

__all__ = ["crm_matrix", "force_turn", "frame_force", "body_force", "force_turn_correction", "loop_row_derivatives",
           "loop_error_derivative", "reference_rows", "kkt_derivatives"]


def _T(a: np.ndarray) -> np.ndarray:
    return np.swapaxes(a, -1, -2)


def _mv(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    return (m @ x[..., None])[..., 0]


def crm_matrix(v: np.ndarray) -> np.ndarray:
    """``(v ×)`` `(..., 6, 6)` of motions ``v = [ω; u]``: ``[[ω]×, 0; [u]×, [ω]×]``."""
    w, u = skew_unchecked(v[..., :3]), skew_unchecked(v[..., 3:])
    z = np.zeros_like(w)
    return np.concatenate([np.concatenate([w, z], -1), np.concatenate([u, w], -1)], -2)


def force_turn(f: np.ndarray, reference: str) -> np.ndarray:
    """``G`` `(..., 6, 6)` with ``∂f/∂q_k = G ᶠJ_k`` for a force ``f = [n; f]`` `(..., 6)` in a frame's
    coordinates held fixed in ``reference`` ('local', 'local_world_aligned', 'world'; module docstring)."""
    n, fl = skew_unchecked(f[..., :3]), skew_unchecked(f[..., 3:])
    z = np.zeros_like(n)
    if reference == "local":
        return np.zeros(f.shape[:-1] + (6, 6), dtype=f.dtype)
    top = np.concatenate([n, fl if reference == "world" else z], -1)
    return np.concatenate([top, np.concatenate([fl, z], -1)], -2)


def frame_force(lam6: np.ndarray, B: np.ndarray | None) -> np.ndarray:
    """``f_a = Bᵀ λ₆`` `(..., 6)`: a constraint's force λ₆ `(..., 6)` in its reference, in the frame's coordinates
    (``B`` `(..., 6, 6)` the reference's map of the frame's motions, ``None`` for LOCAL)."""
    return lam6 if B is None else _mv(_T(B), lam6)


def body_force(f_frame: np.ndarray, R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The spatial force `(..., 6)` in a body's coordinates of ``f_frame`` `(..., 6)` at a frame placed ``(R, p)``
    in the body: ``[R n + p × R f; R f]``."""
    n, f = _mv(R, f_frame[..., :3]), _mv(R, f_frame[..., 3:])
    return np.concatenate([n + cross3(p, f), f], axis=-1)


def force_turn_correction(rho: np.ndarray, Ja: np.ndarray, f_a: np.ndarray, reference: str,
                          XJb: np.ndarray | None = None) -> np.ndarray:
    """The term `(..., nv, nv)` added to RNEA's ``∂τ/∂q`` (forces held in the bodies) for a constraint's force
    held in its ``reference``: ``− ρᵀ G_ref(f_a) ᵃJ − (ᵃX_b ᵇJ)ᵀ G_WORLD(f_a) ρ`` (module docstring; ρ, ᵃJ,
    ``ᵃX_b ᵇJ`` `(..., 6, nv)`, the last ``None`` for a contact)."""
    out = -(_T(rho) @ force_turn(f_a, reference) @ Ja)
    if XJb is not None:
        out = out - _T(XJb) @ force_turn(f_a, "world") @ rho
    return out


def loop_row_derivatives(Ja: np.ndarray, Jb: np.ndarray, aXb: np.ndarray, va: np.ndarray, vb: np.ndarray,
                         aa: np.ndarray | None, ab: np.ndarray | None, dva: tuple[np.ndarray, np.ndarray],
                         dvb: tuple[np.ndarray, np.ndarray], daa: tuple[np.ndarray, np.ndarray] | None,
                         dab: tuple[np.ndarray, np.ndarray] | None
                         ) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """A loop's relative velocity ``r = v_a − ᵃX_b v_b`` and acceleration ``A = a_a − ᵃX_b a_b + r × ᵃX_b v_b``
    (a's LOCAL coordinates; ``J q̇`` and ``J q̈ + γ`` before the reference) with their derivatives along q and q̇,
    as ``{"r": (r, ∂r/∂q, ∂r/∂q̇), "A": (...)}`` (`(..., 6)`, `(..., 6, nv)`), from the frames' LOCAL Jacobians
    ``Ja``, ``Jb``, ``ᵃX_b`` `(..., 6, 6)`, velocities, accelerations (``None``: velocity only) and their
    derivatives ``(∂/∂q, ∂/∂q̇)``::

        ∂ᵃX_b/∂q_k = −(ρ_k ×) ᵃX_b,   ρ = Ja − ᵃX_b Jb
        ∂(ᵃX_b y)/∂q = ᵃX_b ∂y/∂q + (ᵃX_b y ×) ρ        (y a motion of b)
    """
    rho = Ja - aXb @ Jb
    Vb = _mv(aXb, vb)
    dVb_q = aXb @ dvb[0] + crm_matrix(Vb) @ rho
    dVb_v = aXb @ dvb[1]
    r = va - Vb
    out = {"r": (r, dva[0] - dVb_q, dva[1] - dVb_v)}
    if aa is None or ab is None or daa is None or dab is None:
        return out
    Ab = _mv(aXb, ab)
    dAb_q = aXb @ dab[0] + crm_matrix(Ab) @ rho
    dAb_v = aXb @ dab[1]
    A = aa - Ab + _mv(crm_matrix(r), Vb)
    # ∂(r × Vb) = ∂r × Vb + r × ∂Vb = −(Vb ×) ∂r + (r ×) ∂Vb
    _, dr_q, dr_v = out["r"]
    dA_q = daa[0] - dAb_q - crm_matrix(Vb) @ dr_q + crm_matrix(r) @ dVb_q
    dA_v = daa[1] - dAb_v - crm_matrix(Vb) @ dr_v + crm_matrix(r) @ dVb_v
    out["A"] = (A, dA_q, dA_v)
    return out


def loop_error_derivative(xi: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """``∂e/∂q`` `(..., 6, nv)` of ``e = log(ᵃM_b)`` (ξ `(..., 6)` ``[ω; v]``): ᵃM_b moves as ``exp(−ε ρ_k) ᵃM_b``,
    so ``∂e/∂q = −Jl(ξ)⁻¹ ρ`` with ``Jl(ξ) = Jr(−ξ)``."""
    return -(se3_right_jacobian_inverse(-xi) @ rho)


def reference_rows(B: np.ndarray | None, reference: str, u: np.ndarray, du: Sequence[np.ndarray], Ja: np.ndarray
                   ) -> list[np.ndarray]:
    """``∂(B u)/∂x`` `(..., 6, nv)` for a loop's LOCAL quantity ``u`` `(..., 6)` with partials ``du``: ``B`` turns
    with frame a along q (``∂B/∂q_k = B (ᵃJ_k ×)`` in WORLD, the rotation part only in LWA)::

        ∂(B u)/∂q = B (∂u/∂q − T(u) ᵃJ),   T(u) = (u ×) (WORLD),  [[u_ω]×, 0; [u_v]×, 0] (LWA);   ∂(B u)/∂q̇ = B ∂u/∂q̇
    """
    if B is None:
        return list(du)
    T = crm_matrix(u)
    if reference != "world":
        T = T.copy()
        T[..., :, 3:] = 0.0
    return [B @ (du[0] - T @ Ja)] + [B @ d for d in du[1:]]


def kkt_derivatives(Minv: np.ndarray, J: np.ndarray, R1: Sequence[np.ndarray], R2: Sequence[np.ndarray | None],
                    pseudo_inverse: bool = False) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(∂q̈/∂x, ∂λ/∂x)`` `(..., nv, n)`, `(..., m, n)` of each pair ``(R₁, R₂)`` `(..., nv, n)`, `(..., m, n)`
    (``None``: zero) from ``M⁻¹`` `(..., nv, nv)` and ``J`` `(..., m, nv)`::

        ∂λ = D⁻¹ (J M⁻¹ R₁ − R₂),   ∂q̈ = M⁻¹ (Jᵀ ∂λ − R₁),   D = J M⁻¹ Jᵀ   (D⁺ when ``pseudo_inverse``)
    """
    JM = J @ Minv
    D = JM @ _T(J)
    Dinv = np.linalg.pinv(D, hermitian=True) if pseudo_inverse else np.linalg.inv(D)
    out = []
    for r1, r2 in zip(R1, R2, strict=True):
        rhs = JM @ r1 if r2 is None else JM @ r1 - r2
        dlam = Dinv @ rhs
        out.append((Minv @ (_T(J) @ dlam - r1), dlam))
    return out
