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

// The ∂M/∂q products, row block by row block r of the tensors (nv, nv, nv): with P_X[j, k] = Σ_s ∂M_rs/∂q_j X[s, k]
// (dM [r, s, j] as dM_dq, nonzero only for r, s, j on one path; the three blocks formed in P, 3 nv² scratch that
// stays in cache, in one pass over dM's row block):
//     d2q[r] += P_Fq + P_Fqᵀ,   dqdv[r] += P_Fv,   dqdtau[r] = P_Minv
inline void add_dM_products(int nv, const double* dM, const double* Fq, const double* Fv, const double* Minv,
                            double* d2q, double* dqdv, double* dqdtau, double* P) {
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  double *P1 = P, *P2 = P + n2, *P3 = P + 2 * n2;
  for (size_t r = 0; r < n; ++r) {
    std::fill(P, P + 3 * n2, 0.0);
    for (size_t s = 0; s < n; ++s)
      for (size_t j = 0; j < n; ++j) {
        const double c = dM[(r * n + s) * n + j];
        if (c == 0.0) continue;
        double *p1 = P1 + j * n, *p2 = P2 + j * n, *p3 = P3 + j * n;
        const double *x = Fq + s * n, *y = Fv + s * n, *z = Minv + s * n;
        for (size_t k = 0; k < n; ++k) p1[k] += c * x[k], p2[k] += c * y[k], p3[k] += c * z[k];
      }
    double *t = d2q + r * n2, *u = dqdv + r * n2;
    for (size_t j = 0; j < n; ++j)
      for (size_t k = 0; k < n; ++k) t[j * n + k] += P1[j * n + k] + P1[k * n + j];
    for (size_t x = 0; x < n2; ++x) u[x] += P2[x];
    std::copy(P3, P3 + n2, dqdtau + r * n2);
  }
}

// T ← −M⁻¹ T for a tensor T (nv, nv, nv) read as (nv, nv²), L = M's factor: the columns (j, k) with k ≥ from[j]
// (every column when `from` is null) gathered a few j at a time into `buf` (nv rows of at most 128 columns, or one
// j's: the block stays in the L1 cache through both sweeps), solved (ltl.hpp), scattered back; then, with `from`,
// the others mirrored, T[:, j, k] = T[:, k, j] (for T symmetric in j, k but on the columns solved).
inline void minus_minv_columns(const ModelView& mv, const int* lambda, const double* L, double* T, const int* from,
                               std::vector<double>& buf) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  constexpr int max_width = 128;
  buf.resize(n * static_cast<size_t>(std::max(max_width, nv)));
  auto k0 = [&](int j) { return from ? from[j] : 0; };
  for (int j0 = 0, j1 = 0; j0 < nv; j0 = j1) {
    int width = 0;
    for (j1 = j0; j1 < nv && (j1 == j0 || width + nv - k0(j1) <= max_width); ++j1) width += nv - k0(j1);
    auto move = [&](bool in) {  // T's columns (j, k ≥ k0(j)), j ∈ [j0, j1), ↔ buf (nv, width)
      for (size_t r = 0; r < n; ++r) {
        double* b = buf.data() + r * static_cast<size_t>(width);
        for (int j = j0; j < j1; ++j) {
          double* t = T + r * n2 + static_cast<size_t>(j) * n + static_cast<size_t>(k0(j));
          const int len = nv - k0(j);
          in ? std::copy_n(t, len, b) : std::copy_n(b, len, t);
          b += len;
        }
      }
    };
    move(true);
    ltl_solve_rows(mv, lambda, L, buf.data(), width, true);
    move(false);
  }
  if (from == nullptr) return;
  for (size_t r = 0; r < n; ++r)
    for (int j = 0; j < nv; ++j)
      for (int k = 0; k < from[j]; ++k) T[r * n2 + static_cast<size_t>(j) * n + k] = T[r * n2 + static_cast<size_t>(k) * n + j];
}

// ∂²q̈ (each (nv, nv, nv) row-major, file comment) of q̈ = FD(q, q̇, τ, f_ext). Returns −1, or the joint whose
// pivot is not positive (M singular). RNEA's second derivatives are written straight into the outputs, the
// ∂M/∂q products added there, and each output, read as an (nv, nv²) matrix, solved in place with M's
// tree-sparse factor (ltl.hpp; 2 Σ depth products a column): no dense M⁻¹ product. d2ddq_dv2 is symmetric in
// j, k, and so is d2ddq_dq2 but on two columns of one joint (the bracket): only the columns k ≥ j (k in j's
// joint or after) are solved, the others mirrored.
inline int aba_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* tau,
                                  const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                  double* dqdtau) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), n2 = n * n, n3 = n2 * n;
  const int* lambda = dof_tree(mv).lambda.data();
  thread_local std::vector<double> first, dM, buf;
  thread_local std::vector<int> from_v, from_q;
  first.resize(n + 6 * n2 + aba_derivatives_scratch(nv));
  dM.resize(n3);
  from_v.resize(n), from_q.resize(n);
  double* qdd = first.data();
  double* Fq = qdd + n;  // ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹, a row block's products
  double* Fv = Fq + n2;
  double* Minv = Fv + n2;
  double* P = Minv + n2;
  double* scratch = P + 3 * n2;  // M's factor L first (aba_derivatives)
  const int bad = aba_derivatives(mv, lambda, q, qd, tau, f_ext, gravity, qdd, Fq, Fv, Minv, scratch);
  if (bad >= 0) return bad;
  const double* L = scratch;
  rnea_second_derivatives(mv, q, qd, qdd, f_ext, gravity, d2q, d2v, dqdv, dM.data());  // (outputs scanned)
  add_dM_products(nv, dM.data(), Fq, Fv, Minv, d2q, dqdv, dqdtau, P);
  for (int i = 0; i < mv.nb; ++i)
    for (int c = 0; c < mv.nv_i[i]; ++c) from_v[mv.idx_v[i] + c] = mv.idx_v[i] + c, from_q[mv.idx_v[i] + c] = mv.idx_v[i];
  minus_minv_columns(mv, lambda, L, d2q, from_q.data(), buf);
  minus_minv_columns(mv, lambda, L, d2v, from_v.data(), buf);
  minus_minv_columns(mv, lambda, L, dqdv, nullptr, buf);
  minus_minv_columns(mv, lambda, L, dqdtau, nullptr, buf);
  return -1;
}

}  // namespace fdcore
