"""Derivatives of inverse and forward dynamics, the joint torque regressor (reference).

∂τ/∂q and ∂τ/∂q̇ by the tangent-linear RNEA (the derivative of each line of
``rnea.py``; Carpentier & Mansard, RSS 2018, written in body coordinates).
A derivative with respect to q is taken along the tangent of
``fd.integrate``: ``q ⊕ ε e_j`` moves body k — the body of direction j,
column c of its motion subspace — by ``ᵖM_k exp(ε S_c)``, so that
``δX_up[k] = −S_c × X_up[k]``. For the bodies i of k's subtree::

    δv_k = −S_c × (X_up[k] v_λ(k)),            δa_k = −S_c × (X_up[k] a_λ(k)) + δv_k × S_k q̇_k
    δv_i = X_up[i] δv_λ(i),                     δa_i = X_up[i] δa_λ(i) + δv_i × S_i q̇_i
    δf_i = I_i δa_i + δv_i ×* I_i v_i + v_i ×* I_i δv_i
    δτ_i = S_iᵀ δF_i,   δF_λ(i) += X_up[i]ᵀ δF_i,   at k: δF_λ(k) += X_up[k]ᵀ (δF_k + S_c ×* F_k)

and up the ancestors of k (F: the forces after RNEA's backward pass). A q̇
direction starts from ``δv_k = S_c``, ``δa_k = S_c × S_k q̇_k + v_k × S_c``.

Forward dynamics: ``q̈ = ABA(q, q̇, τ)`` solves ``RNEA(q, q̇, q̈) = τ``, so
``∂q̈/∂q = −M⁻¹ ∂τ/∂q``, ``∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇``, ``∂q̈/∂τ = M⁻¹``, with
M⁻¹ from the articulated-body recursion on unit joint forces (M is never
inverted). The regressor: RNEA is linear in each body's ten parameters
``π_i = [m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]`` (I about the body
origin), ``τ = Y π``.
"""

from __future__ import annotations

import numpy as np

from ..frames import ReferenceFrame
from ..model import Model
from ..spatial_algebra import SpatialForce, SpatialMotion, cross_force, cross_motion
from . import aba as _aba
from ._common import TreeData, batch_dtype, expand, zeros
from .rnea import forward_pass

__all__ = ["rnea_derivatives", "mass_matrix_inverse", "aba_derivatives", "joint_torque_regressor",
           "dynamic_parameters", "frame_motion_derivatives"]


def _nominal(model: Model, td: TreeData, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None,
             a0: SpatialMotion) -> tuple[list, list, list, list, list]:
    """RNEA's passes (``rnea.forward_pass``, then the backward accumulation): ``X_up``, ``S q̇``, ``v``, ``a``, ``F``."""
    X_up, vJs, vel, acc, F = forward_pass(td, q, qd, qdd, f_ext, a0)
    for i in range(td.nb - 1, -1, -1):
        if td.parents[i] != -1:
            F[td.parents[i]] = F[td.parents[i]] + X_up[i].apply_inverse(F[i])
    return X_up, vJs, vel, acc, F


def _subtree(model: Model, k: int) -> list[int]:
    """Body k and its descendants, in increasing order."""
    inside = {k}
    for i in range(k + 1, model.nbodies):
        if model.parents[i] in inside:
            inside.add(i)
    return sorted(inside)


