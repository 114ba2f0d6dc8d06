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

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

#include "crba.hpp"
#include "pack.hpp"
#include "scratch.hpp"

namespace fdcore {

// λ_d (nv,) of the file comment.
inline void dof_parents(const ModelView& mv, int* lambda) {
  for (int i = 0; i < mv.nb; ++i) {
    const int iv = mv.idx_v[i], lam = mv.parent[i];
    for (int c = 0; c < mv.nv_i[i]; ++c)
      lambda[iv + c] = c > 0 ? iv + c - 1 : lam == -1 ? -1 : mv.idx_v[lam] + mv.nv_i[lam] - 1;
  }
}

// The body whose joint owns dof k (a failed pivot of the factor is reported by body).
inline int dof_body(const ModelView& mv, int k) {
  for (int i = 0; i < mv.nb; ++i)
    if (mv.idx_v[i] <= k && k < mv.idx_v[i] + mv.nv_i[i]) return i;
  return 0;
}

// In place: M (nv, nv) row-major, full and symmetric → L in its lower triangle (the strict upper part is
// left as it was). Returns −1, or the dof whose pivot is not positive (M not positive definite).
// S: double, or Pack (lanes factored together; a pivot that fails in any lane fails the call).
template <class S>
int ltl_factor(const ModelView& mv, const int* lambda, S* M) {
  using std::sqrt;
  const int nv = mv.nv;
  for (int k = nv - 1; k >= 0; --k) {
    const S d = M[k * nv + k];
    if (lanes_le(d, 0.0)) return k;
    const S a = sqrt(d);
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

// Whether `key` holds λ_d (nv,) already; if not, it does after the call (the per-thread caches below are
// rebuilt only when a call brings another tree).
inline bool same_tree(std::vector<int>& key, const int* lambda, int nv) {
  if (key.size() == static_cast<size_t>(nv) && std::equal(lambda, lambda + nv, key.begin())) return true;
  key.assign(lambda, lambda + nv);
  return false;
}

// One past the last dof of each dof's subtree (the calling thread's array), when every subtree is the
// contiguous range [k, end_k) of a depth-first numbering (λ(k) < k); nullptr for any other numbering.
inline const int* subtree_ends(const int* lambda, int nv) {
  thread_local std::vector<int> key, end, count;
  thread_local bool depth_first = false;
  if (same_tree(key, lambda, nv)) return depth_first ? end.data() : nullptr;
  end.resize(static_cast<size_t>(nv));
  count.assign(static_cast<size_t>(nv), 1);
  for (int k = 0; k < nv; ++k) end[k] = k + 1;
  for (int k = nv - 1; k >= 0; --k)
    if (lambda[k] >= 0) end[lambda[k]] = std::max(end[lambda[k]], end[k]), count[lambda[k]] += count[k];
  depth_first = true;
  for (int k = 0; k < nv; ++k)
    if (count[k] != end[k] - k || lambda[k] >= k) depth_first = false;
  return depth_first ? end.data() : nullptr;
}

// The columns where row k of ∂τ/∂q or ∂τ/∂q̇ may be nonzero — k's ancestor dofs and k's subtree, since τ_k
// depends only on the coordinates of the dofs on k's paths — as runs [seg[2s], seg[2s + 1]) of columns,
// s ∈ [off[k], off[k + 1]), ascending. A run per branch point above k: talos' arm rows have three (the base,
// the torso, the arm and its subtree).
struct RowSupport {
  const int* off;
  const int* seg;
};

// RowSupport of the dofs (the calling thread's arrays) when the numbering is depth-first (subtree_ends);
// false for any other numbering.
inline bool row_supports(const int* lambda, int nv, RowSupport& out) {
  const int* end = subtree_ends(lambda, nv);
  if (end == nullptr) return false;
  thread_local std::vector<int> key, off, seg, anc;
  if (same_tree(key, lambda, nv)) {
    out = {off.data(), seg.data()};
    return true;
  }
  off.assign(1, 0);
  seg.clear();
  for (int k = 0; k < nv; ++k) {
    anc.clear();
    for (int i = lambda[k]; i != -1; i = lambda[i]) anc.push_back(i);  // deepest first
    anc.insert(anc.begin(), k);
    int s = anc.back(), e = s + 1;
    for (auto it = anc.rbegin() + 1; it != anc.rend(); ++it) {  // the ancestors root first, then k
      if (*it != e) seg.push_back(s), seg.push_back(e), s = *it;
      e = *it + 1;
    }
    seg.push_back(s), seg.push_back(end[k]);  // k's run reaches the end of its subtree
    off.push_back(static_cast<int>(seg.size() / 2));
  }
  out = {off.data(), seg.data()};
  return true;
}

// [c0, c1) as blocks of 8 columns, then at most one of 4, of 2 and of 1: op(std::integral_constant<int, B>, c).
template <class Op>
inline void blocks_of(int c0, int c1, const Op& op) {
  int c = c0;
  for (; c + 8 <= c1; c += 8) op(std::integral_constant<int, 8>{}, c);
  if (c + 4 <= c1) op(std::integral_constant<int, 4>{}, c), c += 4;
  if (c + 2 <= c1) op(std::integral_constant<int, 2>{}, c), c += 2;
  if (c < c1) op(std::integral_constant<int, 1>{}, c);
}

// B entries x of row k (from column c) in the second sweep: x ← (x − Σ_t l_t · rows[t][c ..]) · inv over the
// n ancestors, the entries kept in registers through all of them (each entry sees the operations of the
// plain loop, in its order: the ancestors deepest first, then the scaling).
template <int B, class S>
inline void sweep_down_block(S* x, S* const* rows, const S* ls, int n, S inv, int c) {
  S acc[B];
  for (int j = 0; j < B; ++j) acc[j] = x[j];
  for (int t = 0; t < n; ++t) {
    const S* xi = rows[t] + c;
    const S l = ls[t];
    for (int j = 0; j < B; ++j) acc[j] -= l * xi[j];
  }
  for (int j = 0; j < B; ++j) x[j] = acc[j] * inv;
}

// B entries x of row k (from column c) in the first sweep: x ← x · inv, then rows[t][c ..] −= l_t · x for the
// n ancestors, x kept in registers (each entry sees the operations of the plain loop).
template <int B, class S>
inline void sweep_up_block(S* x, S* const* rows, const S* ls, int n, S inv, int c) {
  S acc[B];
  for (int j = 0; j < B; ++j) acc[j] = x[j] * inv, x[j] = acc[j];
  for (int t = 0; t < n; ++t) {
    S* xi = rows[t] + c;
    const S l = ls[t];
    for (int j = 0; j < B; ++j) xi[j] -= l * acc[j];
  }
}

// One state (doubles): B consecutive columns of a row as one vector type (GCC/Clang vector extensions); B = 1: a
// double. The vectors stay local (no vector crosses a call: no ABI dependence).
template <int B>
struct Cols;
template <>
struct Cols<8> {
  typedef double V __attribute__((vector_size(64)));
};
template <>
struct Cols<4> {
  typedef double V __attribute__((vector_size(32)));
};
template <>
struct Cols<2> {
  typedef double V __attribute__((vector_size(16)));
};
template <>
struct Cols<1> {
  typedef double V;
};

// B consecutive doubles as N vectors of W = min(B, PACK_WIDTH) doubles (pack.hpp: a register of the unit's
// instruction set, 2 at the baseline, 4 with AVX2, 8 with AVX-512), each one register: a vector type wider than a
// register is split through memory by the compiler (every operation a store and a load), N registers are not.
// Loaded and stored with memcpy (any alignment); every entry sees the operations written, in their order.
template <int B>
struct Regs {
  static constexpr int W = B < PACK_WIDTH ? B : PACK_WIDTH;
  static constexpr int N = B / W;
  using V = typename Cols<W>::V;
  V r[N];
  void load(const double* x) {
    for (int h = 0; h < N; ++h) std::memcpy(&r[h], x + W * h, sizeof(V));
  }
  void store(double* x) const {
    for (int h = 0; h < N; ++h) std::memcpy(x + W * h, &r[h], sizeof(V));
  }
};

// sweep_up_block on B columns of doubles held in registers: the same operations entry by entry.
template <int B>
inline void sweep_up_cols(double* x, double* const* rows, const double* ls, int n, double inv, int c) {
  Regs<B> a;
  a.load(x);
  for (int h = 0; h < Regs<B>::N; ++h) a.r[h] = a.r[h] * inv;
  a.store(x);
  for (int t = 0; t < n; ++t) {
    Regs<B> y;
    y.load(rows[t] + c);
    for (int h = 0; h < Regs<B>::N; ++h) y.r[h] = y.r[h] - ls[t] * a.r[h];
    y.store(rows[t] + c);
  }
}

// sweep_down_block on B columns of doubles held in registers: the same operations entry by entry.
template <int B>
inline void sweep_down_cols(double* x, double* const* rows, const double* ls, int n, double inv, int c) {
  Regs<B> acc;
  acc.load(x);
  for (int t = 0; t < n; ++t) {
    Regs<B> y;
    y.load(rows[t] + c);
    for (int h = 0; h < Regs<B>::N; ++h) acc.r[h] = acc.r[h] - ls[t] * y.r[h];
  }
  for (int h = 0; h < Regs<B>::N; ++h) acc.r[h] = acc.r[h] * inv;
  acc.store(x);
}

// The columns [c0, c1) of row x in the second sweep: x ← (x − Σ_t l_t · rows[t]) · inv, by blocks of columns
// (sweep_down_cols on doubles, sweep_down_block on Packs).
template <class S>
inline void sweep_down_row(S* x, S* const* rows, const S* ls, int n, S inv, int c0, int c1) {
  blocks_of(c0, c1, [&](auto B, int c) {
    if constexpr (std::is_same_v<S, double>)
      sweep_down_cols<B()>(x + c, rows, ls, n, inv, c);
    else
      sweep_down_block<B()>(x + c, rows, ls, n, inv, c);
  });
}

// ltl_sweeps' row pointers and factors (nv each).
template <class S>
struct SweepWork {
  std::vector<S*> rows;
  std::vector<S> ls;
  void resize(size_t nv) {
    if (rows.size() < nv) rows.resize(nv), ls.resize(nv);
  }
};

// The two sweeps of ltl_solve_Lt / ltl_solve_L on the columns of X's nv rows (`stride` apart) that
// `columns(op)` gives as runs op(c0, c1) (the columns are solved independently: the others are left as they
// are), each pivot's reciprocal taken once (a row is scaled by multiplications, not divisions). The first sweep
// runs on the runs, within those, that `runs(k, op)` gives row k: the caller's statement that row k is zero
// outside them when its turn comes (a pattern the sweep keeps: a row adds only into its ancestors, whose runs
// hold its own); the second sweep on all of `columns`. negate: X ← −M⁻¹ X instead, by the same operations on
// −X: the first sweep keeps its rows as they are until their turn and stores each finished row negated (an
// update adds l·(−x_k) where it subtracted l·x_k, the scaling multiplies by −1/L_kk), and the second sweep is
// linear. IEEE arithmetic being symmetric in sign, every entry is the negation of the plain result (up to the
// sign of a zero) with no pass of its own.
template <class S, class Columns, class Runs>
void ltl_sweeps(const ModelView& mv, const int* lambda, const S* L, S* X, size_t stride, const Columns& columns,
                const Runs& runs, bool negate) {
  const int nv = mv.nv;
  SweepWork<S>& w = thread_workspace<SweepWork<S>>(nv);  // row k's ancestors and their factors, deepest first
  S** rows = w.rows.data();
  S* ls = w.ls.data();
  auto ancestors = [&](int k, bool neg) {
    int n = 0;
    for (int i = lambda[k]; i != -1; i = lambda[i], ++n)
      rows[n] = X + static_cast<size_t>(i) * stride, ls[n] = neg ? -L[k * nv + i] : L[k * nv + i];
    return n;
  };
  // A few columns at a time, kept in registers through all of the row's ancestors: B Packs (sweep_*_block),
  // or for one state B doubles as one vector (sweep_*_cols). Each entry sees the same operations in the same
  // order either way (the lanes stay bit-identical to one state).
  for (int k = nv - 1; k >= 0; --k) {
    S* xk = X + static_cast<size_t>(k) * stride;
    const int n = ancestors(k, negate);
    const S inv = S(negate ? -1.0 : 1.0) / L[k * nv + k];
    runs(k, [&](int c0, int c1) {
      blocks_of(c0, c1, [&](auto B, int c) {
        if constexpr (std::is_same_v<S, double>)
          sweep_up_cols<B()>(xk + c, rows, ls, n, inv, c);
        else
          sweep_up_block<B()>(xk + c, rows, ls, n, inv, c);
      });
    });
  }
  for (int k = 0; k < nv; ++k) {
    S* xk = X + static_cast<size_t>(k) * stride;
    const int n = ancestors(k, false);
    const S inv = S(1.0) / L[k * nv + k];
    columns([&](int c0, int c1) { sweep_down_row(xk, rows, ls, n, inv, c0, c1); });
  }
}

// X ← M⁻¹ X = L⁻¹ L⁻ᵀ X on the ncols columns of X (nv, ncols) row-major at once (negate: X ← −M⁻¹ X).
template <class S>
void ltl_solve_rows(const ModelView& mv, const int* lambda, const S* L, S* X, int ncols, bool negate = false) {
  auto all = [&](auto&& op) { op(0, ncols); };
  ltl_sweeps(mv, lambda, L, X, static_cast<size_t>(ncols), all, [&](int, auto&& op) { all(op); }, negate);
}

// ltl_solve_rows on X = [B_1 … B_blocks], nv columns each, whose row k is zero outside the columns of k's
// ancestors and subtree in every block (RowSupport) — ∂τ/∂q and ∂τ/∂q̇. The first sweep keeps that pattern
// (a row adds into its ancestors, whose support holds its own), so it runs on the row's support only and the
// operations it skips would subtract products with zero (talos: 62 % of the first sweep's products). The
// second sweep fills the rows from the root down, on every column. A numbering that is not depth-first:
// ltl_solve_rows.
template <class S>
void ltl_solve_rows_tree_pattern(const ModelView& mv, const int* lambda, const S* L, S* X, int blocks,
                                 bool negate = false) {
  RowSupport support{};
  if (!row_supports(lambda, mv.nv, support)) return ltl_solve_rows(mv, lambda, L, X, blocks * mv.nv, negate);
  const int nv = mv.nv;
  auto runs = [&](int k, auto&& op) {  // row k's support in each block of nv columns
    for (int b = 0; b < blocks * nv; b += nv)
      for (int s = support.off[k]; s < support.off[k + 1]; ++s) op(b + support.seg[2 * s], b + support.seg[2 * s + 1]);
  };
  ltl_sweeps(mv, lambda, L, X, static_cast<size_t>(blocks * nv), [&](auto&& op) { op(0, blocks * nv); }, runs, negate);
}

template <class S>
struct LtlWork {
  std::vector<int> lambda;
  std::vector<S> Y;
  void resize(size_t) {}
};

// D = J M⁻¹ Jᵀ (m, m) for J (m, nv) row-major, L the factor of M(q). Row r of Y = J L⁻¹ solves Lᵀ y = J_rᵀ.
// A row of J is zero outside the support of its frame, and so is its row of Y (the solve only moves
// entries to ancestors): the sweep skips zero entries and D's products run over row r's nonzeros only.
template <class S>
void delassus_from_factor(const ModelView& mv, const int* lambda, const S* L, const S* J, int m, S* D,
                          std::vector<S>& Y) {
  const int nv = mv.nv;
  Y.assign(J, J + static_cast<size_t>(m) * nv);
  thread_local std::vector<int> nz, start;
  nz.clear();
  start.assign(static_cast<size_t>(m) + 1, 0);
  for (int r = 0; r < m; ++r) {
    S* y = Y.data() + static_cast<size_t>(r) * nv;
    for (int k = nv - 1; k >= 0; --k) {
      if (y[k] == S(0.0)) continue;
      y[k] = y[k] / L[k * nv + k];
      for (int i = lambda[k]; i != -1; i = lambda[i]) y[i] = y[i] - L[k * nv + i] * y[k];
    }
    for (int k = 0; k < nv; ++k)
      if (y[k] != S(0.0)) nz.push_back(k);
    start[r + 1] = static_cast<int>(nz.size());
  }
  for (int r = 0; r < m; ++r) {
    const S* yr = Y.data() + static_cast<size_t>(r) * nv;
    for (int c = 0; c <= r; ++c) {
      const S* yc = Y.data() + static_cast<size_t>(c) * nv;
      S x(0.0);
      for (int t = start[r]; t < start[r + 1]; ++t) x = x + yr[nz[t]] * yc[nz[t]];
      D[r * m + c] = D[c * m + r] = x;
    }
  }
}

}  // namespace fdcore

namespace fdcore {

// Dense Cholesky of a symmetric (m, m) A in place (lower triangle). Returns the lanes whose pivot is ≤ tol·max|A_ii|
// (S = double: 0 or 1; 0: factored in every lane, a failed lane's entries are not to be read).
// S: double, or Pack (each line the same operations, comparisons as lane masks: the lanes are bit-identical).
template <class S>
int dense_cholesky(S* A, int m, double tol) {
  using std::sqrt;
  S scale(0.0);
  for (int i = 0; i < m; ++i) scale = lane_max(scale, lane_abs(A[i * m + i]));
  for (int j = 0; j < m; ++j) {
    S d = A[j * m + j];
    for (int k = 0; k < j; ++k) d -= A[j * m + k] * A[j * m + k];
    const int bad = lanes_le(d, S(tol) * scale);
    if (bad) return bad;
    const S l = sqrt(d);
    A[j * m + j] = l;
    for (int i = j + 1; i < m; ++i) {
      S x = A[i * m + j];
      for (int k = 0; k < j; ++k) x -= A[i * m + k] * A[j * m + k];
      A[i * m + j] = x / l;
    }
  }
  return 0;
}

// x ← A⁻¹ x for the Cholesky factor of dense_cholesky.
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

// X ← A⁻¹ X on the ncols columns of X (m, ncols) row-major at once, for the Cholesky factor C of dense_cholesky
// (A = C Cᵀ): C Y = X from the first row down, then Cᵀ X = Y from the last row up. Each row is its entries less
// a sum over the rows already solved, times its pivot's reciprocal, a few columns in registers at a time (the
// sweeps' blocks above); m² ncols multiply-adds and no inverse formed. rows, ls: scratch of m entries each.
template <class S>
void dense_cholesky_solve_rows(const S* C, int m, S* X, int ncols, S** rows, S* ls) {
  const auto solve_row = [&](int i, int n) {  // row i ← (row i − Σ_t ls[t] rows[t]) / C_ii
    sweep_down_row(X + static_cast<size_t>(i) * ncols, rows, ls, n, S(1.0) / C[i * m + i], 0, ncols);
  };
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < i; ++k) rows[k] = X + static_cast<size_t>(k) * ncols, ls[k] = C[i * m + k];
    solve_row(i, i);
  }
  for (int i = m - 1; i >= 0; --i) {
    int n = 0;
    for (int k = i + 1; k < m; ++k) rows[n] = X + static_cast<size_t>(k) * ncols, ls[n++] = C[k * m + i];
    solve_row(i, n);
  }
}

// The constrained dynamics of M q̈ + h = τ + Jᵀ λ, J q̈ = c (c: the constraint's right-hand side, e.g.
// −γ − K_p e − K_d J q̇), by the Schur complement on the LᵀL factor (M is never inverted):
//
//     q̈_f = M⁻¹ (τ − h),   D = J M⁻¹ Jᵀ,   D λ = c − J q̈_f,   q̈ = q̈_f + M⁻¹ Jᵀ λ
//
// With mu > 0 the proximal iterations λ ← (D + μ 1)⁻¹ (c − J q̈_f + μ λ) (Carpentier, Budhiraja &
// Mansard, RSS 2021) converge to the minimum-norm λ also when J is rank-deficient; with mu = 0 a
// singular D is refused. L: the factor of M(q) (ltl_factor), tau_h = τ − h (nv,), J (m, nv), c (m,).
// Iterations stop when ‖D λ − (c − J q̈_f)‖∞ ≤ tol · max(1, ‖c − J q̈_f‖∞). Returns the iterations done
// (≥ 1), −1 for a singular D (mu = 0), or −2 when not converged.
struct KktResult {
  int iterations = 0;
  double residual = 0.0;  // ‖J q̈ − c‖∞
};

struct KktWork {
  std::vector<double> qf, Y, D, D0, rhs, x, col;
  void resize(size_t) {}
};

inline KktResult kkt_solve(const ModelView& mv, const int* lambda_d, const double* L, const double* tau_h,
                           const double* J, const double* c, int m, double mu, int max_iter, double tol,
                           double singular_tol, double* qdd, double* lam) {
  const int nv = mv.nv;
  KktWork& w = thread_workspace<KktWork>(0);  // sized below: a warm call allocates nothing
  std::vector<double>&qf = w.qf, &Y = w.Y, &D = w.D, &rhs = w.rhs, &x = w.x, &col = w.col;
  qf.assign(tau_h, tau_h + nv);
  D.resize(static_cast<size_t>(m) * m);
  rhs.resize(m);
  x.resize(m);
  col.resize(nv);
  ltl_solve_Lt(mv, lambda_d, L, qf.data());
  ltl_solve_L(mv, lambda_d, L, qf.data());
  delassus_from_factor(mv, lambda_d, L, J, m, D.data(), Y);
  for (int r = 0; r < m; ++r) {
    double jq = 0.0;
    for (int k = 0; k < nv; ++k) jq += J[r * nv + k] * qf[k];
    rhs[r] = c[r] - jq;
  }
  std::vector<double>& D0 = w.D0;  // D before the proximal shift and the factorisation
  D0.assign(D.begin(), D.end());
  double rhs_size = 1.0;
  for (int r = 0; r < m; ++r) rhs_size = std::max(rhs_size, std::fabs(rhs[r]));
  for (int i = 0; i < m; ++i) D[i * m + i] += mu;
  KktResult out;
  if (dense_cholesky<double>(D.data(), m, mu > 0.0 ? 0.0 : singular_tol) != 0) {
    out.iterations = -1;
    return out;
  }
  for (int r = 0; r < m; ++r) lam[r] = 0.0;
  const int iters = mu > 0.0 ? std::max(1, max_iter) : 1;
  for (int it = 1; it <= iters; ++it) {
    for (int r = 0; r < m; ++r) x[r] = rhs[r] + mu * lam[r];
    dense_cholesky_solve<double>(D.data(), m, x.data());
    for (int r = 0; r < m; ++r) lam[r] = x[r];
    out.iterations = it;
    if (mu <= 0.0) break;
    double dual = 0.0;  // ‖D λ − (c − J q̈_f)‖∞: the constraint rows' residual at this λ
    for (int r = 0; r < m; ++r) {
      double y = -rhs[r];
      for (int k = 0; k < m; ++k) y += D0[r * m + k] * lam[k];
      dual = std::max(dual, std::fabs(y));
    }
    if (dual <= tol * rhs_size) break;
    if (it == iters) out.iterations = -2;
  }
  // q̈ = q̈_f + M⁻¹ Jᵀ λ
  for (int k = 0; k < nv; ++k) {
    double s = 0.0;
    for (int r = 0; r < m; ++r) s += J[r * nv + k] * lam[r];
    col[k] = s;
  }
  ltl_solve_Lt(mv, lambda_d, L, col.data());
  ltl_solve_L(mv, lambda_d, L, col.data());
  for (int k = 0; k < nv; ++k) qdd[k] = qf[k] + col[k];
  for (int r = 0; r < m; ++r) {
    double jq = 0.0;
    for (int k = 0; k < nv; ++k) jq += J[r * nv + k] * qdd[k];
    out.residual = std::max(out.residual, std::fabs(jq - c[r]));
  }
  return out;
}

}  // namespace fdcore

