"""Derivatives of a frame's motion, of the centre of mass and of the centroidal momentum (reference).

Every quantity in world coordinates at the world origin: ``⁰S_j`` joint columns, ``v_i``,
``a_i`` body velocities and accelerations (no gravity; ``a_i = d v_i / dt`` in world
coordinates), ``I_i`` body inertias. A derivative with respect to q is taken along the
tangent of ``fd.integrate``: column ``s = ⁰S_j`` of joint k moves k's subtree rigidly by
``exp(ε s)``; with ``u = v_λ(k)``, ``w = a_λ(k)`` (zero at a root) and ``z = s × u``, each
body i of the subtree answers with (docs/derivatives.md)::

    ∂I_i = s ×* I_i − I_i s×,   ∂v_i = s × (v_i − u),   ∂a_i = s × (a_i − w) − z × (v_i − u)
    ∂v_i/∂q̇_j = s,              ∂a_i/∂q̇_j = v_k × s + s × (v_i − u),   ∂a_i/∂q̈_j = s

Summed over the subtree (composites ``I^C``, ``h^C = Σ I_i v_i``, ``F^C = Σ (I_i a_i + v_i ×* I_i v_i)``,
``İ^C = Σ (v_i ×* I_i − I_i v_i×)``) the momentum ``h_O = Σ I_i v_i`` and its rate ``ḣ_O`` give::

    ∂h_O/∂q_j = s ×* h^C − I^C z                      ∂h_O/∂q̇_j = I^C s
    ∂ḣ_O/∂q_j = s ×* F^C − I^C (s × w) + I^C (z × u) − İ^C z − z ×* h^C
    ∂ḣ_O/∂q̇_j = I^C (v_k × s + u × s) + İ^C s + s ×* h^C          ∂ḣ_O/∂q̈_j = I^C s

and, the centre of mass ``c = (I^C_tree)'s first moment / m``, ``ċ = p / m``::

    ∂c/∂q_j = lin(I^C s) / m,    ∂ċ/∂q_j = lin(∂h_O/∂q_j) / m
    h_G = [k_O − c × p; p]:      ∂h_G = [∂k_O − c × ∂p − ∂c × p; ∂p]     (ḣ_G the same with ṗ)

A frame's motion derivatives are :func:`derivatives.frame_motion_derivatives`'s; its classical
acceleration ``a^c = [ω̇; a_lin + ω × v_lin]`` (ω, v, a of the frame in the reference) adds
``[0; ∂ω × v_lin + ω × ∂v_lin]``.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..frames import ReferenceFrame
from ..model import Model
from ..spatial import PluckerTransform
from ..spatial.ops import crf_apply, crm_apply, cross3
from ._common import TreeData, batch_dtype, zeros
from .derivatives import frame_motion_derivatives
from .energy import center_of_mass
from .jacobians import world_columns
from .kinematics import body_at, forward_kinematics, frame_pose, motion_at

__all__ = ["kinematics_derivatives", "center_of_mass_derivatives", "centroidal_dynamics_derivatives"]


def _frame_motion(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, fid: int, ref: ReferenceFrame,
                  point: np.ndarray | None, batch: tuple[int, ...], dtype: np.dtype) -> tuple[np.ndarray, np.ndarray]:
    """``(v, a)`` `(..., 6)` of the frame (moved to ``point``) in ``ref``, as ``fd.frame_velocity`` and
    ``fd.frame_acceleration`` give them."""
    kin = forward_kinematics(model, q, qd, qdd)
    body = model.frames[fid].body
    if body == -1:  # a frame fixed to the world does not move
        z = zeros(batch, (6,), dtype)
        return z, z.copy()
    oMf = frame_pose(model, kin, fid)
    if point is not None:
        eye = np.broadcast_to(np.eye(3, dtype=dtype), batch + (3, 3))
        oMf = oMf @ PluckerTransform._wrap(eye, np.broadcast_to(np.asarray(point, dtype=dtype), batch + (3,)),
                                           None, None)
    oMb = body_at(kin.placements, body)
    assert kin.velocities is not None and kin.accelerations is not None
    out = []
    for m in (motion_at(kin.velocities, body), motion_at(kin.accelerations, body)):
        world = oMb.apply(m)
        local = oMf.apply_inverse(world).vector
        if ref is ReferenceFrame.WORLD:
            out.append(world.vector)
        elif ref is ReferenceFrame.LOCAL:
            out.append(local)
        else:
            R = oMf.rotation
            out.append(np.concatenate([(R @ local[..., :3, None])[..., 0], (R @ local[..., 3:, None])[..., 0]],
                                      axis=-1))
    return out[0], out[1]


def kinematics_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, frame: int,
                           reference: ReferenceFrame, point: np.ndarray | None = None
                           ) -> tuple[np.ndarray, ...]:
    """``(∂v/∂q, ∂v/∂q̇, ∂a/∂q, ∂a/∂q̇, ∂a/∂q̈, ∂a^c/∂q, ∂a^c/∂q̇, ∂a^c/∂q̈)`` `(..., 6, nv)` of a frame (at
    ``point``) in ``reference`` on checked arrays (module docstring; ``∂a/∂q̈ = ∂a^c/∂q̈ = ∂v/∂q̇ = J``, as
    copies; public: :func:`featherdyn.kinematics_derivatives`)::

        a^c = [ω̇; a_lin + ω × v_lin],    ∂a^c = ∂a + [0; ∂ω × v_lin + ω × ∂v_lin]
    """
    batch, dtype = batch_dtype(q, qd, qdd)
    if point is not None:  # the state broadcast to the points' batch as well
        batch = np.broadcast_shapes(batch, np.shape(point)[:-1])
        dtype = np.result_type(dtype, np.asarray(point).dtype) if dtype.kind != "O" else dtype
        q, qd, qdd = (np.broadcast_to(x, batch + x.shape[-1:]) for x in (q, qd, qdd))
    dv_dq, dv_dv, da_dq, da_dv, _ = frame_motion_derivatives(model, q, qd, qdd, frame, reference, point)
    v, _ = _frame_motion(model, q, qd, qdd, frame, reference, point, batch, dtype)
    w, lin = v[..., None, :3], v[..., None, 3:]

    def classical(da: np.ndarray, dv: np.ndarray) -> np.ndarray:
        dvt = np.swapaxes(dv, -1, -2)  # (..., nv, 6)
        extra = cross3(dvt[..., :3], lin) + cross3(w, dvt[..., 3:])
        out = da.copy()
        out[..., 3:, :] = out[..., 3:, :] + np.swapaxes(extra, -1, -2)
        return out

    return (dv_dq, dv_dv, da_dq, da_dv, dv_dv.copy(), classical(da_dq, dv_dq), classical(da_dv, dv_dv),
            dv_dv.copy())


def _composites(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray | None
                ) -> tuple[tuple[int, ...], np.dtype, np.ndarray, list[np.ndarray], list[np.ndarray],
                           list[np.ndarray], list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
    """World columns `(..., nv, 6)`, the bodies' world velocities and accelerations, and the subtree composites
    ``I^C`` `(..., 6, 6)`, ``h^C``, ``F^C`` `(..., 6)` and ``İ^C`` `(..., 6, 6)` (module docstring)."""
    if not model.total_mass > 0:
        raise ModelError.no_mass(model.name)
    batch, dtype = batch_dtype(q, qd, qdd)
    td = TreeData(model, dtype)
    nb = model.nbodies
    acc = qdd if qdd is not None else np.zeros(batch + (model.nv,), dtype=dtype)
    kin = forward_kinematics(model, q, qd, acc)
    assert kin.velocities is not None and kin.accelerations is not None
    W = world_columns(model, td, kin.placements, batch)
    v, a, IC, hC, FC, BC = [], [], [], [], [], []
    for i in range(nb):
        P = body_at(kin.placements, i)
        vi = P.apply(motion_at(kin.velocities, i)).vector
        ai = P.apply(motion_at(kin.accelerations, i)).vector
        I = np.broadcast_to(P.apply(td.I[i]).matrix(), batch + (6, 6))
        h = np.einsum("...ij,...j->...i", I, vi)
        v.append(vi)
        a.append(ai)
        IC.append(I)
        hC.append(h)
        FC.append(np.einsum("...ij,...j->...i", I, ai) + crf_apply(vi, h))
        BC.append(_crf_matrix(vi) @ I - I @ _crm_matrix(vi))
    for i in range(nb - 1, -1, -1):
        lam = model.parents[i]
        if lam != -1:
            IC[lam], hC[lam], FC[lam], BC[lam] = IC[lam] + IC[i], hC[lam] + hC[i], FC[lam] + FC[i], BC[lam] + BC[i]
    return batch, dtype, W, v, a, IC, hC, FC, BC


def _crm_matrix(v: np.ndarray) -> np.ndarray:
    """`(..., 6, 6)` of ``m ↦ v × m`` (its columns: ``v × e_k``)."""
    eye = np.eye(6, dtype=v.dtype) if v.dtype.kind != "O" else np.eye(6).astype(object)
    return np.swapaxes(crm_apply(v[..., None, :], eye), -1, -2)


def _crf_matrix(v: np.ndarray) -> np.ndarray:
    """`(..., 6, 6)` of ``f ↦ v ×* f = −(v×)ᵀ f``."""
    return -np.swapaxes(_crm_matrix(v), -1, -2)


def _mv(M: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.einsum("...ij,...j->...i", M, x)


def _momentum_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray | None
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray | None,
                                     np.ndarray | None, np.ndarray | None]:
    """``(h_O, ḣ_O, ∂c/∂q`` `(..., 3, nv)`, ``∂h_O/∂q`` `(..., 6, nv)`, and with ``qdd`` ``∂ḣ_O/∂q, ∂q̇, ∂q̈)``."""
    batch, dtype, W, v, a, IC, hC, FC, BC = _composites(model, q, qd, qdd)
    nv, m = model.nv, model.total_mass
    dc, dh = zeros(batch, (3, nv), dtype), zeros(batch, (6, nv), dtype)
    rate = qdd is not None
    dhd_q, dhd_v, dhd_a = (zeros(batch, (6, nv), dtype) for _ in range(3)) if rate else (None, None, None)
    zero6 = zeros(batch, (6,), dtype)
    for k in range(model.nbodies):
        lam = model.parents[k]
        u, w = (v[lam], a[lam]) if lam != -1 else (zero6, zero6)
        for j in range(model.idx_v[k], model.idx_v[k] + model.nvs[k]):
            s = W[..., j, :]
            z = crm_apply(s, u)
            Is = _mv(IC[k], s)
            dc[..., :, j] = Is[..., 3:] / m
            dh[..., :, j] = crf_apply(s, hC[k]) - _mv(IC[k], z)
            if rate:
                assert dhd_q is not None and dhd_v is not None and dhd_a is not None
                dhd_q[..., :, j] = (crf_apply(s, FC[k]) - _mv(IC[k], crm_apply(s, w)) + _mv(IC[k], crm_apply(z, u))
                                    - _mv(BC[k], z) - crf_apply(z, hC[k]))
                dhd_v[..., :, j] = (_mv(IC[k], crm_apply(v[k], s) + crm_apply(u, s)) + _mv(BC[k], s)
                                    + crf_apply(s, hC[k]))
                dhd_a[..., :, j] = Is
    roots = [i for i in range(model.nbodies) if model.parents[i] == -1]
    h_O = sum((hC[i] for i in roots), zero6)
    hd_O = sum((FC[i] for i in roots), zero6)
    return h_O, hd_O, dc, dh, dhd_q, dhd_v, dhd_a


def center_of_mass_derivatives(model: Model, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(∂c/∂q, ∂ċ/∂q)`` `(..., 3, nv)` of the centre of mass in world coordinates on checked arrays (module
    docstring; ``∂ċ/∂q̇ = ∂c/∂q``, Pinocchio's ``jacobianCenterOfMass``; public:
    :func:`featherdyn.center_of_mass_derivatives`)::

        ∂c/∂q_j = lin(I^C_k s) / m,    ∂ċ/∂q_j = lin(s ×* h^C_k − I^C_k (s × v_λ(k))) / m

    Raises:
        ModelError: the tree has no mass (the centre of mass is undefined).
    """
    _, _, dc, dh, _, _, _ = _momentum_derivatives(model, q, qd, None)
    return dc, dh[..., 3:, :] / model.total_mass


