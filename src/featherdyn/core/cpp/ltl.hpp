// The tree-sparse LᵀL factorisation of the mass matrix (RBDA §6.5, table 6.3; reference:
// featherdyn/algorithms/) and what it solves without ever forming M⁻¹:
//
//     M = Lᵀ L,  L lower triangular with L_kj ≠ 0 only for j = k or j an ancestor dof of k
//     M x = b:  Lᵀ y = b, then L x = y   (each a sweep over the dofs' ancestors)
//     J M⁻¹ Jᵀ = (J L⁻¹)(J L⁻¹)ᵀ           (the Delassus matrix of constraint Jacobian J)
//
// The dofs' parent array λ_d: within a joint the previous dof, the first dof of a joint hangs from the
// last dof of its parent body's joint (−1 at a root). Factorising costs Σ_k depth(k)², the solves Σ depth.
#pragma once

#include <cmath>
#include <vector>

#include "crba.hpp"

namespace fdcore {

// λ_d (nv,) of the file comment.
inline void dof_parents(const ModelView& mv, int* lambda) {
  for (int i = 0; i < mv.nb; ++i) {
    const int iv = mv.idx_v[i], lam = mv.parent[i];
    for (int c = 0; c < mv.nv_i[i]; ++c)
      lambda[iv + c] = c > 0 ? iv + c - 1 : lam == -1 ? -1 : mv.idx_v[lam] + mv.nv_i[lam] - 1;
  }
}

// In place: M (nv, nv) row-major, full and symmetric → L in its lower triangle (the strict upper part is
// left as it was). Returns −1, or the dof whose pivot is not positive (M not positive definite).
template <class S>
int ltl_factor(const ModelView& mv, const int* lambda, S* M) {
  const int nv = mv.nv;
  for (int k = nv - 1; k >= 0; --k) {
    const S d = M[k * nv + k];
    if (!(d > S(0.0))) return k;
    const S a = std::sqrt(d);
    M[k * nv + k] = a;
    for (int i = lambda[k]; i != -1; i = lambda[i]) M[k * nv + i] = M[k * nv + i] / a;
    for (int i = lambda[k]; i != -1; i = lambda[i])
      for (int j = i; j != -1; j = lambda[j]) M[i * nv + j] = M[i * nv + j] - M[k * nv + i] * M[k * nv + j];
  }
  return -1;
}

// x ← L⁻ᵀ x (solve Lᵀ y = x) and x ← L⁻¹ x (solve L y = x), L from ltl_factor.
template <class S>
void ltl_solve_Lt(const ModelView& mv, const int* lambda, const S* L, S* x) {
  const int nv = mv.nv;
  for (int k = nv - 1; k >= 0; --k) {
    x[k] = x[k] / L[k * nv + k];
    for (int i = lambda[k]; i != -1; i = lambda[i]) x[i] = x[i] - L[k * nv + i] * x[k];
  }
}
template <class S>
void ltl_solve_L(const ModelView& mv, const int* lambda, const S* L, S* x) {
  const int nv = mv.nv;
  for (int k = 0; k < nv; ++k) {
    for (int i = lambda[k]; i != -1; i = lambda[i]) x[k] = x[k] - L[k * nv + i] * x[i];
    x[k] = x[k] / L[k * nv + k];
  }
}

template <class S>
struct LtlWork {
  std::vector<int> lambda;
  std::vector<S> Y;
  void resize(size_t) {}
};

// D = J M⁻¹ Jᵀ (m, m) for J (m, nv) row-major, L the factor of M(q). Row r of Y = J L⁻¹ solves Lᵀ y = J_rᵀ.
template <class S>
void delassus_from_factor(const ModelView& mv, const int* lambda, const S* L, const S* J, int m, S* D,
                          std::vector<S>& Y) {
  const int nv = mv.nv;
  Y.assign(J, J + static_cast<size_t>(m) * nv);
  for (int r = 0; r < m; ++r) ltl_solve_Lt(mv, lambda, L, Y.data() + static_cast<size_t>(r) * nv);
  for (int r = 0; r < m; ++r)
    for (int c = 0; c <= r; ++c) {
      S x(0.0);
      for (int k = 0; k < nv; ++k) x = x + Y[r * nv + k] * Y[c * nv + k];
      D[r * m + c] = D[c * m + r] = x;
    }
}

}  // namespace fdcore
