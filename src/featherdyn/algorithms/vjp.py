"""Vector–Jacobian products of inverse and forward dynamics: the gradients of ``wᵀ τ(q, q̇, q̈)``,
``wᵀ q̈(q, q̇, τ)`` and ``⟨W, M(q)⟩`` (public: :func:`featherdyn.rnea_vjp`, :func:`featherdyn.aba_vjp`,
:func:`featherdyn.crba_vjp`).

The reference takes the other road from the compiled kernel (``core/cpp/vjp.hpp``, an O(nb) recursion): it forms
the Jacobians of :mod:`.derivatives` and contracts them with ``w``, so each checks the other::

    ∂(wᵀτ)/∂x = wᵀ ∂τ/∂x,     ∂(wᵀq̈)/∂x = wᵀ ∂q̈/∂x      (∂/∂q along ``fd.integrate``'s tangent)
"""

from __future__ import annotations

import numpy as np

from ..model import Model
from .derivatives import aba_derivatives, rnea_derivatives
from .second_order import rnea_second_derivatives

__all__ = ["rnea_vjp", "aba_vjp", "crba_vjp"]


def _rows(w: np.ndarray, jacobians: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    return tuple(np.einsum("...i,...ij->...j", w, J) for J in jacobians)


def rnea_vjp(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, w: np.ndarray,
             f_ext: np.ndarray | None = None, gravity: bool = True) -> tuple[np.ndarray, ...]:
    """``(wᵀ ∂τ/∂q, wᵀ ∂τ/∂q̇, wᵀ M)`` `(..., nv)` each, ``τ = RNEA(q, q̇, q̈, f_ext)``, on checked arrays."""
    return _rows(w, rnea_derivatives(model, q, qd, qdd, f_ext, gravity))


def aba_vjp(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, w: np.ndarray,
            f_ext: np.ndarray | None = None, gravity: bool = True) -> tuple[np.ndarray, ...]:
    """``(wᵀ ∂q̈/∂q, wᵀ ∂q̈/∂q̇, wᵀ M⁻¹)`` `(..., nv)` each, ``q̈ = ABA(q, q̇, τ, f_ext)``, on checked arrays."""
    return _rows(w, aba_derivatives(model, q, qd, tau, f_ext, gravity))


def crba_vjp(model: Model, q: np.ndarray, W: np.ndarray) -> np.ndarray:
    """``∂⟨W, M(q)⟩/∂q = Σ_ij W_ij ∂M_ij/∂q`` `(..., nv)`, on checked arrays: ``W`` contracted with ``∂M/∂q`` of
    :func:`.second_order.rnea_second_derivatives` (the kernel: one pass per column over its subtree)."""
    zero = np.zeros(q.shape[:-1] + (model.nv,), dtype=np.result_type(q, W))
    dM_dq = rnea_second_derivatives(model, q, zero, zero, None, False)[3]
    return np.einsum("...ij,...ijk->...k", W, dM_dq)