namespace fdcore {

// The packed storage of the same factor (contacts.hpp): row k of L keeps only its entries at the ancestor dofs
// of k, root first, then the diagonal:
//
//     P[off_k + t] = L_{k, chain_k[t]}   (t < depth_k: chain_k[t] is the ancestor dof of k at depth t)
//     P[off_k + depth_k] = L_kk
//
// The ancestors of an ancestor i = chain_k[s] of k are chain_k[0 .. s), so row i's entries sit at the same
// positions as row k's first s + 1: the factor's update of row i by row k, and every solve along one chain,
// run over contiguous entries with no walk of λ_d in the inner loops.
struct DofTree {
  int nv = 0;
  std::vector<int> lambda, depth, off, chain;
  std::vector<std::int32_t> key;  // nb, then the parent, nv_i and idx_v arrays of the model it was built for
};

// The calling thread's DofTree for this model (rebuilt when the model's tree differs from the last one's). Not
// inlined, as thread_workspace (scratch.hpp).
[[gnu::noinline]] inline const DofTree& dof_tree(const ModelView& mv) {
  thread_local DofTree t;
  const size_t nb = static_cast<size_t>(mv.nb);
  bool same = t.key.size() == 3 * nb + 1 && t.key[0] == mv.nb && t.nv == mv.nv;
  for (size_t i = 0; same && i < nb; ++i)
    same = t.key[1 + i] == mv.parent[i] && t.key[1 + nb + i] == mv.nv_i[i] && t.key[1 + 2 * nb + i] == mv.idx_v[i];
  if (same) return t;
  const int nv = mv.nv;
  t.nv = nv;
  t.key.assign(3 * nb + 1, 0);
  t.key[0] = mv.nb;
  for (size_t i = 0; i < nb; ++i)
    t.key[1 + i] = mv.parent[i], t.key[1 + nb + i] = mv.nv_i[i], t.key[1 + 2 * nb + i] = mv.idx_v[i];
  t.lambda.resize(nv);
  t.depth.resize(nv);
  t.off.resize(static_cast<size_t>(nv) + 1);
  dof_parents(mv, t.lambda.data());
  t.off[0] = 0;
  for (int k = 0; k < nv; ++k) {  // λ_d(k) < k: the parent's depth is known
    t.depth[k] = t.lambda[k] == -1 ? 0 : t.depth[t.lambda[k]] + 1;
    t.off[k + 1] = t.off[k] + t.depth[k] + 1;
  }
  t.chain.resize(static_cast<size_t>(t.off[nv]));
  for (int k = 0; k < nv; ++k)
    for (int i = k, d = t.depth[k]; i != -1; i = t.lambda[i], --d) t.chain[t.off[k] + d] = i;
  return t;
}

// In place: P holds M's entries in the packed layout (row k: M_{k, chain_k[t]}, then M_kk) → L, as ltl_factor
// (each row scaled by the reciprocal of its pivot); dinv (nv,) ← 1 / L_kk for the solves below. With `rows`
// (nv,) only the rows k with rows[k] != 0 (a set closed under ancestors, holding a Schur complement) are read
// and factored. Returns −1, or the dof whose pivot is not positive (in some lane).
// S: double, or Pack (contacts.hpp's batches; the same operations lane by lane: the lanes are bit-identical).
template <class S>
int ltl_factor_packed(const DofTree& t, S* P, S* dinv, const char* rows = nullptr) {
  using std::sqrt;
  for (int k = t.nv - 1; k >= 0; --k) {
    if (rows && !rows[k]) continue;
    S* __restrict Lk = P + t.off[k];
    const int dk = t.depth[k];
    const S d = Lk[dk];
    if (lanes_le(d, 0.0)) return k;
    const S r = S(1.0) / d, a = sqrt(d), inv = a * r;  // 1/√d = √d / d: the division and the root overlap
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

// x ← L⁻ᵀ x and x ← L⁻¹ x on the packed factor (x (nv,), the whole joint space).
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

// y ← L⁻ᵀ y for each of `n` vectors y (the rows of Y, row stride `stride`) that are zero outside the chain of
// dof k (root … k), held in chain positions y[0 .. depth_k]. Lᵀ only moves entries to ancestors,
// so the solve stays on the chain, contiguous; the rows share the chain's rows of L and their independent
// updates interleave.
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

// A⁻¹ (m, m), full and exactly symmetric, from the Cholesky factor of dense_cholesky (A = C Cᵀ): W = C⁻¹ (lower
// triangular; its columns kept as the rows of Wt, so every sum below runs over contiguous entries), then
// A⁻¹ = Wᵀ W. Costs m³/3 multiply-adds and m divisions. Wt: (m, m) scratch.
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
