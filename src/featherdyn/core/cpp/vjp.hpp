// Vector–Jacobian products of inverse and forward dynamics in O(nb) (reference: featherdyn/algorithms/vjp.py;
// the derivation: docs/derivatives.md, "Vector–Jacobian products"): the gradient of the scalar wᵀ τ(q, q̇, q̈) —
// a row of the Jacobians of RNEA, without forming them — and of wᵀ q̈(q, q̇, τ) through ABA.
//
// wᵀ τ = Σ_j u_j · f_j, the bodies' forces f_j paired with the velocities u_j the joints give at rates w (the virtual
// power). Moving q_k turns subtree(i) of its joint i rigidly, which leaves the pairing within the subtree unchanged
// but for what the ancestors keep: the parent's motions v_λ, a_λ (with gravity, a₀ = −g) and u_λ. With the
// subtree's sums over j ∈ subtree(i) (body coordinates, carried up as forces are)
//
//     F_i = Σ f_j (RNEA's),   H_i = Σ I_j u_j,   D_i = Σ u_j ×* I_j v_j + I_j (v_j × u_j) − v_j ×* I_j u_j
//
// each column k of joint i gets
//
//     ∂(wᵀτ)/∂q_k = S_kᵀ (v_λ ×* (D_i + v_λ ×* H_i) − u_λ ×* F_i − a_λ ×* H_i)
//     ∂(wᵀτ)/∂q̇_k = −S_kᵀ (D_i + (v_λ + v_i) ×* H_i)
//     ∂(wᵀτ)/∂q̈_k = S_kᵀ H_i + armature_k w_k               (= (M w)_k)
//
// (∂/∂q along fd.integrate's tangent, as fd.rnea_derivatives). Forward dynamics by the implicit function theorem:
// RNEA(q, q̇, q̈) = τ at q̈ = ABA(q, q̇, τ), so with λ = M⁻¹ w
//
//     ∂(wᵀq̈)/∂q = −∂(λᵀτ)/∂q,   ∂(wᵀq̈)/∂q̇ = −∂(λᵀτ)/∂q̇   (at q̈),   ∂(wᵀq̈)/∂τ = λ
//
// And the mass matrix's, ∂⟨W, M(q)⟩/∂q for a matrix W (nv, nv): ⟨W, M⟩ = Σ_b Σ_{i, j ≼ b} W_ij S_iᵀ I_b S_j, and
// moving q_k (a column of joint c) turns subtree(c) rigidly, so only the pairs with a column i of an ancestor of c
// change: with W̃ = W + Wᵀ, u_{i,b} = Σ_{j ≼ b} W̃_ij S_j and F_{i,c} = Σ_{b ∈ subtree(c)} I_b u_{i,b},
//
//     ∂⟨W, M⟩/∂q_k = −S_kᵀ Σ_{i ≺ c} S_i ×* F_{i,c}
//
// one pass per column i down its joint's path and subtree and one up the subtree: O(Σ_i (depth_i + |subtree_i|)),
// the order of CRBA itself.
#pragma once

#include <vector>

#include "aba.hpp"
#include "joints.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

template <class S>
struct VjpWork {
  std::vector<Xform<S>> X_up;
  std::vector<Motion<S>> v, a, u, vp, ap, up;  // each body's v, a, u; its parent's, in its coordinates
  std::vector<Force<S>> F, H, D;
  void resize(size_t nb) {
    if (X_up.size() < nb)
      X_up.resize(nb), v.resize(nb), a.resize(nb), u.resize(nb), vp.resize(nb), ap.resize(nb), up.resize(nb),
          F.resize(nb), H.resize(nb), D.resize(nb);
  }
};

// (∂(wᵀτ)/∂q, ∂(wᵀτ)/∂q̇, ∂(wᵀτ)/∂q̈) (nv,) each, for τ = RNEA(q, q̇, q̈, f_ext); f_ext (nb, 6) or nullptr.
template <class S>
void rnea_vjp(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* w, const S* f_ext, bool gravity,
              S* g_q, S* g_v, S* g_a) {
  const int nb = mv.nb;
  VjpWork<S>& k = thread_workspace<VjpWork<S>>(nb);
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  const Motion<S> a0 = base_acceleration<S>(mv, gravity);
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    const Xform<S>& X = k.X_up[i] = joint_X_up(mv, i, q);
    const Motion<S> vJ = S_times(mv, i, qd);
    k.vp[i] = lam == -1 ? zero : X.apply(k.v[lam]);
    k.up[i] = lam == -1 ? zero : X.apply(k.u[lam]);
    k.ap[i] = X.apply(lam == -1 ? a0 : k.a[lam]);
    k.v[i] = k.vp[i] + vJ;
    k.u[i] = k.up[i] + S_times(mv, i, w);
    k.a[i] = k.ap[i] + S_times(mv, i, qdd) + cross_motion(k.v[i], vJ);
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    const Force<S> h = I * k.v[i];
    k.H[i] = I * k.u[i];
    k.F[i] = I * k.a[i] + cross_force(k.v[i], h);
    if (f_ext) {
      const S* fx = f_ext + 6 * i;
      k.F[i] = k.F[i] - Force<S>{{fx[0], fx[1], fx[2]}, {fx[3], fx[4], fx[5]}};
    }
    k.D[i] = cross_force(k.u[i], h) + I * cross_motion(k.v[i], k.u[i]) - cross_force(k.v[i], k.H[i]);
  }
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], at = mv.idx_v[i];
    const Force<S> turn = cross_force(k.vp[i], k.D[i] + cross_force(k.vp[i], k.H[i])) -
                          cross_force(k.up[i], k.F[i]) - cross_force(k.ap[i], k.H[i]);
    St_times(mv, i, turn, g_q + at);
    St_times(mv, i, k.D[i] + cross_force(k.vp[i] + k.v[i], k.H[i]), g_v + at);
    for (int c = 0; c < mv.nv_i[i]; ++c) g_v[at + c] = -g_v[at + c];
    St_times(mv, i, k.H[i], g_a + at);
    if (lam != -1) {
      k.F[lam] += k.X_up[i].apply_transpose(k.F[i]);
      k.H[lam] += k.X_up[i].apply_transpose(k.H[i]);
      k.D[lam] += k.X_up[i].apply_transpose(k.D[i]);
    }
  }
  if (mv.armature)
    for (int c = 0; c < mv.nv; ++c) g_a[c] = g_a[c] + S(mv.armature[c]) * w[c];
}

