"""Jacobians of the exponential maps of SO(3), SE(3) and SE(2) (the derivatives of ``fd.integrate`` and ``fd.difference``).

Right Jacobians in featherdyn's orders — ``ω`` for SO(3), ``ξ = [ω; v]`` for
SE(3), ``[ω, v_x, v_y]`` for SE(2) — so that, for a right-multiplied step,

    exp(ξ + δ) ≈ exp(ξ) exp(Jr(ξ) δ),      log(exp(ξ) exp(δ)) ≈ ξ + Jr(ξ)⁻¹ δ

(Barfoot, *State Estimation for Robotics*, §7.1.5 and §7.2; Solà, Deray &
Atchuthan, "A micro Lie theory", 2018, appendices). The coefficients are
evaluated by their Taylor series below ``_SERIES`` rad, where the closed forms
lose digits to cancellation.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .ops import skew_unchecked

__all__ = ["so3_right_jacobian", "so3_right_jacobian_inverse", "se3_right_jacobian", "se3_right_jacobian_inverse",
           "se3_inverse_adjoint_of_exp", "se2_right_jacobian", "se2_inverse_adjoint_of_exp"]

#: below this angle (rad) the coefficients are their Taylor series (eight terms: the first left out is below 1e-17
#: of the sum there; five left 2e-11 at 0.5 rad)
_SERIES = 0.5


def _coef(theta: np.ndarray, closed: Callable[[np.ndarray], np.ndarray], series: tuple[float, ...]) -> np.ndarray:
    """``closed(θ)`` where θ ≥ _SERIES, else Σ_k series[k] θ^(2k)."""
    t2 = theta * theta
    s = np.zeros_like(theta)
    for c in reversed(series):
        s = s * t2 + c
    big = theta >= _SERIES
    safe = np.where(big, theta, 1.0)
    return np.where(big, closed(safe), s)


# (1 − cos θ)/θ², (θ − sin θ)/θ³, sin θ / θ
def _a1(t: np.ndarray) -> np.ndarray:
    return _coef(t, lambda x: (1 - np.cos(x)) / x**2, (1 / 2, -1 / 24, 1 / 720, -1 / 40320, 1 / 3628800,
                                                               -1 / 479001600, 1 / 87178291200, -1 / 20922789888000))


def _a2(t: np.ndarray) -> np.ndarray:
    return _coef(t, lambda x: (x - np.sin(x)) / x**3, (1 / 6, -1 / 120, 1 / 5040, -1 / 362880, 1 / 39916800,
                                                               -1 / 6227020800, 1 / 1307674368000,
                                                               -1 / 355687428096000))


def _sinc(t: np.ndarray) -> np.ndarray:
    return _coef(t, lambda x: np.sin(x) / x, (1.0, -1 / 6, 1 / 120, -1 / 5040, 1 / 362880, -1 / 39916800,
                                                   1 / 6227020800, -1 / 1307674368000))


def so3_right_jacobian(w: np.ndarray) -> np.ndarray:
    """``Jr(ω)`` `(..., 3, 3)`::

        Jr(ω) = 1 − (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×²,   θ = |ω|
    """
    t = np.linalg.norm(w, axis=-1)[..., None, None]
    W = skew_unchecked(w)
    return np.eye(3) - _a1(t) * W + _a2(t) * (W @ W)


def so3_right_jacobian_inverse(w: np.ndarray) -> np.ndarray:
    """``Jr(ω)⁻¹`` `(..., 3, 3)`::

        Jr(ω)⁻¹ = 1 + ½ [ω]× + (1/θ² − (1 + cos θ)/(2 θ sin θ)) [ω]×²
    """
    t = np.linalg.norm(w, axis=-1)[..., None, None]
    W = skew_unchecked(w)
    e = _coef(t, lambda x: 1 / x**2 - (1 + np.cos(x)) / (2 * x * np.sin(x)),
              (1 / 12, 1 / 720, 1 / 30240, 1 / 1209600, 1 / 47900160, 691 / 1307674368000,
               1 / 74724249600, 3617 / 10670622842880000))
    return np.eye(3) + 0.5 * W + e * (W @ W)


def _se3_Q(rho: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Barfoot's ``Q(ρ, φ)`` (the coupling block of SE(3)'s left Jacobian; ρ translation, φ rotation)."""
    t = np.linalg.norm(phi, axis=-1)[..., None, None]
    P, R = skew_unchecked(phi), skew_unchecked(rho)
    a = _a2(t)
    b = _coef(t, lambda x: (x**2 / 2 + np.cos(x) - 1) / x**4, (1 / 24, -1 / 720, 1 / 40320, -1 / 3628800, 1 / 479001600,
                                    -1 / 87178291200, 1 / 20922789888000, -1 / 6402373705728000))
    d = _coef(t, lambda x: (2 * x - 3 * np.sin(x) + x * np.cos(x)) / (2 * x**5),
              (1 / 120, -1 / 2520, 1 / 120960, -1 / 9979200, 1 / 1245404160, -1 / 217945728000,
               1 / 50812489728000, -1 / 15205637551104000))
    PR, RP, PRP = P @ R, R @ P, P @ R @ P
    return 0.5 * R + a * (PR + RP + PRP) + b * (P @ PR + RP @ P - 3 * PRP) + d * (PRP @ P + P @ PRP)


def se3_right_jacobian(xi: np.ndarray) -> np.ndarray:
    """``Jr(ξ)`` `(..., 6, 6)` for ``ξ = [ω; v]``: ``[[Jr(ω), 0], [Q(−v, −ω), Jr(ω)]]``."""
    w, v = xi[..., :3], xi[..., 3:]
    J = so3_right_jacobian(w)
    out = np.zeros(xi.shape[:-1] + (6, 6))
    out[..., :3, :3] = J
    out[..., 3:, 3:] = J
    out[..., 3:, :3] = _se3_Q(-v, -w)
    return out


def se3_right_jacobian_inverse(xi: np.ndarray) -> np.ndarray:
    """``Jr(ξ)⁻¹`` `(..., 6, 6)`: ``[[A, 0], [B, A]]⁻¹ = [[A⁻¹, 0], [−A⁻¹ B A⁻¹, A⁻¹]]``."""
    w, v = xi[..., :3], xi[..., 3:]
    Ai = so3_right_jacobian_inverse(w)
    out = np.zeros(xi.shape[:-1] + (6, 6))
    out[..., :3, :3] = Ai
    out[..., 3:, 3:] = Ai
    out[..., 3:, :3] = -Ai @ _se3_Q(-v, -w) @ Ai
    return out


def se3_inverse_adjoint_of_exp(xi: np.ndarray) -> np.ndarray:
    """``Ad(exp(ξ))⁻¹`` `(..., 6, 6)` on ``[ω; v]`` motions: ``[[Rᵀ, 0], [−Rᵀ [p]×, Rᵀ]]`` for ``exp(ξ) = (R, p)``."""
    w, v = xi[..., :3], xi[..., 3:]
    t = np.linalg.norm(w, axis=-1)[..., None, None]
    W = skew_unchecked(w)
    R = np.eye(3) + _sinc(t) * W + _a1(t) * (W @ W)
    V = np.eye(3) + _a1(t) * W + _a2(t) * (W @ W)
    p = (V @ v[..., None])[..., 0]
    Rt = np.swapaxes(R, -1, -2)
    out = np.zeros(xi.shape[:-1] + (6, 6))
    out[..., :3, :3] = Rt
    out[..., 3:, 3:] = Rt
    out[..., 3:, :3] = -Rt @ skew_unchecked(p)
    return out


def se2_right_jacobian(xi: np.ndarray) -> np.ndarray:
    """``Jr(ξ)`` `(..., 3, 3)` for ``ξ = [ω, v_x, v_y]`` (Solà et al., eq. 163, reordered angle-first)."""
    th, r1, r2 = xi[..., 0], xi[..., 1], xi[..., 2]
    t = np.abs(th)
    s, c1 = _sinc(t), _a1(t) * th  # sin θ/θ,  (1 − cos θ)/θ
    # (θ ρ1 − ρ2 + ρ2 cos θ − ρ1 sin θ)/θ² = ρ1 (θ − sin θ)/θ² − ρ2 (1 − cos θ)/θ²
    d1 = r1 * _a2(t) * th - r2 * _a1(t)
    d2 = r2 * _a2(t) * th + r1 * _a1(t)
    out = np.zeros(xi.shape[:-1] + (3, 3))
    out[..., 0, 0] = 1.0
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2] = d1, s, c1
    out[..., 2, 0], out[..., 2, 1], out[..., 2, 2] = d2, -c1, s
    return out


