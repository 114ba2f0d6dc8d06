// ltl.hpp's packed-layout factor and sweeps, and the dense Cholesky of the constraint rows, on any scalar:
// double (one state) or Pack (W states per instruction, contacts.hpp's batches). Each line is ltl.hpp's, in the
// same order (so the lanes are bit-identical to one state); only the comparisons change, to lane masks:
//
//     double:  !(d > tol) → true / false            Pack:  a bit per lane (lanes_le, lanes_not_greater)
//
// (ltl.hpp keeps its double-only ltl_factor_packed, ltl_solve_*_packed, ltl_solve_Lt_chain_rows and
// dense_cholesky* for kkt_solve; contacts.hpp calls these templates for both scalars.)
#pragma once

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "ltl.hpp"
#include "pack.hpp"

namespace fdcore {

// √x in one instruction for all lanes: IEEE 754's square root is correctly rounded, so each lane is std::sqrt's
// (pack.hpp's sqrt calls it lane by lane; here, in the factors, there is one per dof and per contact row).
inline double lane_sqrt(double x) { return std::sqrt(x); }
inline Pack lane_sqrt(const Pack& x) {
#if defined(__AVX512F__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12's avx512fintrin.h: the masked form's unused source
  return Pack::raw(reinterpret_cast<Pack::V>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(x.v))));
#pragma GCC diagnostic pop
#elif defined(__AVX2__)
  return Pack::raw(reinterpret_cast<Pack::V>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(x.v))));
#elif defined(__SSE2__)
  return Pack::raw(reinterpret_cast<Pack::V>(_mm_sqrt_pd(reinterpret_cast<__m128d>(x.v))));
#else
  return sqrt(x);
#endif
}

// |x|, max(a, b) as std::fabs and std::max ((a < b) ? b : a) lane by lane.
inline double lane_abs(double x) { return std::fabs(x); }
inline Pack lane_abs(const Pack& x) {
  Pack r;
  for (int k = 0; k < PACK_WIDTH; ++k) r.set(k, std::fabs(x[k]));
  return r;
}
inline double lane_max(double a, double b) { return std::max(a, b); }
inline Pack lane_max(const Pack& a, const Pack& b) { return Pack::raw(a.v < b.v ? b.v : a.v); }

// The lanes where !(x > y), as a bit mask (double: 0 or 1); every lane's bit.
inline int lanes_not_greater(double x, double y) { return !(x > y) ? 1 : 0; }
inline int lanes_not_greater(const Pack& x, const Pack& y) {
  int mask = 0;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (!(x[k] > y[k])) mask |= 1 << k;
  return mask;
}
// The lanes where x ≤ y.
inline int lanes_at_most(double x, double y) { return x <= y ? 1 : 0; }
inline int lanes_at_most(const Pack& x, const Pack& y) {
  int mask = 0;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (x[k] <= y[k]) mask |= 1 << k;
  return mask;
}
template <class S>
constexpr int all_lanes() {
  return 1;
}
template <>
constexpr int all_lanes<Pack>() {
  return (1 << PACK_WIDTH) - 1;
}

// The lanes of `mask` from a, the others from b (double: mask ? a : b).
inline double blend(int mask, double a, double b) { return mask ? a : b; }
inline Pack blend(int mask, const Pack& a, const Pack& b) {
  Pack r = b;
  for (int k = 0; k < PACK_WIDTH; ++k)
    if (mask >> k & 1) r.set(k, a[k]);
  return r;
}

// ltl.hpp: ltl_factor_packed. Returns −1, or the dof whose pivot is not positive (in some lane, for a Pack).
template <class S>
int ltl_factor_packed(const DofTree& t, S* P, S* dinv, const char* rows = nullptr) {
  for (int k = t.nv - 1; k >= 0; --k) {
    if (rows && !rows[k]) continue;
    S* __restrict Lk = P + t.off[k];
    const int dk = t.depth[k];
    const S d = Lk[dk];
    if (lanes_le(d, 0.0)) return k;
    const S r = S(1.0) / d, a = lane_sqrt(d), inv = a * r;  // 1/√d = √d / d: the division and the root overlap
    Lk[dk] = a;
    dinv[k] = inv;
    for (int s = 0; s < dk; ++s) Lk[s] = Lk[s] * inv;
    const int* ch = t.chain.data() + t.off[k];
    for (int s = 0; s < dk; ++s) {  // row i = chain_k[s]: L_i[0 .. s] −= L_k[s] · L_k[0 .. s]
      S* __restrict Li = P + t.off[ch[s]];
      const S l = Lk[s];
      for (int u = 0; u <= s; ++u) Li[u] = Li[u] - l * Lk[u];
    }
  }
  return -1;
}

