// Forward kinematics (chapter §8.1, RBDA §5.3; reference: featherdyn/algorithms/kinematics.py):
//
//     ᵖM_i = Xtree_i · M_J(q_i),      X_up[i] = (ᵖM_i)⁻¹,      ⁰M_i = ⁰M_λ(i) · ᵖM_i
//     v_i  = X_up[i] v_λ(i) + S_i q̇_i
//     a_i  = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i          (no gravity)
#pragma once

#include "joints.hpp"
#include "scratch.hpp"

namespace fdcore {

// World placements ⁰M_i as homogeneous matrices H (nb, 4, 4); placements in the parent body
// ᵖM_i (nb, 4, 4) when Hp is given; body velocities vel and accelerations acc (nb, 6) in body
// coordinates when qd (and qdd) are given (else nullptr).
template <class S>
struct FkWork {
  std::vector<Mat3<S>> oR;
  std::vector<Vec3<S>> op;
  std::vector<Motion<S>> v, a;
  void resize(size_t nb) {
    if (oR.size() < nb) oR.resize(nb), op.resize(nb), v.resize(nb), a.resize(nb);
  }
};

// [[R, p], [0, 1]] row-major into H (16,)
template <class S>
inline void write_homogeneous(const Mat3<S>& R, const Vec3<S>& p, S* H) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) H[4 * r + c] = R(r, c);
  }
  H[3] = p.x;
  H[7] = p.y;
  H[11] = p.z;
  H[12] = H[13] = H[14] = S(0.0);
  H[15] = S(1.0);
}

// Body i's pose (R, p) in its parent and its world placement oR[i], op[i] (its parent's already set).
template <class S>
inline void place_body(const ModelView& mv, int i, const S* q, Mat3<S>* oR, Vec3<S>* op, Mat3<S>& R, Vec3<S>& p) {
  const int lam = mv.parent[i];
  pose_in_parent(mv, i, q, R, p);
  if (lam == -1) {
    oR[i] = R;
    op[i] = p;
  } else {
    oR[i] = oR[lam] * R;
    op[i] = op[lam] + oR[lam] * p;
  }
}

template <class S>
void forward_kinematics(const ModelView& mv, const S* q, const S* qd, const S* qdd, S* H, S* vel, S* acc,
                        S* Hp = nullptr) {
  const int nb = mv.nb;
  FkWork<S>& w = thread_workspace<FkWork<S>>(nb);
  Mat3<S>* oR = w.oR.data();
  Vec3<S>* op = w.op.data();
  Motion<S>* v = w.v.data();
  Motion<S>* a = w.a.data();
  // the poses in the parents first (independent: sin, cos), then the recursion (as in rnea.hpp)
  for (int i = 0; i < nb; ++i) pose_in_parent(mv, i, q, oR[i], op[i]);
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    const Mat3<S> R = oR[i];  // ᵖM_i, composed in place into ⁰M_i
    const Vec3<S> p = op[i];
    if (lam != -1) {
      oR[i] = oR[lam] * R;
      op[i] = op[lam] + oR[lam] * p;
    }
    write_homogeneous(oR[i], op[i], H + 16 * i);
    if (Hp) write_homogeneous(R, p, Hp + 16 * i);
    if (qd == nullptr) continue;
    const Xform<S> X_up{R.transpose(), p};
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up.apply(v[lam]) + vJ;
    const Motion<S>& vi = v[i];
    S* out = vel + 6 * i;
    out[0] = vi.w.x, out[1] = vi.w.y, out[2] = vi.w.z, out[3] = vi.v.x, out[4] = vi.v.y, out[5] = vi.v.z;
    if (qdd == nullptr) continue;
    const Motion<S> aJ = S_times(mv, i, qdd) + cross_motion(vi, vJ);
    a[i] = lam == -1 ? aJ : X_up.apply(a[lam]) + aJ;
    const Motion<S>& ai = a[i];
    out = acc + 6 * i;
    out[0] = ai.w.x, out[1] = ai.w.y, out[2] = ai.w.z, out[3] = ai.v.x, out[4] = ai.v.y, out[5] = ai.v.z;
  }
}

}  // namespace fdcore
