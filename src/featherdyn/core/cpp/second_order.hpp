// Second-order derivatives of inverse and forward dynamics (reference: featherdyn/algorithms/second_order.py;
// docs/derivatives.md, "Second order").
//
// Inverse dynamics (rnea_second_order.hpp): the second derivatives of τ = RNEA(q, q̇, q̈, f_ext), q along
// fd.integrate's tangent X_k (q ⊕ ε e_k):
//
//     d2tau_dq2[i, j, k]  = X_k (X_j τ_i)        (not symmetric in j, k on two columns of one free-flyer, spherical
//                                                 or planar joint: the tangent fields' bracket)
//     d2tau_dv2[i, j, k]  = ∂²τ_i/∂q̇_j∂q̇_k        (symmetric in j, k; independent of q̇, q̈)
//     d2tau_dqdv[i, j, k] = ∂/∂q̇_k (X_j τ_i)
//     dM_dq[i, j, k]      = X_k M_ij              (= ∂²τ_i/∂q_k∂q̈_j;  ∂²τ/∂q̈² = 0)
//
// by the analytical recursion of Singh, Russell & Wensing: O(nv · depth²) dot products of 6-vectors.
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
// (nv, nv²) matrix, each is one solve with M's tree-sparse factor (aba_derivatives leaves it in its scratch).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "derivatives.hpp"
#include "rnea_second_order.hpp"

namespace fdcore {

// T[r, j, k] += Σ_s ∂M_rs/∂q_j B[s, k]  (dM [r, s, j] as dM_dq; B (nv, nv); T (nv, nv, nv)), and when `both`
// T[r, k, j] += the same: per row r, the (nv, nv) block P_r = Σ_s dM[r, s, :] ⊗ B[s, :] formed in P (nv² scratch,
// in cache) from dM's nonzeros (∂M_rs/∂q_j ≠ 0 only for r, s, j on one path), then added to T's block r.
inline void add_dM_times(int nv, const double* dM, const double* B, double* T, bool both, double* P) {
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  for (size_t r = 0; r < n; ++r) {
    std::fill(P, P + n2, 0.0);
    for (size_t s = 0; s < n; ++s)
      for (size_t j = 0; j < n; ++j) {
        const double c = dM[(r * n + s) * n + j];
        if (c == 0.0) continue;
        double* p = P + j * n;
        const double* b = B + s * n;
        for (size_t k = 0; k < n; ++k) p[k] += c * b[k];
      }
    double* t = T + r * n2;
    for (size_t j = 0; j < n; ++j)
      for (size_t k = 0; k < n; ++k) t[j * n + k] += both ? P[j * n + k] + P[k * n + j] : P[j * n + k];
  }
}

// ∂²q̈ (each (nv, nv, nv) row-major, file comment) of q̈ = FD(q, q̇, τ, f_ext). Returns −1, or the joint whose
// pivot is not positive (M singular). RNEA's second derivatives are written straight into the outputs, the
// ∂M/∂q products added there, and each output, read as an (nv, nv²) matrix, solved in place with M's
// tree-sparse factor (ltl.hpp: X ← −M⁻¹ X, 2 Σ depth products a column; d2tau_dv2's rows are zero off their
// dofs' paths, so its first sweep runs on those only). No dense M⁻¹ product.
inline int aba_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* tau,
                                  const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                  double* dqdtau) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), n2 = n * n, n3 = n2 * n;
  const int* lambda = dof_tree(mv).lambda.data();
  thread_local std::vector<double> first, dM;
  first.resize(n + 4 * n2 + aba_derivatives_scratch(nv));
  dM.resize(n3);
  double* qdd = first.data();
  double* Fq = qdd + n;  // ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹, a block's products
  double* Fv = Fq + n2;
  double* Minv = Fv + n2;
  double* P = Minv + n2;
  double* scratch = P + n2;  // M's factor L first (aba_derivatives)
  const int bad = aba_derivatives(mv, lambda, q, qd, tau, f_ext, gravity, qdd, Fq, Fv, Minv, scratch);
  if (bad >= 0) return bad;
  const double* L = scratch;
  rnea_second_derivatives(mv, q, qd, qdd, f_ext, gravity, d2q, d2v, dqdv, dM.data());
  add_dM_times(nv, dM.data(), Fq, d2q, true, P);  // + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j
  add_dM_times(nv, dM.data(), Fv, dqdv, false, P);  // + ∂M/∂q_j ∂q̈/∂q̇_k
  std::fill(dqdtau, dqdtau + n3, 0.0);
  add_dM_times(nv, dM.data(), Minv, dqdtau, false, P);  // ∂M/∂q_j M⁻¹
  const int cols = nv * nv;
  ltl_solve_rows(mv, lambda, L, d2q, cols, true);
  ltl_solve_rows_tree_pattern(mv, lambda, L, d2v, nv, true);
  ltl_solve_rows(mv, lambda, L, dqdv, cols, true);
  ltl_solve_rows(mv, lambda, L, dqdtau, cols, true);
  return -1;
}

}  // namespace fdcore
