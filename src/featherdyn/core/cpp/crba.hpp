// The joint-space mass matrix by the Composite Rigid Body Algorithm (chapter §5.3; RBDA
// table 6.2; reference: featherdyn/algorithms/crba.py), in body coordinates:
//
//     I^C_i = I_i + Σ_{children j} X_up[j]ᵀ I^C_j X_up[j]      (i = nb−1 … 0)
//     F = I^C_i S_i,   M_ii = S_iᵀ F
//     j = i;  while λ(j) ≠ −1:  F = X_up[j]ᵀ F;  j = λ(j);  M_ji = S_jᵀ F;  M_ij = M_jiᵀ
//     M += diag(armature)                                   (reflected rotor inertia)
#pragma once

#include "rnea.hpp"

namespace fdcore {

template <class S>
struct CrbaWork {
  std::vector<Xform<S>> X_up;
  std::vector<RigidInertia<S>> IC;
  void resize(size_t nb) {
    if (X_up.size() < nb) X_up.resize(nb), IC.resize(nb);
  }
};

// M (nv, nv), full and exactly symmetric.
template <class S>
void crba(const ModelView& mv, const S* q, S* M) {
  const int nb = mv.nb, nv = mv.nv;
  CrbaWork<S>& w = thread_workspace<CrbaWork<S>>(nb);
  Xform<S>* X_up = w.X_up.data();
  RigidInertia<S>* IC = w.IC.data();
  for (int i = 0; i < nb; ++i) {
    X_up[i] = joint_X_up(mv, i, q);
    IC[i] = body_inertia<S>(mv, i);
  }
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    if (lam != -1) IC[lam] = IC[lam] + transform_to_parent(X_up[i], IC[i]);
  }
  for (int k = 0; k < nv * nv; ++k) M[k] = S(0.0);

  Force<S> F[6];
  S col[6];
  for (int i = 0; i < nb; ++i) {
    const int iv = mv.idx_v[i], ki = mv.nv_i[i];
    for (int c = 0; c < ki; ++c) F[c] = IC[i] * S_col<S>(mv, i, c);
    for (int c = 0; c < ki; ++c) {  // M_ii = S_iᵀ I^C_i S_i: the upper triangle, mirrored
      St_times(mv, i, F[c], col);
      for (int r = 0; r <= c; ++r) M[(iv + r) * nv + iv + c] = M[(iv + c) * nv + iv + r] = col[r];
      if (mv.armature) M[(iv + c) * nv + iv + c] += S(mv.armature[iv + c]);
    }
    int j = i;
    while (mv.parent[j] != -1) {
      for (int c = 0; c < ki; ++c) F[c] = X_up[j].apply_transpose(F[c]);
      j = mv.parent[j];
      const int jv = mv.idx_v[j], kj = mv.nv_i[j];
      for (int c = 0; c < ki; ++c) {
        St_times(mv, j, F[c], col);
        for (int r = 0; r < kj; ++r) M[(jv + r) * nv + iv + c] = M[(iv + c) * nv + jv + r] = col[r];
      }
    }
  }
}

}  // namespace fdcore
