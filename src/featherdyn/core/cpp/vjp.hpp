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

}  // namespace fdcore
