"""Second-order derivatives of inverse and forward dynamics (reference).

The second derivatives of ``τ = RNEA(q, q̇, q̈)`` are the derivatives of its analytical first order
(:mod:`.derivatives`: ``∂τ/∂q`` along ``q ⊕ δ e_j``, ``∂τ/∂q̇``, ``M``) along ``q ⊕ ε e_k`` and ``q̇ + ε e_k``::

    d2tau_dq2[i, j, k]  = d/dε (∂τ_i/∂q_j)(q ⊕ ε e_k, q̇, q̈)
    d2tau_dv2[i, j, k]  = d/dε (∂τ_i/∂q̇_j)(q, q̇ + ε e_k, q̈)          (symmetric in j, k)
    d2tau_dqdv[i, j, k] = d/dε (∂τ_i/∂q_j)(q, q̇ + ε e_k, q̈)  = ∂²τ_i/∂q_j∂q̇_k
    dM_dq[i, j, k]      = d/dε M_ij(q ⊕ ε e_k)                        (= ∂²τ_i/∂q_k∂q̈_j;  ∂²τ/∂q̈² = 0)

taken exactly by forward-mode differentiation: the first-order algorithm runs on :class:`Dual` numbers
(a value and its derivatives along the 2 nv directions), seeded where the state enters it. ``q̇``'s
seeds are ``e_k``; ``q`` enters only through the joints' poses in their parents, and along ``q ⊕ ε e_c`` (c
a column of joint i, ``fd.integrate``'s tangent) the pose moves as ``ᵖM_i exp(ε Ŝ_c)``::

    d/dε ᵖR_i = ᵖR_i [ω_c]×,    d/dε ᵖp_i = ᵖR_i u_c           (S_c = [ω_c; u_c] in body i)

so no trigonometry is differentiated and the values keep their dtype: float64, or SymPy objects (small
cases checked symbolically). The core (``core/cpp/rnea_second_order.hpp``) runs Singh, Russell & Wensing's
analytical second-order recursion instead: two independent routes to the same numbers.

On a free-flyer, spherical or planar joint the tangent fields ``X_j`` (``q ↦ d/dδ q ⊕ δ e_j``) do not
commute, and ``d2tau_dq2[i, j, k] − d2tau_dq2[i, k, j] = ([X_k, X_j] τ)_i``: the first order along the fields'
bracket, ``[X_k, X_j] = Σ_c (S_cᵀ (S_k × S_j)) X_c`` for two columns of one joint (e.g. a free-flyer's
``[X_ω_k, X_ω_j] = X_ω_(e_k × e_j)``, ``[X_ω_k, X_v_j] = X_v_(e_k × e_j)``), zero otherwise. It is symmetric on
revolute and prismatic joints (docs/derivatives.md).

Forward dynamics: ``q̈ = FD(q, q̇, τ)`` solves ``RNEA(q, q̇, FD) = τ``; differentiating
``(X_j τ)(q, q̇, q̈) + M X_j q̈ = 0`` once more (the ``q̈``-derivative of ``X_j τ`` is ``X_j M``)::

    d2ddq_dq2[:, j, k]    = −M⁻¹ (d2tau_dq2[:, j, k] + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j)
    d2ddq_dv2[:, j, k]    = −M⁻¹ d2tau_dv2[:, j, k]
    d2ddq_dqdv[:, j, k]   = −M⁻¹ (d2tau_dqdv[:, j, k] + ∂M/∂q_j ∂q̈/∂q̇_k)
    d2ddq_dqdtau[:, j, k] = −(M⁻¹ ∂M/∂q_j M⁻¹)[:, k]

with RNEA's terms at ``q̈ = FD(q, q̇, τ)`` and ``∂M/∂q_j = dM_dq[:, :, j]``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..model import Model
from ..spatial import PluckerTransform
from ..spatial.ops import skew_unchecked
from . import aba as _aba
from . import derivatives as _first
from ._common import TreeData, batch_dtype
from .crba import mass_matrix_on

__all__ = ["Dual", "rnea_second_derivatives", "aba_second_derivatives"]


class Dual:
    """A value ``v`` and its derivatives ``d`` `(K,)` along K directions (``ε_k ε_l = 0``), for NumPy's object
    arrays: ``(v + ε·d)(w + ε·e) = v w + ε·(d w + v e)``. ``v`` and ``d`` hold any scalar type (float, SymPy)."""

    __slots__ = ("d", "v")
    __array_ufunc__ = None  # NumPy scalars defer to the reflected operators below

    def __init__(self, v: Any, d: np.ndarray) -> None:
        self.v = v
        self.d = d

    def __add__(self, o: Any) -> Dual:
        return Dual(self.v + o.v, self.d + o.d) if isinstance(o, Dual) else Dual(self.v + o, self.d)

    __radd__ = __add__

    def __sub__(self, o: Any) -> Dual:
        return Dual(self.v - o.v, self.d - o.d) if isinstance(o, Dual) else Dual(self.v - o, self.d)

    def __rsub__(self, o: Any) -> Dual:
        return Dual(o - self.v, -self.d)

    def __neg__(self) -> Dual:
        return Dual(-self.v, -self.d)

    def __pos__(self) -> Dual:
        return self

    def __mul__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            return Dual(self.v * o.v, self.d * o.v + o.d * self.v)
        return Dual(self.v * o, self.d * o)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            r = self.v / o.v
            return Dual(r, (self.d - o.d * r) / o.v)
        return Dual(self.v / o, self.d / o)

    def __rtruediv__(self, o: Any) -> Dual:
        r = o / self.v
        return Dual(r, self.d * (-r / self.v))

    def __repr__(self) -> str:
        return f"Dual({self.v!r}, {self.d!r})"


def _duals(values: np.ndarray, derivatives: np.ndarray) -> np.ndarray:
    """The object array of ``Dual(values[x], derivatives[x])`` (``derivatives``: one more trailing axis, K)."""
    out = np.empty(values.shape, dtype=object)
    for x in np.ndindex(values.shape):
        out[x] = Dual(values[x], derivatives[x])
    return out


def _derivatives(a: np.ndarray, k: int, dtype: np.dtype) -> np.ndarray:
    """The derivatives of the entries of ``a`` (object: Dual, or a constant) as an array with a trailing axis K."""
    out = np.zeros(a.shape + (k,), dtype=dtype) if dtype.kind != "O" else np.full(a.shape + (k,), 0, dtype=object)
    for x in np.ndindex(a.shape):
        if isinstance(a[x], Dual):
            out[x] = a[x].d
    return out


class _SeededTree(TreeData):
    """The tree data on object arrays whose joint poses carry their derivatives along ``q ⊕ ε e_k``: direction k of
    the ``2 nv`` (the first nv; the others are ``q̇``'s)."""

    def __init__(self, model: Model, base: np.dtype) -> None:
        super().__init__(model, np.dtype(object))
        self.base = base
        self.ndir = 2 * model.nv

    def pose_in_parent(self, q: np.ndarray, i: int) -> PluckerTransform:
        P = super().pose_in_parent(q, i)
        R, p = P.rotation, P.translation
        m = self.model
        dR = np.zeros(R.shape + (self.ndir,), dtype=object)
        dp = np.zeros(p.shape + (self.ndir,), dtype=object)
        for c in range(m.nvs[i]):  # d/dε ᵖM_i exp(ε Ŝ_c) = ᵖM_i Ŝ_c:  R [ω_c]×,  R u_c
            k = m.idx_v[i] + c
            w, u = self.S[i][:3, c], self.S[i][3:, c]
            dR[..., k] = R @ skew_unchecked(w)
            dp[..., k] = np.einsum("...ab,b->...a", R, u)
        if self.base.kind != "O":
            dR, dp = dR.astype(self.base), dp.astype(self.base)
        return PluckerTransform._wrap(_duals(R, dR), _duals(p, dp), None, None)


def rnea_second_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                            f_ext: np.ndarray | None = None,
                            gravity: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(d2tau_dq2, d2tau_dv2, d2tau_dqdv, dM_dq)``, each `(..., nv, nv, nv)`, of ``τ = RNEA(q, q̇, q̈)`` on
    checked arrays: the first-order algorithm on :class:`Dual` numbers (module docstring)::

        d2tau_dq2[i, j, k] = ∂(∂τ_i/∂q_j)/∂q_k,  d2tau_dv2[i, j, k] = ∂²τ_i/∂q̇_j∂q̇_k,
        d2tau_dqdv[i, j, k] = ∂²τ_i/∂q_j∂q̇_k,     dM_dq[i, j, k] = ∂M_ij/∂q_k      (q along q ⊕ ε e_k)
    """
    batch, dtype = batch_dtype(q, qd, qdd, f_ext=f_ext)
    nv = model.nv
    td = _SeededTree(model, dtype)
    K = td.ndir
    seeds = np.zeros(batch + (nv, K), dtype=dtype) if dtype.kind != "O" else np.full(batch + (nv, K), 0, dtype=object)
    for k in range(nv):
        seeds[..., k, nv + k] = 1
    V = _duals(np.broadcast_to(qd, batch + (nv,)).astype(object), seeds)
    A = np.broadcast_to(qdd, batch + (nv,)).astype(object)
    F = None if f_ext is None else f_ext.astype(object)
    qq = np.broadcast_to(q, batch + (model.nq,))
    dq, dv = _first.partials_on(td, batch, qq, V, A, F, gravity)
    M = mass_matrix_on(td, batch, qq)
    Dq, Dv, DM = (_derivatives(x, K, dtype) for x in (dq, dv, M))
    return Dq[..., :nv], Dv[..., nv:], Dq[..., nv:], DM[..., :nv]


def aba_second_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray,
                           f_ext: np.ndarray | None = None,
                           gravity: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(d2ddq_dq2, d2ddq_dv2, d2ddq_dqdv, d2ddq_dqdtau)``, each `(..., nv, nv, nv)`, of ``q̈ = ABA(q, q̇, τ)``
    on checked arrays, from RNEA's second derivatives at ``q̈`` (module docstring)::

        d2ddq_dq2[:, j, k] = −M⁻¹ (∂²τ/∂q_j∂q_k + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j),
        d2ddq_dv2 = −M⁻¹ ∂²τ/∂q̇²,  d2ddq_dqdv[:, j, k] = −M⁻¹ (∂²τ/∂q_j∂q̇_k + ∂M/∂q_j ∂q̈/∂q̇_k),
        d2ddq_dqdtau[:, j, k] = −(M⁻¹ ∂M/∂q_j M⁻¹)[:, k]
    """
    qdd = _aba.aba(model, q, qd, tau, f_ext, gravity)
    Fq, Fv, Minv = _first.aba_derivatives(model, q, qd, tau, f_ext, gravity)
    t2q, t2v, tqv, dM = rnea_second_derivatives(model, q, qd, qdd, f_ext, gravity)

    def minus_minv(x: np.ndarray) -> np.ndarray:
        return -np.einsum("...ir,...rjk->...ijk", Minv, x)

    P = np.einsum("...rsj,...sk->...rjk", dM, Fq)  # (∂M/∂q_j ∂q̈/∂q_k)_r
    d2q = minus_minv(t2q + P + np.swapaxes(P, -1, -2))
    d2v = minus_minv(t2v)
    dqdv = minus_minv(tqv + np.einsum("...rsj,...sk->...rjk", dM, Fv))
    dqdtau = minus_minv(np.einsum("...rsj,...sk->...rjk", dM, Minv))
    return d2q, d2v, dqdv, dqdtau