def rnea_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None = None,
                     gravity: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """``(∂τ/∂q, ∂τ/∂q̇)`` `(..., nv, nv)` of ``τ = RNEA(q, q̇, q̈)`` on checked arrays (module docstring)."""
    batch, dtype = batch_dtype(q, qd, qdd, f_ext=f_ext)
    td = TreeData(model, dtype)
    a0 = td.a0 if gravity else SpatialMotion._wrap(np.zeros(6, dtype=td.dtype), None)
    X_up, vJ, vel, acc, F = _nominal(model, td, q, qd, qdd, f_ext, a0)
    nv = model.nv
    out = {False: zeros(batch, (nv, nv), td.dtype), True: zeros(batch, (nv, nv), td.dtype)}

    def put(m: np.ndarray, i: int, j: int, f: SpatialForce) -> None:
        m[..., model.idx_v[i]: model.idx_v[i] + model.nvs[i], j] = f.vector @ td.S[i]

    for k in range(td.nb):
        lam_k = td.parents[k]
        sub = _subtree(model, k)
        xv = None if lam_k == -1 else X_up[k].apply(vel[lam_k])
        xa = X_up[k].apply(a0 if lam_k == -1 else acc[lam_k])
        for c in range(model.nvs[k]):
            Sc = SpatialMotion._wrap(np.broadcast_to(td.S[k][:, c], batch + (6,)).copy(), None)
            j = model.idx_v[k] + c
            for wrt_v in (False, True):
                dv: dict[int, SpatialMotion] = {}
                da: dict[int, SpatialMotion] = {}
                dF: dict[int, SpatialForce] = {}
                for i in sub:
                    if i == k and wrt_v:
                        dv[k] = Sc
                        da[k] = cross_motion(Sc, vJ[k]) + cross_motion(vel[k], Sc)
                    elif i == k:
                        dv[k] = -cross_motion(Sc, xv) if xv is not None else Sc - Sc
                        da[k] = -cross_motion(Sc, xa) + cross_motion(dv[k], vJ[k])
                    else:
                        lam = td.parents[i]
                        dv[i] = X_up[i].apply(dv[lam])
                        da[i] = X_up[i].apply(da[lam]) + cross_motion(dv[i], vJ[i])
                    I = td.I[i]
                    dF[i] = I @ da[i] + cross_force(dv[i], I @ vel[i]) + cross_force(vel[i], I @ dv[i])
                for i in reversed(sub[1:]):
                    put(out[wrt_v], i, j, dF[i])
                    dF[td.parents[i]] = dF[td.parents[i]] + X_up[i].apply_inverse(dF[i])
                put(out[wrt_v], k, j, dF[k])
                if lam_k == -1:
                    continue
                G = X_up[k].apply_inverse(dF[k] if wrt_v else dF[k] + cross_force(Sc, F[k]))
                i = lam_k
                while i != -1:
                    put(out[wrt_v], i, j, G)
                    if td.parents[i] != -1:
                        G = X_up[i].apply_inverse(G)
                    i = td.parents[i]
    return out[False], out[True]


def mass_matrix_inverse(model: Model, q: np.ndarray) -> np.ndarray:
    """``M(q)⁻¹`` `(..., nv, nv)`: the articulated-body recursion on unit joint forces, no velocity, no gravity::

        M⁻¹ e_j = ABA(q, 0, e_j)
    """
    nv = model.nv
    dtype = np.result_type(q.dtype, np.float64) if q.dtype.kind != "O" else q.dtype
    eye = np.eye(nv, dtype=dtype) if dtype.kind != "O" else np.eye(nv).astype(object)
    cols = _aba.aba(model, q[..., None, :], np.zeros_like(eye[:1]), eye, None, False)  # row j: M⁻¹ e_j
    return np.swapaxes(cols, -1, -2)


def aba_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, f_ext: np.ndarray | None = None,
                    gravity: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)`` `(..., nv, nv)` of ``q̈ = ABA(q, q̇, τ)``::

        ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (∂τ of RNEA at q̈ = ABA(q, q̇, τ))
    """
    qdd = _aba.aba(model, q, qd, tau, f_ext, gravity)
    dq, dv = rnea_derivatives(model, q, qd, qdd, f_ext, gravity)
    Minv = mass_matrix_inverse(model, q)
    return -(Minv @ dq), -(Minv @ dv), Minv


def dynamic_parameters(model: Model) -> np.ndarray:
    """The bodies' dynamic parameters stacked, `(10 nb,)` (``SpatialInertia.to_dynamic_parameters`` order)."""
    if model.nbodies == 0:
        return np.zeros(0)
    return np.concatenate([model.inertias[i].to_dynamic_parameters() for i in range(model.nbodies)])


