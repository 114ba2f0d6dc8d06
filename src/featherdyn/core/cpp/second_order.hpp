// Second-order derivatives of inverse and forward dynamics (reference: featherdyn/algorithms/second_order.py;
// docs/derivatives.md, "Second order").
//
// Inverse dynamics. The second derivatives are the derivatives of the analytical first order
// (derivatives.hpp: ∂τ/∂q along q ⊕ δ e_j, ∂τ/∂q̇, M) along q ⊕ ε e_k and along q̇ + ε e_k:
//
//     d2tau_dq2[i, j, k]  = d/dε (∂τ_i/∂q_j)(q ⊕ ε e_k, q̇, q̈)      (not symmetric in j, k on a free-flyer or
//                                                                  spherical joint: the tangent fields' bracket)
//     d2tau_dv2[i, j, k]  = d/dε (∂τ_i/∂q̇_j)(q, q̇ + ε e_k, q̈)      (symmetric in j, k; independent of q̇, q̈)
//     d2tau_dqdv[i, j, k] = d/dε (∂τ_i/∂q_j)(q, q̇ + ε e_k, q̈)
//     dM_dq[i, j, k]      = d/dε M_ij(q ⊕ ε e_k)                    (= ∂²τ_i/∂q_k∂q̈_j;  ∂²τ/∂q̈² = 0)
//
// each taken exactly by forward-mode differentiation: the first-order template rnea_derivatives_to (itself
// templated on the scalar) runs on Dual numbers, each of DERIV_LANES lanes seeded with one direction — the
// tangent of q ⊕ ε e_k (seed_tangent, derivatives.hpp) or e_k in q̇ — 2 nv directions, ⌈2 nv / 8⌉ passes of
// the O(nv · depth) first-order algorithm. No finite differences.
//
// Forward dynamics. q̈ = FD(q, q̇, τ) solves RNEA(q, q̇, FD) = τ. With X_j the derivative along q ⊕ δ e_j, one
// differentiation gives (X_j τ)(q, q̇, q̈) + M X_j q̈ = 0, a second (the a-derivative of X_j τ being X_j M):
//
//     d2ddq_dq2[:, j, k]   = −M⁻¹ (d2tau_dq2[:, j, k] + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j)
//     d2ddq_dv2[:, j, k]   = −M⁻¹ d2tau_dv2[:, j, k]
//     d2ddq_dqdv[:, j, k]  = −M⁻¹ (d2tau_dqdv[:, j, k] + ∂M/∂q_j ∂q̈/∂q̇_k)
//     d2ddq_dqdtau[:, j, k] = −(M⁻¹ ∂M/∂q_j M⁻¹)[:, k]
//
// (∂M/∂q_j = dM_dq[:, :, j]; the RNEA terms at q̈ = FD(q, q̇, τ)). With the tensor [r, j, k] read as an
// (nv, nv²) matrix, each is one product of M⁻¹ (aba_derivatives: from M's tree-sparse factor) with it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "derivatives.hpp"
#include "scratch.hpp"

namespace fdcore {

// The first-order outputs on Dual numbers and the Dual state, per thread.
struct SecondOrderWork {
  std::vector<DualK> Q, V, A, F, dq, dv, M;
  void resize(size_t) {}
};

// ∂²τ (each (nv, nv, nv) row-major, [i, j, k] = ∂²τ_i/∂x_j∂y_k; file comment) of τ = RNEA(q, q̇, q̈, f_ext).
inline void rnea_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                                    const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                    double* dM) {
  const int nq = mv.nq, nv = mv.nv, nf = 6 * mv.nb;
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  SecondOrderWork& w = thread_workspace<SecondOrderWork>(mv.nb);
  w.Q.resize(static_cast<size_t>(nq)), w.V.resize(n), w.A.resize(n), w.F.resize(f_ext ? static_cast<size_t>(nf) : 0);
  w.dq.resize(n2), w.dv.resize(n2), w.M.resize(n2);
  for (int k = 0; k < nv; ++k) w.A[k] = DualK(qdd[k]);
  for (int k = 0; f_ext && k < nf; ++k) w.F[k] = DualK(f_ext[k]);
  for (int start = 0; start < 2 * nv; start += DERIV_LANES) {
    const int lanes = seed_state_directions(mv, q, qd, start, w.Q.data(), w.V.data());
    // a pass of q's directions only does not form ∂τ/∂q̇, one of q̇'s only not M (independent of q̇)
    const bool q_only = start + lanes <= nv, v_only = start >= nv;
    rnea_derivatives_to(mv, w.Q.data(), w.V.data(), w.A.data(), f_ext ? w.F.data() : nullptr, gravity,
                        StateOut<DualK>{{w.dq.data(), q_only ? nullptr : w.dv.data(), v_only ? nullptr : w.M.data()}});
    // lane l is direction start + l: q's below nv, q̇'s from nv; each entry's lanes land side by side in the
    // tensors' last index (contiguous writes)
    const int nq_lanes = std::clamp(nv - start, 0, lanes);
    const size_t k0 = static_cast<size_t>(start);
    const int kv0 = start + nq_lanes - nv;  // q̇'s direction of lane nq_lanes
    for (size_t ij = 0; ij < n2; ++ij) {
      const DualK &x = w.dq[ij], &y = w.dv[ij], &m = w.M[ij];
      for (int l = 0; l < nq_lanes; ++l) {  // along q ⊕ ε e_k: ∂τ/∂q and M
        d2q[ij * n + k0 + l] = x.d[l];
        dM[ij * n + k0 + l] = m.d[l];
      }
      for (int l = nq_lanes; l < lanes; ++l) {  // along q̇ + ε e_k: ∂τ/∂q̇ and ∂τ/∂q
        const size_t k = static_cast<size_t>(kv0 + l - nq_lanes);
        d2v[ij * n + k] = y.d[l];
        dqdv[ij * n + k] = x.d[l];
      }
    }
  }
}