// (∂(wᵀq̈)/∂q, ∂(wᵀq̈)/∂q̇, ∂(wᵀq̈)/∂τ) (nv,) each, for q̈ = ABA(q, q̇, τ, f_ext). Returns −1, or the joint whose
// articulated inertia is singular (aba's).
template <class S>
int aba_vjp(const ModelView& mv, const S* q, const S* qd, const S* tau, const S* w, const S* f_ext, bool gravity,
            S* g_q, S* g_v, S* g_tau) {
  thread_local std::vector<S> qdd, Mw;
  const size_t nv = static_cast<size_t>(mv.nv);
  qdd.resize(nv), Mw.resize(nv);
  const int bad = aba<S>(mv, q, qd, tau, f_ext, gravity, qdd.data());
  if (bad >= 0) return bad;
  aba_resolve<S>(mv, w, g_tau);  // λ = M⁻¹ w on the same factorisation
  rnea_vjp<S>(mv, q, qd, qdd.data(), g_tau, f_ext, gravity, g_q, g_v, Mw.data());
  for (size_t c = 0; c < nv; ++c) g_q[c] = -g_q[c], g_v[c] = -g_v[c];
  return -1;
}

template <class S>
struct MassVjpWork {
  std::vector<Xform<S>> X_up;
  std::vector<Motion<S>> u, s;  // u_{i,b}; column i in body b's coordinates
  std::vector<Force<S>> F, acc;  // F_{i,b}; Σ_i S_i ×* F_{i,c}
  std::vector<S> row;            // W̃'s row i
  std::vector<char> below;       // b ∈ subtree of i's joint
  void resize(size_t nb) {
    if (X_up.size() < nb) X_up.resize(nb), u.resize(nb), s.resize(nb), F.resize(nb), acc.resize(nb), below.resize(nb);
  }
};

// ∂⟨W, M(q)⟩/∂q (nv,) along fd.integrate's tangent, for W (nv, nv) row-major (armature: no q in it).
template <class S>
void crba_vjp(const ModelView& mv, const S* q, const S* W, S* g) {
  const int nb = mv.nb, nv = mv.nv;
  MassVjpWork<S>& k = thread_workspace<MassVjpWork<S>>(nb);
  k.row.resize(static_cast<size_t>(nv));
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  const Force<S> none{{z, z, z}, {z, z, z}};
  for (int b = 0; b < nb; ++b) k.X_up[b] = joint_X_up(mv, b, q), k.acc[b] = none;
  for (int bi = 0; bi < nb; ++bi) {
    for (int ci = 0; ci < mv.nv_i[bi]; ++ci) {
      const int i = mv.idx_v[bi] + ci;
      for (int j = 0; j < nv; ++j) k.row[j] = W[i * nv + j] + W[j * nv + i];
      // u down the path to bi's parent (root first), then over the subtree with the column carried along
      int path[64], depth = 0;
      for (int b = mv.parent[bi]; b != -1 && depth < 64; b = mv.parent[b]) path[depth++] = b;
      auto down = [&](int b) {
        const int lam = mv.parent[b];
        k.u[b] = (lam == -1 ? zero : k.X_up[b].apply(k.u[lam])) + S_times(mv, b, k.row.data());
      };
      if (depth == 64) {  // (deeper than the path buffer: every body before bi, in order)
        for (int b = 0; b < bi; ++b) down(b);
      } else {
        for (int d = depth - 1; d >= 0; --d) down(path[d]);
      }
      for (int b = bi; b < nb; ++b) {
        k.below[b] = b == bi || (b > bi && mv.parent[b] >= bi && k.below[mv.parent[b]]);
        if (!k.below[b]) continue;
        down(b);
        k.s[b] = b == bi ? S_col<S>(mv, bi, ci) : k.X_up[b].apply(k.s[mv.parent[b]]);
        k.F[b] = body_inertia<S>(mv, b) * k.u[b];
      }
      for (int b = nb - 1; b > bi; --b) {
        if (!k.below[b]) continue;
        k.F[mv.parent[b]] += k.X_up[b].apply_transpose(k.F[b]);  // (F_b complete: its children come after it)
        k.acc[b] += cross_force(k.s[b], k.F[b]);
      }
    }
  }
  for (int b = 0; b < nb; ++b) {
    St_times(mv, b, k.acc[b], g + mv.idx_v[b]);
    for (int c = 0; c < mv.nv_i[b]; ++c) g[mv.idx_v[b] + c] = -g[mv.idx_v[b] + c];
  }
}

}  // namespace fdcore