def _unit_parameter_force(k: int, a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``I(e_k) a + v ×* I(e_k) v`` `(..., 6)` for the inertia whose parameters are the unit vector e_k.

    In the ``(m, h = m c, I_O)`` form (``I_O`` about the body origin), which also holds the
    massless first moments of e_1 … e_3::

        I x = [I_O x_ω + h × x_v;  m x_v − h × x_ω],    v ×* p = [ω × p_n + v_lin × p_f;  ω × p_f]
    """
    m = 1.0 if k == 0 else 0.0
    h = np.zeros(3)
    Io = np.zeros((3, 3))
    if 1 <= k <= 3:
        h[k - 1] = 1.0
    elif k >= 4:
        r, c = [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)][k - 4]
        Io[r, c] = Io[c, r] = 1.0

    def times(x: np.ndarray) -> np.ndarray:
        xw, xv = x[..., :3], x[..., 3:]
        n = xw @ Io.T + np.cross(h, xv)
        f = m * xv - np.cross(h, xw)
        return np.concatenate([n, f], axis=-1)

    p = times(v)
    w, vl = v[..., :3], v[..., 3:]
    vp = np.concatenate([np.cross(w, p[..., :3]) + np.cross(vl, p[..., 3:]), np.cross(w, p[..., 3:])], axis=-1)
    return times(a) + vp


def joint_torque_regressor(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """``Y`` `(..., nv, 10 nb)` with ``RNEA(q, q̇, q̈) = Y π + armature ∘ q̈`` (gravity included), float64::

        Y[joint j, 10 i + k] = S_jᵀ ʲX_i* (I(e_k) a_i + v_i ×* I(e_k) v_i)    (j supporting i)

    The armature is not a body parameter: ``Y π`` is the rigid bodies' part.
    """
    batch, dtype = batch_dtype(q, qd, qdd)
    td = TreeData(model, dtype)
    X_up, _, vel, acc, _ = _nominal(model, td, q, qd, qdd, None, td.a0)
    Y = zeros(batch, (model.nv, 10 * td.nb), td.dtype)
    for i in range(td.nb):
        for k in range(10):
            f = SpatialForce._wrap(_unit_parameter_force(k, acc[i].vector, vel[i].vector), None)
            j = i
            while True:
                Y[..., model.idx_v[j]: model.idx_v[j] + model.nvs[j], 10 * i + k] = f.vector @ td.S[j]
                if td.parents[j] == -1:
                    break
                f = X_up[j].apply_inverse(f)
                j = td.parents[j]
    return Y


def _crm(s: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``s × m`` for 6D motions ``[ω; v]`` `(..., 6)` (the motion cross product, RBDA eq. 2.31)."""
    ws, vs, wm, vm = s[..., :3], s[..., 3:], m[..., :3], m[..., 3:]
    return np.concatenate([np.cross(ws, wm), np.cross(ws, vm) + np.cross(vs, wm)], axis=-1)


def frame_motion_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray | None, fid: int,
                             ref: ReferenceFrame) -> list[np.ndarray]:
    """``[∂v_f/∂q, ∂v_f/∂q̇]`` and, with ``qdd``, ``[∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈]``, each `(..., 6, nv)`.

    In world coordinates (``⁰S_k``: joint k's columns carried to the world, ``⁰v_k`` body k's velocity),
    the frame's body b has ``⁰v_b = Σ ⁰S_i q̇_i`` and ``⁰a_b = Σ ⁰S_i q̈_i + ⁰v_i × ⁰S_i q̇_i`` over its
    support; moving joint k along column s = ``⁰S_kc`` turns every ``⁰S_i`` below k by ``s ×``::

        ∂⁰v_b/∂q_kc = s × (⁰v_b − ⁰v_λ(k))
        ∂⁰a_b/∂q_kc = Σ_{i ⪰ k} s × ⁰S_i q̈_i + (δ⁰v_i × ⁰S_i + ⁰v_i × (s × ⁰S_i)) q̇_i,   δ⁰v_i = s × (⁰v_i − ⁰v_λ(k))
        ∂⁰a_b/∂q̇_kc = Σ_{i ⪰ k} (s × ⁰S_i) q̇_i + ⁰v_k × s,       ∂⁰v_b/∂q̇ = ∂⁰a_b/∂q̈ = ⁰J

    then LOCAL ``ᶠy = ᶠX_0 ⁰y`` (``δᶠy = ᶠX_0 δ⁰y − (ᶠX_0 s) × ᶠy``) and LOCAL_WORLD_ALIGNED
    ``blkdiag(R_f, R_f) ᶠy`` (``+ [ᶠω_s]×`` on each half before rotating), as ``fd.frame_velocity``.
    """
    from .jacobians import _world_columns, support
    from .kinematics import _body_at, _motion_at, forward_kinematics, frame_pose

    batch, dtype = batch_dtype(q, qd, qdd)
    td = TreeData(model, dtype)
    kin = forward_kinematics(model, q, qd, None)
    nv = model.nv
    body = model.frames[fid].body
    sup = support(model, body)
    W = _world_columns(model, td, kin.placements, batch)  # (..., nv, 6)
    assert kin.velocities is not None
    v0 = {i: _body_at(kin.placements, i).apply(_motion_at(kin.velocities, i)).vector for i in sup}
    zero6 = np.zeros(batch + (6,), dtype=dtype)
    dofs = {i: range(model.idx_v[i], model.idx_v[i] + model.nvs[i]) for i in sup}
    vb = v0[sup[-1]] if sup else zero6
    ab = zero6.copy()
    for i in sup:
        for d in dofs[i]:
            ab = ab + (W[..., d, :] * qdd[..., d, None] if qdd is not None else 0.0) + _crm(v0[i], W[..., d, :]) * qd[..., d, None]
    dv_dq, dv_dv = zeros(batch, (6, nv), dtype), zeros(batch, (6, nv), dtype)
    da_dq, da_dv, da_da = (zeros(batch, (6, nv), dtype) for _ in range(3))
    for pos, k in enumerate(sup):
        v_parent = v0[sup[pos - 1]] if pos > 0 else zero6
        below = sup[pos:]
        for j in dofs[k]:
            s = W[..., j, :]
            dv_dq[..., :, j] = _crm(s, vb - v_parent)
            dv_dv[..., :, j] = s
            da_da[..., :, j] = s
            acc = zero6.copy()
            accv = _crm(v0[k], s)
            for i in below:
                dvi = _crm(s, v0[i] - v_parent)
                for d in dofs[i]:
                    Si = W[..., d, :]
                    if qdd is not None:
                        acc = acc + _crm(s, Si) * qdd[..., d, None]
                    acc = acc + (_crm(dvi, Si) + _crm(v0[i], _crm(s, Si))) * qd[..., d, None]
                    accv = accv + _crm(s, Si) * qd[..., d, None]
            da_dq[..., :, j] = acc
            da_dv[..., :, j] = accv
    if ref is not ReferenceFrame.WORLD:
        oMf = frame_pose(model, kin, fid)

        def local(x: np.ndarray) -> np.ndarray:  # ᶠX_0 applied to every column of x (..., 6, n)
            cols = SpatialMotion._wrap(np.ascontiguousarray(np.swapaxes(x, -1, -2)), None)
            return np.swapaxes(expand(oMf).apply_inverse(cols).vector, -1, -2).copy()

        def local_vec(x: np.ndarray) -> np.ndarray:
            return oMf.apply_inverse(SpatialMotion._wrap(x, None)).vector

        vf, af = local_vec(vb), local_vec(ab)
        sf = local(np.swapaxes(W, -1, -2))  # (..., 6, nv): ᶠX_0 s per column (columns off the support unused)
        outs = []
        for dq_w, y in ((dv_dq, vf), (da_dq, af)):
            dm = local(dq_w)
            for k in sup:
                for j in dofs[k]:
                    dm[..., :, j] = dm[..., :, j] - _crm(sf[..., :, j], y)
            outs.append(dm)
        dv_dq, da_dq = outs
        dv_dv, da_dv, da_da = local(dv_dv), local(da_dv), local(da_da)
        if ref is ReferenceFrame.LOCAL_WORLD_ALIGNED:
            R = oMf.rotation[..., None, :, :]

            def rotate(x: np.ndarray) -> np.ndarray:  # blkdiag(R, R) on the row axis
                xt = np.swapaxes(x, -1, -2)
                return np.swapaxes(np.concatenate([(R @ xt[..., :3, None])[..., 0], (R @ xt[..., 3:, None])[..., 0]],
                                                  axis=-1), -1, -2)

            for dm, y in ((dv_dq, vf), (da_dq, af)):
                for k in sup:
                    for j in dofs[k]:
                        w = sf[..., :3, j]
                        dm[..., :3, j] = dm[..., :3, j] + np.cross(w, y[..., :3])
                        dm[..., 3:, j] = dm[..., 3:, j] + np.cross(w, y[..., 3:])
            dv_dq, dv_dv, da_dq, da_dv, da_da = (rotate(x) for x in (dv_dq, dv_dv, da_dq, da_dv, da_da))
    if qdd is None:
        return [dv_dq, dv_dv]
    return [dv_dq, dv_dv, da_dq, da_dv, da_da]