// out ← −Minv R: the tensor R [r, j, k] read as an (nv, nv²) matrix, out likewise. By blocks of columns, so that
// R's block (nv × 256 doubles) stays in cache while every row of out reads it.
inline void minus_minv_times(int nv, const double* Minv, const double* R, double* out) {
  constexpr size_t block = 256;
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  for (size_t c0 = 0; c0 < n2; c0 += block) {
    const size_t c1 = std::min(n2, c0 + block);
    for (size_t i = 0; i < n; ++i) {
      double* o = out + i * n2;
      std::fill(o + c0, o + c1, 0.0);
      for (size_t r = 0; r < n; ++r) {
        const double m = -Minv[i * n + r];
        if (m == 0.0) continue;
        const double* row = R + r * n2;
        for (size_t c = c0; c < c1; ++c) o[c] += m * row[c];
      }
    }
  }
}

// P[r, j, k] = Σ_s ∂M_rs/∂q_j B[s, k]  (dM [r, s, j] as dM_dq; B (nv, nv)).
inline void dM_times(int nv, const double* dM, const double* B, double* P) {
  const size_t n = static_cast<size_t>(nv);
  std::fill(P, P + n * n * n, 0.0);
  for (size_t r = 0; r < n; ++r)
    for (size_t s = 0; s < n; ++s)
      for (size_t j = 0; j < n; ++j) {
        const double c = dM[(r * n + s) * n + j];
        if (c == 0.0) continue;
        double* p = P + (r * n + j) * n;
        const double* b = B + s * n;
        for (size_t k = 0; k < n; ++k) p[k] += c * b[k];
      }
}

// ∂²q̈ (each (nv, nv, nv) row-major, file comment) of q̈ = FD(q, q̇, τ, f_ext). Returns −1, or the joint whose
// pivot is not positive (M singular).
inline int aba_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* tau,
                                  const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                  double* dqdtau) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), n2 = n * n, n3 = n2 * n;
  thread_local std::vector<double> first, second;
  first.resize(n + 3 * n2 + aba_derivatives_scratch(nv));
  second.resize(6 * n3);
  double* qdd = first.data();
  double* Fq = qdd + n;  // ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹
  double* Fv = Fq + n2;
  double* Minv = Fv + n2;
  double* t2q = second.data();  // RNEA's second derivatives at q̈, then the products with ∂M/∂q
  double* t2v = t2q + n3;
  double* tqv = t2v + n3;
  double* dM = tqv + n3;
  double* P = dM + n3;
  double* R = P + n3;
  const int bad = aba_derivatives(mv, dof_tree(mv).lambda.data(), q, qd, tau, f_ext, gravity, qdd, Fq, Fv, Minv,
                                  Minv + n2);
  if (bad >= 0) return bad;
  rnea_second_derivatives(mv, q, qd, qdd, f_ext, gravity, t2q, t2v, tqv, dM);
  minus_minv_times(nv, Minv, t2v, d2v);
  dM_times(nv, dM, Fq, P);  // P[r, j, k] = (∂M/∂q_j ∂q̈/∂q_k)_r
  for (size_t r = 0; r < n; ++r)
    for (size_t j = 0; j < n; ++j)
      for (size_t k = 0; k < n; ++k) R[(r * n + j) * n + k] = t2q[(r * n + j) * n + k] + P[(r * n + j) * n + k] +
                                                                 P[(r * n + k) * n + j];
  minus_minv_times(nv, Minv, R, d2q);
  dM_times(nv, dM, Fv, P);  // (∂M/∂q_j ∂q̈/∂q̇_k)_r
  for (size_t x = 0; x < n3; ++x) R[x] = tqv[x] + P[x];
  minus_minv_times(nv, Minv, R, dqdv);
  dM_times(nv, dM, Minv, P);  // (∂M/∂q_j M⁻¹)_rk
  minus_minv_times(nv, Minv, P, dqdtau);
  return -1;
}

}  // namespace fdcore
