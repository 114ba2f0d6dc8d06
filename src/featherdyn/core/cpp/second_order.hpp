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
#include "rnea_second_order.hpp"

namespace fdcore {

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
