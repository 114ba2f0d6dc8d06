// The joint-space mass matrix by the Composite Rigid Body Algorithm (chapter §5.3; RBDA
// table 6.2; reference: featherdyn/algorithms/crba.py), with every quantity of a tree expressed
// in its root body's coordinates (r): the body frame of the tree's first body, which moves with
// the robot, so M stays exact however far the robot is from the world origin:
//
//     ʳX_i = ʳX_λ(i) · ᵖX_i (pose of body i in the root body),   ʳS_i = ʳX_i S_i
//     I^C_i = ʳX_i* I_i ʳX_i⁻¹ + Σ_{children j} I^C_j                     (i = nb−1 … 0)
//     F = I^C_i ʳS_i,   M_ii = ʳS_iᵀ F,   M_ji = ʳS_jᵀ F   (j = λ(i), λ(λ(i)), … ),   M_ij = M_jiᵀ
//     M += diag(armature)                                                     (reflected rotor inertia)
//
// The same sums as the body-coordinate recursion (M_ij = S_iᵀ ⁱX_j* I^C_j S_j is invariant under a
// change of coordinates), but an ancestor costs one 6-vector dot product per column instead of a
// spatial transform of F.
#pragma once

#include "rnea.hpp"

namespace fdcore {

template <class S>
struct CrbaWork {
  std::vector<Mat3<S>> R;         // ʳR_i: body i's axes in its root body
  std::vector<Vec3<S>> p;         // ʳp_i: body i's origin in its root body
  std::vector<RigidInertia<S>> IC;
  std::vector<Motion<S>> Sr;      // ʳS_i, column c of body i at idx_v[i] + c
  void resize(size_t nb) {
    if (R.size() < nb) R.resize(nb), p.resize(nb), IC.resize(nb), Sr.resize(6 * nb);
  }
};

// M (nv, nv), full and exactly symmetric.
template <class S>
void crba(const ModelView& mv, const S* q, S* M) {
  const int nb = mv.nb, nv = mv.nv;
  CrbaWork<S>& w = thread_workspace<CrbaWork<S>>(nb);
  Mat3<S>* R = w.R.data();
  Vec3<S>* p = w.p.data();
  RigidInertia<S>* IC = w.IC.data();
  Motion<S>* Sr = w.Sr.data();
  // (in passes, as in rnea.hpp: only the second waits on the parent at every body)
  for (int i = 0; i < nb; ++i)  // each body's pose in its parent
    if (mv.parent[i] != -1) pose_in_parent(mv, i, q, R[i], p[i]);
  for (int i = 0; i < nb; ++i) {  // composed to root-body coordinates (a child of the root keeps its own)
    const int lam = mv.parent[i];
    if (lam == -1 || mv.parent[lam] == -1) continue;
    p[i] = p[lam] + R[lam] * p[i];
    R[i] = R[lam] * R[i];
  }
  for (int i = 0; i < nb; ++i) {
    const int iv = mv.idx_v[i];
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    if (mv.parent[i] == -1) {  // a root body: its own coordinates
      IC[i] = I;
      for (int c = 0; c < mv.nv_i[i]; ++c) Sr[iv + c] = S_col<S>(mv, i, c);
      continue;
    }
    IC[i] = transform_to_parent(Xform<S>{R[i].transpose(), p[i]}, I);
    for (int c = 0; c < mv.nv_i[i]; ++c) {
      const Motion<S> s = S_col<S>(mv, i, c);
      const Vec3<S> wr = R[i] * s.w;
      Sr[iv + c] = {wr, R[i] * s.v + cross(p[i], wr)};
    }
  }
  // I^C_λ += I^C_i; along a serial stretch (λ(i) = i − 1) the running sum stays in registers instead of a
  // store and a reload per body (as in rnea.hpp)
  RigidInertia<S> IC_i = nb > 0 ? IC[nb - 1] : RigidInertia<S>{};
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    if (lam == i - 1 && lam != -1) {
      IC[lam] = IC_i = IC[lam] + IC_i;
    } else {
      if (lam != -1) IC[lam] = IC[lam] + IC_i;
      if (i > 0) IC_i = IC[i - 1];
    }
  }
  for (int k = 0; k < nv * nv; ++k) M[k] = S(0.0);

  for (int i = 0; i < nb; ++i) {
    const int iv = mv.idx_v[i], ki = mv.nv_i[i];
    for (int c = 0; c < ki; ++c) {
      const Force<S> F = IC[i] * Sr[iv + c];
      for (int r = 0; r <= c; ++r)  // M_ii: the upper triangle, mirrored
        M[(iv + r) * nv + iv + c] = M[(iv + c) * nv + iv + r] = dot(Sr[iv + r], F);
      if (mv.armature) M[(iv + c) * nv + iv + c] += S(mv.armature[iv + c]);
      for (int j = mv.parent[i]; j != -1; j = mv.parent[j]) {
        const int jv = mv.idx_v[j];
        for (int r = 0; r < mv.nv_i[j]; ++r) M[(jv + r) * nv + iv + c] = M[(iv + c) * nv + jv + r] = dot(Sr[jv + r], F);
      }
    }
  }
}

}  // namespace fdcore
