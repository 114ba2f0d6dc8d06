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

// y ← y + c x on n entries (x, y not overlapping: the loop is vectorised).
inline void add_scaled(size_t n, double c, const double* __restrict x, double* __restrict y) {
  for (size_t k = 0; k < n; ++k) y[k] += c * x[k];
}

// The ∂M/∂q products, row block by row block r of the tensors (nv, nv, nv): with P_X[j, k] = Σ_s ∂M_rs/∂q_j X[s, k]
// (dM [r, s, j] as dM_dq, nonzero only for r, s, j on one path), in one pass over dM's row block:
//     d2q[r] += P_Fq + P_Fqᵀ,   dqdv[r] += P_Fv,   dqdtau[r] = P_Minv
// P_Fv and P_Minv summed where they go, P_Fq in P (nv² scratch, in the L1 cache) for its transpose.
inline void add_dM_products(int nv, const double* dM, const double* Fq, const double* Fv, const double* Minv,
                            double* d2q, double* dqdv, double* dqdtau, double* P) {
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  for (size_t r = 0; r < n; ++r) {
    double *t = d2q + r * n2, *u = dqdv + r * n2, *w = dqdtau + r * n2;
    std::fill(P, P + n2, 0.0);
    std::fill(w, w + n2, 0.0);
    for (size_t j = 0; j < n; ++j)  // row j of each product at a time (it stays in the L1 cache)
      for (size_t s = 0; s < n; ++s) {
        const double c = dM[(r * n + s) * n + j];
        if (c == 0.0) continue;
        add_scaled(n, c, Fq + s * n, P + j * n);
        add_scaled(n, c, Fv + s * n, u + j * n);
        add_scaled(n, c, Minv + s * n, w + j * n);
      }
    for (size_t j = 0; j < n; ++j)
      for (size_t k = 0; k < n; ++k) t[j * n + k] += P[j * n + k] + P[k * n + j];
  }
}

// Where a right-hand side T[r, j, k] of the solves below may be nonzero. τ_r and row r of M depend only on the
// coordinates of the dofs on r's paths — r's ancestors, r and r's subtree: "j near r" — so ∂τ_r/∂x_j, ∂M_rs/∂q_j
// (s near r) and their products vanish for j not near r:
//   near_j        T[r, j, k] ≠ 0 only for j near r    (d2tau_dqdv + ∂M/∂q_j ∂q̈/∂q̇_k, ∂M/∂q_j M⁻¹)
//   near_j_and_k  only for j and k near r              (d2tau_dv2)
//   near_j_or_k   only for j or k near r               (d2tau_dq2 + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j)
enum class Near { near_j, near_j_and_k, near_j_or_k };

