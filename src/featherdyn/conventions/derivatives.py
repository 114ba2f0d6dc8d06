"""Derivative matrices between featherdyn's tangent and the layouts other tools use.

featherdyn differentiates with respect to ``q`` along the tangent of
``fd.integrate`` — ``q ⊕ δ`` with δ in ``v``'s layout: a free-flyer's
``[ω; v]`` and a spherical joint's ω in the joint's own (child) frame
(``fd.rnea_derivatives`` & co.). The converters here take a derivative
matrix ``D`` whose last axis runs over that tangent (`(..., k, nv)`), and:

* :func:`derivatives_to_pinocchio` / :func:`derivatives_from_pinocchio`:
  Pinocchio's layout — the same tangent, each free-flyer's two 3-blocks in
  the order ``[v; ω]``; ``rows`` says what the rows are (``"generalized"``:
  joint forces or accelerations, ``nv`` rows, swapped like the columns;
  ``"spatial"``: a 6D motion ``[ω; v]`` → ``[v; ω]``; ``"other"``: untouched);
* :func:`derivatives_to_parent_tangent`: the tangent expressed in each
  joint's parent frame (the world for a root free-flyer):
  ``q ⊕ δ_p`` multiplies on the left, ``T' = exp(δ_p) T``, and
  ``δ = Ad(T)⁻¹ δ_p`` (``Rᵀ δ_p`` for a spherical joint), so
  ``D_p = D · Ad(T)⁻¹`` block by block;
* :func:`derivatives_to_coordinates` / :func:`derivatives_from_coordinates`:
  plain configuration coordinates (the quaternion's four numbers, as autodiff
  tools and finite differences on ``q`` see them), `(..., k, nq)`, by the
  chain rule through the exponential map: ``dq = Q(q) δ`` with
  ``Q = d(q ⊕ δ)/dδ`` at δ = 0 (``quat ⊗ (δω/2, 0)``, ``R δv``), and back
  with its pseudo-inverse (exact on the unit-quaternion tangent).

Joints are told apart by their sizes (``nq, nv``): ``(7, 6)`` free-flyer,
``(4, 3)`` spherical, ``(3, 3)`` planar, ``(1, 1)`` revolute or prismatic;
joint order is featherdyn's (Pinocchio's matches for the same URDF; see
``featherdyn.verify.bridge.JointMap`` otherwise).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ShapeError
from ..rotation import quat_to_matrix

__all__ = ["derivatives_to_pinocchio", "derivatives_from_pinocchio", "derivatives_to_parent_tangent",
           "derivatives_to_coordinates", "derivatives_from_coordinates"]

_ROWS = ("generalized", "spatial", "other")


def _joints(model: Any) -> list[tuple[int, int, int, int]]:
    """``(idx_q, nq, idx_v, nv)`` per joint."""
    return [(int(model.idx_q[i]), int(model.nqs[i]), int(model.idx_v[i]), int(model.nvs[i]))
            for i in range(model.nbodies)]


def _matrix(D: ArrayLike, model: Any, cols: int, name: str = "D") -> np.ndarray:
    arr = np.array(D, dtype=np.float64)
    if arr.ndim < 2 or arr.shape[-1] != cols:
        raise ShapeError(f"{name}: expected shape (..., k, {cols}) for model {model.name!r}, got {arr.shape}")
    return arr


def _swap_permutation(model: Any) -> np.ndarray:
    """The index permutation of v that swaps each free-flyer's [ω; v] into [v; ω] (an involution)."""
    perm = np.arange(model.nv)
    for _, nq, iv, nv in _joints(model):
        if (nq, nv) == (7, 6):
            perm[iv: iv + 6] = np.r_[iv + 3: iv + 6, iv: iv + 3]
    return perm


def derivatives_to_pinocchio(model: Any, D: ArrayLike, rows: str = "generalized") -> np.ndarray:
    """``D`` `(..., k, nv)` in Pinocchio's layout (free-flyer tangent ``[v; ω]``); ``rows`` as the module says::

        D_pin = P_rows D Pᵀ,   P: each free-flyer's [ω; v] → [v; ω]   (rows: the same P, the 6D swap, or none)

    Source: Pinocchio's ``computeRNEADerivatives`` / ``getFrameVelocityDerivatives`` layouts (its motion
    vectors are linear-first).
    """
    if rows not in _ROWS:
        raise ShapeError(f"rows: expected one of {_ROWS}, got {rows!r}")
    out = _matrix(D, model, model.nv)
    perm = _swap_permutation(model)
    out = out[..., perm]
    if rows == "generalized":
        if out.shape[-2] != model.nv:
            raise ShapeError(f"D: rows='generalized' needs {model.nv} rows, got {out.shape[-2]}")
        out = out[..., perm, :]
    elif rows == "spatial":
        if out.shape[-2] != 6:
            raise ShapeError(f"D: rows='spatial' needs 6 rows ([ω; v]), got {out.shape[-2]}")
        out = out[..., [3, 4, 5, 0, 1, 2], :]
    return out


def derivatives_from_pinocchio(model: Any, D: ArrayLike, rows: str = "generalized") -> np.ndarray:
    """The inverse of :func:`derivatives_to_pinocchio`, `(..., k, nv)` (each swap is its own inverse)::

        D = P_rowsᵀ D_pin P

    Source: as :func:`derivatives_to_pinocchio`.
    """
    return derivatives_to_pinocchio(model, D, rows)


