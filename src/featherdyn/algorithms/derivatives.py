"""Derivatives of inverse and forward dynamics, the joint torque regressor (reference).

∂τ/∂q and ∂τ/∂q̇ by the analytical algorithm of Carpentier & Mansard ("Analytical
derivatives of rigid body dynamics algorithms", RSS 2018), with every quantity of
a tree expressed in its root body's coordinates ``r`` (the body frame of the
tree's first body: exact however far the robot is from the world origin; the
core's ``derivatives.hpp`` is the same algorithm line for line). A derivative
with respect to q is taken along the tangent of ``fd.integrate``: ``q ⊕ ε e_j``
with column ``S_j`` of joint k moves k's whole subtree rigidly by ``exp(ε ʳS_j)``.
Seen from the moving subtree only its parent's motion changes::

    ∂V/∂q_j = v_λ(k) × S_j,    ∂A/∂q_j = a_λ(k) × S_j + v_λ(k) × ∂V/∂q_j,    ∂A/∂q̇_j = ∂V/∂q_j + v_k × S_j

(``v``, ``a`` in r, ``a`` with the base acceleration −g), and each body l of the
subtree answers with ``I_l ∂A + D_l ∂V``, ``D_l u = İ_l u + u ×* h_l`` (``İ_l =
v_l ×* I_l − I_l v_l×`` the inertia's rate, ``h_l = I_l v_l`` the momentum).
With the composites ``I^C``, ``D^C``, ``F^C`` (sums over a subtree), for a row of
joint i and a column j of joint k::

    k ∈ support(i):   ∂τ_i/∂q_j = S_iᵀ (I^C_i ∂A/∂q_j + D^C_i ∂V/∂q_j)      ∂τ_i/∂q̇_j = S_iᵀ (I^C_i ∂A/∂q̇_j + D^C_i S_j)
    i ancestor of k:  ∂τ_i/∂q_j = S_iᵀ (S_j ×* F^C_k + I^C_k ∂A/∂q_j + D^C_k ∂V/∂q_j)
                      ∂τ_i/∂q̇_j = S_iᵀ (I^C_k ∂A/∂q̇_j + D^C_k S_j)

(the rotation of ``S_i`` and ``F^C_i`` cancels when i moves with k: power is
frame-invariant). Every other entry is zero.

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
from ..spatial import PluckerTransform, SpatialForce, SpatialMotion
from ..spatial.ops import crf_apply, crm_apply, skew_unchecked
from . import aba as _aba
from . import crba as _crba
from ._common import TreeData, batch_dtype, expand, zeros
from .rnea import forward_pass

__all__ = ["rnea_derivatives", "rnea_partials", "frame_velocity_derivatives", "frame_acceleration_derivatives", "generalized_gravity_derivatives", "static_torque_derivatives", "mass_matrix_inverse", "aba_derivatives", "joint_torque_regressor",
           "dynamic_parameters", "frame_motion_derivatives"]


def _nominal(model: Model, td: TreeData, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None,
             a0: SpatialMotion) -> tuple[list, list, list, list, list]:
    """RNEA's passes (``rnea.forward_pass``, then the backward accumulation): ``X_up``, ``S q̇``, ``v``, ``a``, ``F``."""
    X_up, vJs, vel, acc, F = forward_pass(td, q, qd, qdd, f_ext, a0)
    for i in range(td.nb - 1, -1, -1):
        if td.parents[i] != -1:
            F[td.parents[i]] = F[td.parents[i]] + X_up[i].apply_inverse(F[i])
    return X_up, vJs, vel, acc, F


def _crm_matrix(v: np.ndarray) -> np.ndarray:
    """``[v]×`` `(..., 6, 6)` of an array already checked, any dtype (:func:`featherdyn.spatial.crm`)."""
    w, lin = skew_unchecked(v[..., :3]), skew_unchecked(v[..., 3:])
    zero = np.zeros_like(w)
    return np.concatenate([np.concatenate([w, zero], axis=-1), np.concatenate([lin, w], axis=-1)], axis=-2)