def se2_inverse_adjoint_of_exp(xi: np.ndarray) -> np.ndarray:
    """``Ad(exp(ξ))⁻¹`` `(..., 3, 3)` on ``[ω, v_x, v_y]`` for ``exp(ξ) = (R(θ), t)``::

        Ad(T) [ω; v] = [ω; R v + ω (t_y, −t_x)],   Ad(T)⁻¹ [ω; v] = [ω; Rᵀ (v − ω (t_y, −t_x))]
    """
    th, r1, r2 = xi[..., 0], xi[..., 1], xi[..., 2]
    t = np.abs(th)
    s, c1 = _sinc(t) * th, _a1(t) * th * th  # sin θ, 1 − cos θ
    cth = 1.0 - c1
    # exp: R(θ), translation V ρ with V = [[sin θ/θ, −(1 − cos θ)/θ], [(1 − cos θ)/θ, sin θ/θ]]
    sn, cn = _sinc(t), _a1(t) * th
    tx = sn * r1 - cn * r2
    ty = cn * r1 + sn * r2
    # Ad(T) on (ω, v) with T = (R, t): ω' = ω, v' = R v + ω [t_y, −t_x]; its inverse: v = Rᵀ (v' − ω [t_y, −t_x])
    out = np.zeros(xi.shape[:-1] + (3, 3))
    out[..., 0, 0] = 1.0
    out[..., 1, 1], out[..., 1, 2] = cth, s
    out[..., 2, 1], out[..., 2, 2] = -s, cth
    out[..., 1, 0] = -(cth * ty + s * (-tx))
    out[..., 2, 0] = -(-s * ty + cth * (-tx))
    return out