def _about_com(d: np.ndarray, dc: np.ndarray, c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """``[∂k − c × ∂p − ∂c × p; ∂p]`` `(..., 6, nv)` from ``∂[k; p]`` `(..., 6, nv)` at the world origin."""
    dt = np.swapaxes(d, -1, -2)  # (..., nv, 6)
    k = dt[..., :3] - cross3(c[..., None, :], dt[..., 3:]) - cross3(np.swapaxes(dc, -1, -2), p[..., None, :])
    return np.swapaxes(np.concatenate([k, dt[..., 3:]], axis=-1), -1, -2)


def centroidal_dynamics_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray
                                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈)`` `(..., 6, nv)` of the centroidal momentum ``h_G = [k_G; p]``
    and its rate, about the centre of mass in world axes (``fd.centroidal_momentum``), on checked arrays (module
    docstring; ``∂h_G/∂q̇ = ∂ḣ_G/∂q̈ = A_G``; public: :func:`featherdyn.centroidal_dynamics_derivatives`)::

        ḣ_G = [k̇_O − c × ṗ; ṗ],   ∂ḣ_G/∂q = [∂k̇_O − c × ∂ṗ − ∂c × ṗ; ∂ṗ]

    Raises:
        ModelError: the tree has no mass (the centre of mass is undefined).
    """
    h_O, hd_O, dc, dh, dhd_q, dhd_v, dhd_a = _momentum_derivatives(model, q, qd, qdd)
    assert dhd_q is not None and dhd_v is not None and dhd_a is not None
    c = center_of_mass(model, forward_kinematics(model, q))
    assert isinstance(c, np.ndarray)
    c = np.broadcast_to(c, h_O.shape[:-1] + (3,))
    zero = np.zeros_like(dc)
    p, pd = h_O[..., 3:], hd_O[..., 3:]
    return (_about_com(dh, dc, c, p), _about_com(dhd_q, dc, c, pd), _about_com(dhd_v, zero, c, pd),
            _about_com(dhd_a, zero, c, pd))