// T ← −M⁻¹ T for a tensor T (nv, nv, nv) read as (nv, nv²), L = M's factor, T zero where `near` says, in place:
// the columns (j, k) with k ≥ from[j] (every column when `from` is null) a few j at a time (at most 256 columns
// or one j's: each block lists every row's ancestors once a sweep, and on talos_full_v2 256 was 5–7 % faster than
// 128 or 512), by ltl_sweeps on T's rows (nv² apart) from column (j0, from[j0]), the columns k < from[j] of the
// block's later j skipped. The first sweep runs only on row r's entries that may be nonzero where the tree is
// numbered depth-first ("near" is then two comparisons), on every entry otherwise. With `from`, the columns
// skipped are then mirrored, T[:, j, k] = T[:, k, j] (for T symmetric in j, k but on the columns solved).
inline void minus_minv_columns(const ModelView& mv, const int* lambda, const double* L, double* T, const int* from,
                               Near near) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), n2 = n * n;
  constexpr int max_width = 256;
  auto k0 = [&](int j) { return from ? from[j] : 0; };
  const int* end = subtree_ends(lambda, nv);  // (r's subtree: [r, end[r]))
  RowSupport support{};
  const bool sparse = end != nullptr && row_supports(lambda, nv, support);
  auto is_near = [&](int r, int j) { return (r <= j && j < end[r]) || (j <= r && r < end[j]); };
  for (int j0 = 0, j1 = 0; j0 < nv; j0 = j1) {
    int width = 0;
    for (j1 = j0; j1 < nv && (j1 == j0 || width + nv - k0(j1) <= max_width); ++j1) width += nv - k0(j1);
    auto at = [&](int j) { return (j - j0) * nv - k0(j0); };  // column k of j is the block's column at(j) + k
    // op(c0, c1) on the runs of [c0, c1) that `segments(j, op)` gives in turn, adjacent runs joined
    auto joined = [&](auto&& segments, auto&& op) {
      int c0 = 0, c1 = 0;
      auto add = [&](int a, int b) {
        if (a == c1 && c0 < c1) return void(c1 = b);  // continues the run pending
        if (c0 < c1) op(c0, c1);
        c0 = a, c1 = b;
      };
      for (int j = j0; j < j1; ++j) segments(j, add);
      if (c0 < c1) op(c0, c1);
    };
    auto columns = [&](auto&& op) {
      joined([&](int j, auto&& add) { add(at(j) + k0(j), at(j) + nv); }, op);
    };
    auto runs = [&](int r, auto&& op) {  // row r's columns that may be nonzero
      if (!sparse) return columns(op);
      joined([&](int j, auto&& add) {
        const bool j_near = is_near(r, j);
        if (j_near && near != Near::near_j_and_k) return add(at(j) + k0(j), at(j) + nv);  // every k
        if (near == Near::near_j_or_k || (near == Near::near_j_and_k && j_near))  // (j not near: near_j_or_k)
          for (int s = support.off[r]; s < support.off[r + 1]; ++s) {  // the k near r (from k0(j))
            const int a = std::max(support.seg[2 * s], k0(j)), b = support.seg[2 * s + 1];
            if (a < b) add(at(j) + a, at(j) + b);
          }
      }, op);
    };
    double* X = T + static_cast<size_t>(j0) * n + static_cast<size_t>(k0(j0));
    ltl_sweeps(mv, lambda, L, X, n2, columns, runs, true);
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
  thread_local std::vector<double> first, dM;
  thread_local std::vector<int> from_v, from_q;
  first.resize(n + 4 * n2 + aba_derivatives_scratch(nv));
  dM.resize(n3);
  from_v.resize(n), from_q.resize(n);
  double* qdd = first.data();
  double* Fq = qdd + n;  // ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹, a row block's products
  double* Fv = Fq + n2;
  double* Minv = Fv + n2;
  double* P = Minv + n2;
  double* scratch = P + n2;  // M's factor L first (aba_derivatives)
  const int bad = aba_derivatives(mv, lambda, q, qd, tau, f_ext, gravity, qdd, Fq, Fv, Minv, scratch);
  if (bad >= 0) return bad;
  const double* L = scratch;
  rnea_second_derivatives(mv, q, qd, qdd, f_ext, gravity, d2q, d2v, dqdv, dM.data());  // (outputs scanned)
  add_dM_products(nv, dM.data(), Fq, Fv, Minv, d2q, dqdv, dqdtau, P);
  for (int i = 0; i < mv.nb; ++i)
    for (int c = 0; c < mv.nv_i[i]; ++c) from_v[mv.idx_v[i] + c] = mv.idx_v[i] + c, from_q[mv.idx_v[i] + c] = mv.idx_v[i];
  minus_minv_columns(mv, lambda, L, d2q, from_q.data(), Near::near_j_or_k);
  minus_minv_columns(mv, lambda, L, d2v, from_v.data(), Near::near_j_and_k);
  minus_minv_columns(mv, lambda, L, dqdv, nullptr, Near::near_j);
  minus_minv_columns(mv, lambda, L, dqdtau, nullptr, Near::near_j);
  return -1;
}

}  // namespace fdcore