def _se3_inverse_adjoint(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """``Ad(T)⁻¹`` `(..., 6, 6)` on ``[ω; v]`` motions for ``T = (R, p)``: ``[[Rᵀ, 0], [−Rᵀ [p]×, Rᵀ]]``."""
    Rt = np.swapaxes(R, -1, -2)
    z = np.zeros(p.shape[:-1])
    P = np.stack([np.stack([z, -p[..., 2], p[..., 1]], -1), np.stack([p[..., 2], z, -p[..., 0]], -1),
                  np.stack([-p[..., 1], p[..., 0], z], -1)], -2)
    out = np.zeros(R.shape[:-2] + (6, 6))
    out[..., :3, :3] = Rt
    out[..., 3:, 3:] = Rt
    out[..., 3:, :3] = -Rt @ P
    return out


def derivatives_to_parent_tangent(model: Any, q: ArrayLike, D: ArrayLike) -> np.ndarray:
    """``D`` `(..., k, nv)` with its tangent expressed in each joint's parent frame (module docstring)::

        D_p = D · blkdiag(Ad(T_i)⁻¹)    (free-flyer),   Rᵀ (spherical),   1 (other joints)

    Source: the adjoint relation of left and right perturbations, exp(δ_p) T = T exp(Ad(T)⁻¹ δ_p)
    (Solà, Deray & Atchuthan, "A micro Lie theory", 2018, §II-F).
    """
    qq = np.asarray(q, dtype=np.float64)
    out = _matrix(D, model, model.nv).copy()
    for iq, nq, iv, nv in _joints(model):
        if (nq, nv) == (7, 6):
            B = _se3_inverse_adjoint(quat_to_matrix(qq[..., iq + 3: iq + 7]), qq[..., iq: iq + 3])
        elif (nq, nv) == (4, 3):
            B = np.swapaxes(quat_to_matrix(qq[..., iq: iq + 4]), -1, -2)
        else:
            continue
        out[..., iv: iv + nv] = out[..., iv: iv + nv] @ B
    return out


def _tangent_to_coordinates(model: Any, q: np.ndarray) -> np.ndarray:
    """``Q(q)`` `(..., nq, nv)`: ``d(q ⊕ δ)/dδ`` at δ = 0, block-diagonal by joint."""
    batch = q.shape[:-1]
    Q = np.zeros(batch + (model.nq, model.nv))
    for iq, nq, iv, nv in _joints(model):
        if (nq, nv) in ((7, 6), (4, 3)):
            at = iq + 3 if nq == 7 else iq
            x, y, z, w = (q[..., at + k] for k in range(4))
            # quat ⊗ (e_c / 2, 0) for c = 0, 1, 2: columns (w a + u × a, −u·a)
            half = 0.5
            cols = [np.stack([w, z, -y, -x], -1), np.stack([-z, w, x, -y], -1), np.stack([y, -x, w, -z], -1)]
            for c in range(3):  # the rotation's tangent: the first three columns of either joint
                Q[..., at: at + 4, iv + c] = half * cols[c]
            if nq == 7:
                Q[..., iq: iq + 3, iv + 3: iv + 6] = quat_to_matrix(q[..., at: at + 4])
        elif (nq, nv) == (3, 3):  # planar: q = [x, y, θ], v = [ω, v_x, v_y]
            th = q[..., iq + 2]
            c, s = np.cos(th), np.sin(th)
            Q[..., iq + 2, iv] = 1.0
            Q[..., iq, iv + 1], Q[..., iq + 1, iv + 1] = c, s
            Q[..., iq, iv + 2], Q[..., iq + 1, iv + 2] = -s, c
        else:
            for k in range(nv):
                Q[..., iq + k, iv + k] = 1.0
    return Q


def derivatives_from_coordinates(model: Any, q: ArrayLike, Dq: ArrayLike) -> np.ndarray:
    """``D`` `(..., k, nv)` from a derivative ``Dq`` `(..., k, nq)` with respect to plain coordinates::

        D = Dq · Q(q),   Q = d(q ⊕ δ)/dδ |_{δ=0}:  quat ⊗ (δω/2, 0),  R δv,  R(θ) (δv_x, δv_y)

    Source: the chain rule through the exponential map of ``fd.integrate`` (quaternion kinematics
    q̇ = ½ q ⊗ (ω, 0), body-frame angular velocity).
    """
    qq = np.asarray(q, dtype=np.float64)
    return _matrix(Dq, model, model.nq, "Dq") @ _tangent_to_coordinates(model, qq)


def derivatives_to_coordinates(model: Any, q: ArrayLike, D: ArrayLike) -> np.ndarray:
    """``Dq`` `(..., k, nq)`: the derivative with respect to plain coordinates of ``D`` `(..., k, nv)`::

        Dq = D · Q(q)⁺     (Q⁺ Q = 1: the chain rule gives D back; a quaternion's direction along itself gets 0)

    Source: as :func:`derivatives_from_coordinates` (Q's Moore–Penrose pseudo-inverse).
    """
    qq = np.asarray(q, dtype=np.float64)
    return _matrix(D, model, model.nv) @ np.linalg.pinv(_tangent_to_coordinates(model, qq))
