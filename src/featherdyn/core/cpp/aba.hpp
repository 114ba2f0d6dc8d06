// Forward dynamics by the Articulated-Body Algorithm (RBDA table 7.1; chapter §8 and
// appendix F.5; reference: featherdyn/algorithms/aba.py), gravity as a₀ = −g:
//
//   pass 1 (i = 0 … nb−1):  v_i = X_up[i] v_λ(i) + S_i q̇_i,   c_i = v_i × S_i q̇_i
//                           I^A_i = I_i,   p^A_i = v_i ×* I_i v_i − f_i^ext
//   pass 2 (i = nb−1 … 0):  U_i = I^A_i S_i,   D_i = S_iᵀ U_i + diag(armature_i),   u_i = τ_i − S_iᵀ p^A_i
//                           I^a = I^A_i − U_i D_i⁻¹ U_iᵀ,   p^a = p^A_i + I^a c_i + U_i D_i⁻¹ u_i
//                           I^A_λ(i) += X_up[i]ᵀ I^a X_up[i],   p^A_λ(i) += X_up[i]ᵀ p^a
//   pass 3 (i = 0 … nb−1):  a' = X_up[i] a_λ(i) + c_i
//                           q̈_i = D_i⁻¹ (u_i − U_iᵀ a'),   a_i = a' + S_i q̈_i
//
// D_i is inverted by Cholesky; a pivot ≤ mv.singular_tol (1e-14 × the largest body-inertia
// entry, the reference's rule) makes the mass matrix singular: the kernel returns the joint.
#pragma once

#include <cmath>

#include "pack.hpp"
#include "rnea.hpp"

namespace fdcore {

template <class S>
struct AbaWork {
  std::vector<Xform<S>> X_up;
  std::vector<Motion<S>> v, c, a;
  std::vector<ArticulatedInertia<S>> IA;
  std::vector<Force<S>> pA;
  std::vector<Force<S>> U;  // 6 columns per body
  std::vector<S> Dinv;      // 36 per body, row stride 6
  std::vector<S> u;         // 6 per body
  void resize(size_t nb) {
    if (X_up.size() < nb) {
      X_up.resize(nb), v.resize(nb), c.resize(nb), a.resize(nb), IA.resize(nb), pA.resize(nb);
      U.resize(6 * nb), Dinv.resize(36 * nb), u.resize(6 * nb);
    }
  }
};

// Dinv = D⁻¹ for a symmetric positive definite (k, k) D (row stride 6) by Cholesky, D = L Lᵀ.
// Returns false when a pivot is ≤ tol (D singular; Dinv undefined) — in any lane, for a Pack.
template <class S>
inline bool spd_inverse(const S* D, int k, S* Dinv, double tol) {
  using std::sqrt;
  if (k == 1) {
    if (lanes_le(D[0], tol)) return false;
    Dinv[0] = S(1.0) / D[0];
    return true;
  }
  S L[36];
  for (int j = 0; j < k; ++j) {
    S d = D[7 * j];
    for (int m = 0; m < j; ++m) d -= L[6 * j + m] * L[6 * j + m];
    if (lanes_le(d, tol)) return false;
    L[7 * j] = sqrt(d);
    for (int r = j + 1; r < k; ++r) {
      S x = D[6 * r + j];
      for (int m = 0; m < j; ++m) x -= L[6 * r + m] * L[6 * j + m];
      L[6 * r + j] = x / L[7 * j];
    }
  }
  S Li[36];  // L⁻¹, lower triangular
  for (int j = 0; j < k; ++j) {
    Li[7 * j] = S(1.0) / L[7 * j];
    for (int r = j + 1; r < k; ++r) {
      S x(0.0);
      for (int m = j; m < r; ++m) x -= L[6 * r + m] * Li[6 * m + j];
      Li[6 * r + j] = x / L[7 * r];
    }
  }
  for (int r = 0; r < k; ++r) {  // D⁻¹ = L⁻ᵀ L⁻¹, exactly symmetric
    for (int c = r; c < k; ++c) {
      S x(0.0);
      for (int m = c; m < k; ++m) x += Li[6 * m + r] * Li[6 * m + c];
      Dinv[6 * r + c] = Dinv[6 * c + r] = x;
    }
  }
  return true;
}

// I -= x yᵀ for 6-vectors x, y (only the blocks A, B, C of [[A, B], [Bᵀ, C]]).
template <class S>
inline void subtract_outer(ArticulatedInertia<S>& I, const Force<S>& x, const Force<S>& y) {
  const S xn[3] = {x.n.x, x.n.y, x.n.z}, xf[3] = {x.f.x, x.f.y, x.f.z};
  const S yn[3] = {y.n.x, y.n.y, y.n.z}, yf[3] = {y.f.x, y.f.y, y.f.z};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      I.A(r, c) -= xn[r] * yn[c];
      I.B(r, c) -= xn[r] * yf[c];
      I.C(r, c) -= xf[r] * yf[c];
    }
  }
}