// ltl.hpp: x ← L⁻ᵀ x and x ← L⁻¹ x on the packed factor.
template <class S>
void ltl_solve_Lt_packed(const DofTree& t, const S* P, const S* dinv, S* x) {
  for (int k = t.nv - 1; k >= 0; --k) {
    const S* Lk = P + t.off[k];
    const int* ch = t.chain.data() + t.off[k];
    const int dk = t.depth[k];
    const S xk = x[k] * dinv[k];
    x[k] = xk;
    for (int s = 0; s < dk; ++s) x[ch[s]] = x[ch[s]] - Lk[s] * xk;
  }
}
template <class S>
void ltl_solve_L_packed(const DofTree& t, const S* P, const S* dinv, S* x) {
  for (int k = 0; k < t.nv; ++k) {
    const S* Lk = P + t.off[k];
    const int* ch = t.chain.data() + t.off[k];
    const int dk = t.depth[k];
    S s = x[k];
    for (int u = 0; u < dk; ++u) s = s - Lk[u] * x[ch[u]];
    x[k] = s * dinv[k];
  }
}

// ltl.hpp: y ← L⁻ᵀ y for n rows held in the chain positions of dof k.
template <class S>
void ltl_solve_Lt_chain_rows(const DofTree& t, const S* P, const S* dinv, int k, S* Y, int n, int stride) {
  const int* ch = t.chain.data() + t.off[k];
  for (int s = t.depth[k]; s >= 0; --s) {
    const S* __restrict Li = P + t.off[ch[s]];
    const S di = dinv[ch[s]];
    for (int r = 0; r < n; ++r) {
      S* __restrict y = Y + static_cast<size_t>(r) * stride;
      const S ys = y[s] * di;
      y[s] = ys;
      for (int u = 0; u < s; ++u) y[u] = y[u] - Li[u] * ys;
    }
  }
}

// ltl.hpp: dense Cholesky of a symmetric (m, m) A in place (lower triangle). Returns the lanes whose pivot is
// ≤ tol·max|A_ii| (0: factored in every lane; a failed lane's entries are not to be read).
template <class S>
int dense_cholesky(S* A, int m, double tol) {
  S scale(0.0);
  for (int i = 0; i < m; ++i) scale = lane_max(scale, lane_abs(A[i * m + i]));
  for (int j = 0; j < m; ++j) {
    S d = A[j * m + j];
    for (int k = 0; k < j; ++k) d -= A[j * m + k] * A[j * m + k];
    const int bad = lanes_not_greater(d, S(tol) * scale);
    if (bad) return bad;
    const S l = lane_sqrt(d);
    A[j * m + j] = l;
    for (int i = j + 1; i < m; ++i) {
      S x = A[i * m + j];
      for (int k = 0; k < j; ++k) x -= A[i * m + k] * A[j * m + k];
      A[i * m + j] = x / l;
    }
  }
  return 0;
}

// ltl.hpp: x ← A⁻¹ x for the factor of dense_cholesky.
template <class S>
void dense_cholesky_solve(const S* L, int m, S* x) {
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < i; ++k) x[i] -= L[i * m + k] * x[k];
    x[i] = x[i] / L[i * m + i];
  }
  for (int i = m - 1; i >= 0; --i) {
    for (int k = i + 1; k < m; ++k) x[i] -= L[k * m + i] * x[k];
    x[i] = x[i] / L[i * m + i];
  }
}

// ltl.hpp: A⁻¹ (m, m), full and exactly symmetric, from the factor of dense_cholesky; Wt (m, m) scratch.
template <class S>
void dense_cholesky_inverse(const S* C, int m, S* Wt, S* Ainv) {
  S* r = Ainv;  // the diagonal's reciprocals, in Ainv's first row until it is written
  for (int i = 0; i < m; ++i) r[i] = S(1.0) / C[i * m + i];
  for (int j = 0; j < m; ++j) {  // column j of W = C⁻¹: forward substitution on e_j
    S* w = Wt + static_cast<size_t>(j) * m;
    w[j] = r[j];
    for (int i = j + 1; i < m; ++i) {
      const S* Ci = C + static_cast<size_t>(i) * m;
      S x(0.0);
      for (int k = j; k < i; ++k) x -= Ci[k] * w[k];
      w[i] = x * r[i];
    }
  }
  for (int i = 0; i < m; ++i)  // (Wᵀ W)_ij = Σ_{k ≥ i} W_ki W_kj (the reciprocals are no longer read)
    for (int j = 0; j <= i; ++j) {
      const S* wi = Wt + static_cast<size_t>(i) * m;
      const S* wj = Wt + static_cast<size_t>(j) * m;
      S x(0.0);
      for (int k = i; k < m; ++k) x += wi[k] * wj[k];
      Ainv[i * m + j] = Ainv[j * m + i] = x;
    }
}

}  // namespace fdcore