def _momentum_cross(h: np.ndarray) -> np.ndarray:
    """The `(..., 6, 6)` matrix of ``u ↦ u ×* h`` for a force ``h = [n; f]``: ``[[−[n]×, −[f]×], [−[f]×, 0]]``."""
    nx, fx = skew_unchecked(h[..., :3]), skew_unchecked(h[..., 3:])
    return -np.concatenate([np.concatenate([nx, fx], axis=-1), np.concatenate([fx, np.zeros_like(fx)], axis=-1)],
                           axis=-2)


def rnea_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None = None,
                     gravity: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈ = M)`` `(..., nv, nv)` of ``τ = RNEA(q, q̇, q̈)`` on checked arrays (public:
    :func:`featherdyn.rnea_derivatives`)."""
    dq, dv = rnea_partials(model, q, qd, qdd, f_ext, gravity)
    return dq, dv, _crba.crba(model, q)


def rnea_partials(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None = None,
                  gravity: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """``(∂τ/∂q, ∂τ/∂q̇)`` `(..., nv, nv)` of ``τ = RNEA(q, q̇, q̈)`` on checked arrays (module docstring)."""
    batch, dtype = batch_dtype(q, qd, qdd, f_ext=f_ext)
    return partials_on(TreeData(model, dtype), batch, q, qd, qdd, f_ext, gravity)


def partials_on(td: TreeData, batch: tuple[int, ...], q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                f_ext: np.ndarray | None = None, gravity: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """:func:`rnea_partials` on the tree data ``td`` (its poses ``td.pose_in_parent``, its dtype) and ``batch``."""
    model = td.model
    nb, nv, parents = td.nb, model.nv, td.parents
    a0 = td.a0 if gravity else SpatialMotion._wrap(np.zeros(6, dtype=td.dtype), None)
    S, dV, dA, dAv = (zeros(batch, (nv, 6), td.dtype) for _ in range(4))  # per column: ʳS, ∂V/∂q, ∂A/∂q, ∂A/∂q̇
    pose: list[PluckerTransform] = []  # ʳM_i: body i's pose in its root body (body → root coordinates)
    v: list[np.ndarray] = []
    a: list[np.ndarray] = []
    Ic: list[np.ndarray] = []  # composite inertia, rate, momentum and force, in r
    Bc: list[np.ndarray] = []
    hc: list[np.ndarray] = []
    Fc: list[np.ndarray] = []
    cols = [slice(model.idx_v[i], model.idx_v[i] + model.nvs[i]) for i in range(nb)]

    # forward: poses, ʳS, ʳv, ʳa, the body inertias, momenta, forces and rates, and the columns' ∂V, ∂A
    for i in range(nb):
        lam = parents[i]
        pM = td.pose_in_parent(q, i)
        if lam == -1:  # a root body: its own coordinates; the world's acceleration −g seen from it
            P = PluckerTransform._wrap(np.eye(3, dtype=td.dtype), np.zeros(3, dtype=td.dtype), None, None)
            v_lam = zeros(batch, (6,), td.dtype)
            a_lam = np.broadcast_to(pM.inverse().apply(a0).vector, batch + (6,))
        else:
            P = pM if parents[lam] == -1 else pose[lam] @ pM
            v_lam, a_lam = v[lam], a[lam]
        pose.append(P)
        Sc = expand(P).apply(SpatialMotion._wrap(td.S[i].T, None)).vector  # (..., nv_i, 6)
        S[..., cols[i], :] = Sc
        vJ = np.einsum("...k,...kj->...j", qd[..., cols[i]], Sc)
        v_i = v_lam + vJ
        a_i = a_lam + np.einsum("...k,...kj->...j", qdd[..., cols[i]], Sc) + crm_apply(v_i, vJ)
        I = P.apply(td.I[i]).matrix()
        h = np.einsum("...ij,...j->...i", I, v_i)
        f = np.einsum("...ij,...j->...i", I, a_i) + crf_apply(v_i, h)
        if f_ext is not None:
            f = f - P.apply(SpatialForce._wrap(f_ext[..., i, :], None)).vector
        v.append(v_i)
        a.append(a_i)
        Ic.append(np.broadcast_to(I, batch + (6, 6)))
        vx = _crm_matrix(v_i)
        Bc.append(-vx.swapaxes(-1, -2) @ I - I @ vx)  # [v]×* I − I [v]×
        hc.append(h)
        Fc.append(f)
        dV[..., cols[i], :] = crm_apply(v_lam[..., None, :], Sc)
        dA[..., cols[i], :] = crm_apply(a_lam[..., None, :], Sc) + crm_apply(v_lam[..., None, :], dV[..., cols[i], :])
        dAv[..., cols[i], :] = dV[..., cols[i], :] + crm_apply(v_i[..., None, :], Sc)

    dq, dv = zeros(batch, (nv, nv), td.dtype), zeros(batch, (nv, nv), td.dtype)
    # backward: with i's composites complete, the rows of i against its support's columns, and the rows
    # of i's strict ancestors against i's columns
    for i in range(nb - 1, -1, -1):
        lam, rows = parents[i], cols[i]
        D = Bc[i] + _momentum_cross(hc[i])
        dofs: list[int] = []
        k = i
        while k != -1:
            dofs.extend(range(model.idx_v[k], model.idx_v[k] + model.nvs[k]))
            k = parents[k]
        support = np.array(dofs, dtype=np.intp)  # i's dofs first, then its ancestors'
        Si = S[..., rows, :]
        ar, br = Si @ Ic[i], Si @ D  # rows (I^C S_i)ᵀ and (D^Cᵀ S_i)ᵀ
        dq[..., rows, support] = ar @ dA[..., support, :].swapaxes(-1, -2) + br @ dV[..., support, :].swapaxes(-1, -2)
        dv[..., rows, support] = ar @ dAv[..., support, :].swapaxes(-1, -2) + br @ S[..., support, :].swapaxes(-1, -2)
        if lam == -1:
            continue
        ancestors = support[model.nvs[i]:]
        Fq = (crf_apply(Si, Fc[i][..., None, :]) + dA[..., rows, :] @ Ic[i] + dV[..., rows, :] @ D.swapaxes(-1, -2))
        Fv = dAv[..., rows, :] @ Ic[i] + Si @ D.swapaxes(-1, -2)
        dq[..., ancestors, rows] = S[..., ancestors, :] @ Fq.swapaxes(-1, -2)
        dv[..., ancestors, rows] = S[..., ancestors, :] @ Fv.swapaxes(-1, -2)
        Ic[lam] = Ic[lam] + Ic[i]
        Bc[lam] = Bc[lam] + Bc[i]
        hc[lam] = hc[lam] + hc[i]
        Fc[lam] = Fc[lam] + Fc[i]
    return dq, dv


def generalized_gravity_derivatives(model: Model, q: np.ndarray) -> np.ndarray:
    """``∂g/∂q`` `(..., nv, nv)` of the generalized gravity ``g(q) = RNEA(q, 0, 0)`` on a checked ``q``::

        ∂g/∂q = ∂τ/∂q |_{q̇ = q̈ = 0}

    (Pinocchio's ``computeGeneralizedGravityDerivatives``; the analytical algorithm of the module
    docstring at rest, where only the base acceleration −g drives the bodies.)
    """
    zero = np.zeros(q.shape[:-1] + (model.nv,), dtype=q.dtype)
    return rnea_partials(model, q, zero, zero)[0]


def static_torque_derivatives(model: Model, q: np.ndarray, f_ext: np.ndarray) -> np.ndarray:
    """``∂τ_s/∂q`` `(..., nv, nv)` of the static torque ``τ_s(q) = g(q) − Σ_i J_iᵀ f_i`` on checked arrays::

        τ_s(q) = RNEA(q, 0, 0, f_ext),    ∂τ_s/∂q = ∂τ/∂q |_{q̇ = q̈ = 0}

    ``f_ext`` `(..., nb, 6)`: body-frame forces ``[n; f]``, held fixed in their bodies as q moves
    (Pinocchio's ``computeStaticTorqueDerivatives`` with forces in the joint frames).
    """
    batch = np.broadcast_shapes(q.shape[:-1], f_ext.shape[:-2])
    dtype = np.result_type(q, f_ext)
    zero = np.zeros(batch + (model.nv,), dtype=dtype)
    return rnea_partials(model, q, zero, zero, f_ext)[0]


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
    dq, dv = rnea_partials(model, q, qd, qdd, f_ext, gravity)
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
                             ref: ReferenceFrame, point: np.ndarray | None = None) -> list[np.ndarray]:
    """``[∂v_f/∂q, ∂v_f/∂q̇]`` and, with ``qdd``, ``[∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈]``, each `(..., 6, nv)`.

    With ``point`` `(..., 3)` (in the frame's coordinates): those of the frame moved to that point, its
    orientation kept (``⁰M_f`` followed by the translation ``point``; the same in WORLD).

    In world coordinates (``⁰S_k``: joint k's columns carried to the world, ``⁰v_k`` body k's velocity),
    the frame's body b has ``⁰v_b = Σ ⁰S_i q̇_i`` and ``⁰a_b = Σ ⁰S_i q̈_i + ⁰v_i × ⁰S_i q̇_i`` over its
    support; moving joint k along column s = ``⁰S_kc`` turns every ``⁰S_i`` below k by ``s ×``::

        ∂⁰v_b/∂q_kc = s × (⁰v_b − ⁰v_λ(k))
        ∂⁰a_b/∂q_kc = Σ_{i ⪰ k} s × ⁰S_i q̈_i + (δ⁰v_i × ⁰S_i + ⁰v_i × (s × ⁰S_i)) q̇_i,   δ⁰v_i = s × (⁰v_i − ⁰v_λ(k))
        ∂⁰a_b/∂q̇_kc = Σ_{i ⪰ k} (s × ⁰S_i) q̇_i + ⁰v_k × s,       ∂⁰v_b/∂q̇ = ∂⁰a_b/∂q̈ = ⁰J

    then LOCAL ``ᶠy = ᶠX_0 ⁰y`` (``δᶠy = ᶠX_0 δ⁰y − (ᶠX_0 s) × ᶠy``) and LOCAL_WORLD_ALIGNED
    ``blkdiag(R_f, R_f) ᶠy`` (``+ [ᶠω_s]×`` on each half before rotating), as ``fd.frame_velocity``.
    """
    from .jacobians import support, world_columns
    from .kinematics import body_at, forward_kinematics, frame_pose, motion_at

    batch, dtype = batch_dtype(q, qd, qdd)
    td = TreeData(model, dtype)
    kin = forward_kinematics(model, q, qd, None)
    nv = model.nv
    body = model.frames[fid].body
    sup = support(model, body)
    W = world_columns(model, td, kin.placements, batch)  # (..., nv, 6)
    assert kin.velocities is not None
    v0 = {i: body_at(kin.placements, i).apply(motion_at(kin.velocities, i)).vector for i in sup}
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
        if point is not None:
            p = np.broadcast_to(np.asarray(point, dtype=dtype), batch + (3,))
            eye = np.broadcast_to(np.eye(3, dtype=dtype), batch + (3, 3))
            oMf = oMf @ PluckerTransform._wrap(eye, p, None, None)

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


def frame_velocity_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, frame: int,
                               reference: ReferenceFrame) -> tuple[np.ndarray, np.ndarray]:
    """``(∂v_f/∂q, ∂v_f/∂q̇)`` `(..., 6, nv)` (:func:`frame_motion_derivatives`; public:
    :func:`featherdyn.frame_velocity_derivatives`)."""
    dv_dq, dv_dv = frame_motion_derivatives(model, q, qd, None, frame, reference)
    return dv_dq, dv_dv


def frame_acceleration_derivatives(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, frame: int,
                                   reference: ReferenceFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈)`` `(..., 6, nv)` (:func:`frame_motion_derivatives`; public:
    :func:`featherdyn.frame_acceleration_derivatives`)."""
    _, _, da_dq, da_dv, da_da = frame_motion_derivatives(model, q, qd, qdd, frame, reference)
    return da_dq, da_dv, da_da