// Pass 3 at joint i: x_i = D_i⁻¹ (u_i − U_iᵀ a') into x (at i's dofs); returns a_i = a' + S_i x_i.
template <class S>
FD_INLINE Motion<S> solve_joint(const ModelView& mv, const AbaWork<S>& w, int i, const Motion<S>& a_prime, S* x) {
  const int k = mv.nv_i[i];
  const Force<S>* U = w.U.data() + 6 * i;
  const S* Dinv = w.Dinv.data() + 36 * i;
  const S* u = w.u.data() + 6 * i;
  S rhs[6];
  for (int r = 0; r < k; ++r) rhs[r] = u[r] - dot(a_prime, U[r]);
  S* x_i = x + mv.idx_v[i];
  for (int r = 0; r < k; ++r) {
    S acc(0.0);
    for (int m = 0; m < k; ++m) acc += Dinv[6 * r + m] * rhs[m];
    x_i[r] = acc;
  }
  return a_prime + S_times(mv, i, x);
}

// q̈ (nv,) for (q, q̇, τ); f_ext (nb, 6) body-frame forces or nullptr. Returns −1, or the
// first joint (from the leaves) whose D_i is singular (in some lane, for a Pack); then
// D_singular (36, row stride 6), if given, receives that D_i and q̈ is undefined.
template <class S>
int aba(const ModelView& mv, const S* q, const S* qd, const S* tau, const S* f_ext, bool gravity, S* qdd,
        S* D_singular = nullptr) {
  const int nb = mv.nb;
  AbaWork<S>& w = thread_workspace<AbaWork<S>>(nb);
  Xform<S>* X_up = w.X_up.data();
  Motion<S>* v = w.v.data();
  Motion<S>* c = w.c.data();
  Motion<S>* a = w.a.data();
  ArticulatedInertia<S>* IA = w.IA.data();
  Force<S>* pA = w.pA.data();
  const Motion<S> a0 = base_acceleration<S>(mv, gravity);

  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    X_up[i] = joint_X_up(mv, i, q);
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up[i].apply(v[lam]) + vJ;
    c[i] = cross_motion(v[i], vJ);
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    IA[i].set_rigid(I);
    pA[i] = cross_force(v[i], I * v[i]);
    if (f_ext) {
      const S* fx = f_ext + 6 * i;
      pA[i] = pA[i] - Force<S>{{fx[0], fx[1], fx[2]}, {fx[3], fx[4], fx[5]}};
    }
  }

  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], k = mv.nv_i[i];
    Force<S>* U = w.U.data() + 6 * i;
    S* Dinv = w.Dinv.data() + 36 * i;
    S* u = w.u.data() + 6 * i;
    S D[36] = {};
    for (int col = 0; col < k; ++col) U[col] = IA[i] * S_col<S>(mv, i, col);
    for (int col = 0; col < k; ++col) {
      S Sr_U[6];
      St_times(mv, i, U[col], Sr_U);
      for (int r = 0; r < k; ++r) D[6 * r + col] = Sr_U[r];
    }
    if (mv.armature)  // D_i = S_iᵀ IA_i S_i + diag(armature_i)
      for (int r = 0; r < k; ++r) D[7 * r] += S(mv.armature[mv.idx_v[i] + r]);
    St_times(mv, i, pA[i], u);
    for (int r = 0; r < k; ++r) u[r] = tau[mv.idx_v[i] + r] - u[r];
    if (!spd_inverse(D, k, Dinv, mv.singular_tol)) {
      if (D_singular)
        for (int e = 0; e < 36; ++e) D_singular[e] = D[e];
      return i;
    }
    if (lam == -1) continue;
    // U D⁻¹, column by column
    Force<S> UD[6];
    for (int col = 0; col < k; ++col) {
      const S z(0.0);
      UD[col] = {{z, z, z}, {z, z, z}};
      for (int r = 0; r < k; ++r) UD[col] += Force<S>{Dinv[6 * r + col] * U[r].n, Dinv[6 * r + col] * U[r].f};
    }
    ArticulatedInertia<S> Ia = IA[i];
    for (int col = 0; col < k; ++col) subtract_outer(Ia, UD[col], U[col]);
    Force<S> pa = pA[i] + Ia * c[i];
    for (int col = 0; col < k; ++col) pa += Force<S>{u[col] * UD[col].n, u[col] * UD[col].f};
    IA[lam] += transform_to_parent(X_up[i], Ia);
    pA[lam] += X_up[i].apply_transpose(pa);
  }

  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    a[i] = solve_joint(mv, w, i, X_up[i].apply(lam == -1 ? a0 : a[lam]) + c[i], qdd);
  }
  return -1;
}

