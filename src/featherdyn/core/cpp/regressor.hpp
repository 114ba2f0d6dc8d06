// The joint torque regressor (RBDA §2.13; Atkeson, An & Hollerbach 1986;
// Pinocchio's computeJointTorqueRegressor): RNEA is linear in each body's ten dynamic parameters
//
//     π_i = [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]     (I about the body origin)
//
// so τ = Y(q, q̇, q̈) π with π the bodies' parameters stacked. The forward pass is RNEA's (gravity as
// a₀ = −g); body i's force f_i = I_i a_i + v_i ×* I_i v_i = Y_i π_i, column k of Y_i being that force
// for the unit parameter vector e_k; the backward pass carries each column to the joints that support
// body i:  Y[joint j, 10 i + k] = S_jᵀ ʲX_i* Y_i[:, k]   (j = i, λ(i), λ(λ(i)), …).
#pragma once

#include "rnea.hpp"

namespace fdcore {

// The rigid inertia whose dynamic parameters are the unit vector e_k.
template <class S>
inline RigidInertia<S> unit_parameter(int k) {
  const S z(0.0), one(1.0);
  RigidInertia<S> I{z, {z, z, z}, {z, z, z, z, z, z}};
  switch (k) {
    case 0: I.m = one; break;
    case 1: I.h.x = one; break;
    case 2: I.h.y = one; break;
    case 3: I.h.z = one; break;
    case 4: I.I.xx = one; break;
    case 5: I.I.xy = one; break;
    case 6: I.I.yy = one; break;
    case 7: I.I.xz = one; break;
    case 8: I.I.yz = one; break;
    default: I.I.zz = one; break;
  }
  return I;
}

// Y (nv, 10 nb) row-major.
template <class S>
void joint_torque_regressor(const ModelView& mv, const S* q, const S* qd, const S* qdd, S* Y) {
  const int nb = mv.nb, nv = mv.nv, ncol = 10 * nb;
  RneaWork<S>& w = thread_workspace<RneaWork<S>>(nb);
  Xform<S>* X_up = w.X_up.data();
  Motion<S>* v = w.v.data();
  Motion<S>* a = w.a.data();
  const Motion<S> a0 = base_acceleration<S>(mv, true);
  for (int k = 0; k < nv * ncol; ++k) Y[k] = S(0.0);
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    X_up[i] = joint_X_up(mv, i, q);
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up[i].apply(v[lam]) + vJ;
    a[i] = X_up[i].apply(lam == -1 ? a0 : a[lam]) + S_times(mv, i, qdd) + cross_motion(v[i], vJ);
  }
  S col[6];
  for (int i = 0; i < nb; ++i) {
    for (int k = 0; k < 10; ++k) {
      const RigidInertia<S> I = unit_parameter<S>(k);
      Force<S> F = I * a[i] + cross_force(v[i], I * v[i]);
      for (int j = i;;) {
        St_times(mv, j, F, col);
        for (int r = 0; r < mv.nv_i[j]; ++r) Y[(mv.idx_v[j] + r) * ncol + 10 * i + k] = col[r];
        if (mv.parent[j] == -1) break;
        F = X_up[j].apply_transpose(F);
        j = mv.parent[j];
      }
    }
  }
}

}  // namespace fdcore