// x = M(q)⁻¹ b (nv,) on the factorisation the last aba() call on this thread left in its workspace (X_up, U_i, D_i⁻¹
// of the same q): ABA's passes 2 and 3 without velocities, gravity or inertias — the articulated inertias do not
// depend on the right-hand side:
//
//   pass 2 (i = nb−1 … 0):  u_i = b_i − S_iᵀ p_i,   p_λ(i) += X_up[i]ᵀ (p_i + U_i D_i⁻¹ u_i)      (p = 0 first)
//   pass 3 (i = 0 … nb−1):  a' = X_up[i] a_λ(i),   x_i = D_i⁻¹ (u_i − U_iᵀ a'),   a_i = a' + S_i x_i
template <class S>
void aba_resolve(const ModelView& mv, const S* b, S* x) {
  const int nb = mv.nb;
  AbaWork<S>& w = thread_workspace<AbaWork<S>>(nb);
  const S z(0.0);
  const Force<S> zero_f{{z, z, z}, {z, z, z}};
  const Motion<S> zero_m{{z, z, z}, {z, z, z}};
  for (int i = 0; i < nb; ++i) w.pA[i] = zero_f;
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], k = mv.nv_i[i];
    const Force<S>* U = w.U.data() + 6 * i;
    const S* Dinv = w.Dinv.data() + 36 * i;
    S* u = w.u.data() + 6 * i;
    St_times(mv, i, w.pA[i], u);
    for (int r = 0; r < k; ++r) u[r] = b[mv.idx_v[i] + r] - u[r];
    if (lam == -1) continue;
    Force<S> pa = w.pA[i];
    for (int r = 0; r < k; ++r) {
      S Du(0.0);
      for (int m = 0; m < k; ++m) Du += Dinv[6 * r + m] * u[m];
      pa += Force<S>{Du * U[r].n, Du * U[r].f};
    }
    w.pA[lam] += w.X_up[i].apply_transpose(pa);
  }
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    w.a[i] = solve_joint(mv, w, i, lam == -1 ? zero_m : w.X_up[i].apply(w.a[lam]), x);
  }
}

}  // namespace fdcore
