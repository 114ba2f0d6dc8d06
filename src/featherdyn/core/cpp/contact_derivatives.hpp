// Derivatives of the contacts' constrained dynamics and impulses (reference: featherdyn/algorithms/
// constraint_derivatives.py and api/constraint_derivatives.py, the same equations; docs/derivatives.md,
// "Constrained dynamics and impulses"). Point and frame contacts (contact_spec.hpp); loops take the reference.
//
// The dynamics is the root in (q̈, λ) of F₁ = ID(q, q̇, q̈) − Jᵀλ − τ, F₂ = J q̈ + γ + K_d J q̇; along x (q on
// fd.integrate's tangent, q̇, τ), with R₁ = ∂F₁/∂x and R₂ = ∂F₂/∂x at fixed q̈ and λ:
//
//     ∂λ/∂x = D⁻¹ (J M⁻¹ R₁ − R₂),   ∂q̈/∂x = M⁻¹ (Jᵀ ∂λ/∂x − R₁),   D = J M⁻¹ Jᵀ
//
// computed as the free derivative corrected (never a product with a dense nv × nv matrix but the last rank-m one):
//
//     A = −M⁻¹ R₁              (ABA's derivatives with the contact forces on the bodies: derivatives.hpp's
//                               solves with M's tree-sparse factor, ∂τ/∂q's zero pattern kept)
//     Z = J A + R₂             (how far the free q̈ would leave the contacts' acceleration)
//     ∂λ/∂x = −D⁻¹ Z,   ∂q̈/∂x = A + (M⁻¹ Jᵀ) ∂λ/∂x
//
//   R₁ along q: RNEA's ∂τ/∂q (derivatives.hpp) with the contact forces on the bodies (f_ext + f_c), plus each
//               force's turn with its reference: −ᶠJᵀ G(f_a) ᶠJ, f_a = Bᵀ λ₆ the force in the frame's axes,
//               G = 0 (LOCAL), [[n]×, 0; [f]×, 0] (LOCAL_WORLD_ALIGNED), [[n]×, [f]×; [f]×, 0] (WORLD);
//               along q̇: RNEA's ∂τ/∂q̇; along τ: −1 (so A = M⁻¹)
//   R₂:         the frame's acceleration (classical for a point) and velocity derivatives at q̈ in its reference
//               (kinematics_derivatives.hpp): ∂a/∂x + K_d ∂v/∂x; zero along τ
//
// Impulses (M (v⁺ − v⁻) = JᵀΛ, J v⁺ = −e J v⁻): Λ = −(1 + e) D⁻¹ J v⁻, v⁺ = v⁻ + M⁻¹ Jᵀ Λ; then the same
// correction with R₁ along q from RNEA at zero velocity without gravity (M w − JᵀΛ, w = v⁺ − v⁻) plus the turn,
// R₂ = ∂(J u)/∂q at u = v⁺ + e v⁻, and along v⁻ R₁ = −M (A = 1), R₂ = e J. A row of J is zero off the dofs of
// its frame's chain (root … its body): products with J run over those columns. D by its Cholesky factor;
// CONSTRAINT when D is singular (dependent contacts): the caller's reference path takes them.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#include "contacts.hpp"
#include "crba.hpp"
#include "derivatives.hpp"
#include "frames.hpp"
#include "kinematics_derivatives.hpp"
#include "ltl.hpp"

namespace fdcore {

// The kernels below are templates on the scalar S: double (one state) or Pack (PACK_WIDTH states, simd_groups.hpp's
// batches), with the same operations in the same order, so every lane is bit-identical to its one-state result.
// What decides the control flow (the contacts, their rows' chains, the references) depends on the model and the
// specs only; what depends on the state (a pivot of M or of D) fails the call, for a Pack in any lane.
template <class S>
struct ContactDerivWork {
  std::vector<S> f, dq, dv, L, kin, J, R1, X, Z, Y, Pt, D, scratch, u, acc;
  std::vector<int> supp, off;  // row r of J: its nonzero columns supp[off[r] .. off[r + 1])
  std::vector<const S*> rows;  // add_product's operands
  std::vector<S> coef;
  std::vector<S*> solved;      // dense_cholesky_solve_rows' rows (its factors in coef)
  std::vector<int> bodies;     // the bodies on some contact's support, ascending (parents first)
  std::vector<char> on_support;  // body b is among them
  WorldPassWork<S> pass;       // their placements, columns and motion (contact_terms)
  void resize(size_t nb) { pass.resize(nb); }
};

namespace contact_deriv {

// f_a = Bᵀ λ₆: contact s's force (its rows of λ₆, the rest zero) in the frame's axes, about its origin.
template <class S>
inline Force<S> frame_force(const ContactSpec& s, const S* lam, const Mat3<S>& R, const Vec3<S>& p) {
  S l6[6] = {S(0.0), S(0.0), S(0.0), S(0.0), S(0.0), S(0.0)};
  for (int r = 0; r < s.rows; ++r) l6[6 - s.rows + r] = lam[r];
  Vec3<S> n{l6[0], l6[1], l6[2]};
  const Vec3<S> f{l6[3], l6[4], l6[5]};
  if (s.ref == LOCAL) return {n, f};
  if (s.ref == WORLD) n = n - cross(p, f);  // about the world origin → about the frame's
  return {mul_transpose(R, n), mul_transpose(R, f)};
}

// f_a added to the external force (nb, 6) of the frame's body: [R n + p × R f; R f], (R, p) the frame in the body.
template <class S>
inline void add_to_body(const ModelView& mv, int frame, const Force<S>& fa, S* f) {
  const int b = mv.frame_body[frame];
  if (b < 0) return;
  const Mat3<S> R = load9<S>(mv.frame_R + 9 * frame);
  const Vec3<S> p = load3<S>(mv.frame_p + 3 * frame), ff = R * fa.f, n = R * fa.n + cross(p, ff);
  S* o = f + 6 * b;
  o[0] += n.x, o[1] += n.y, o[2] += n.z, o[3] += ff.x, o[4] += ff.y, o[5] += ff.z;
}

// R₁ −= ᶠJᵀ G(f_a) ᶠJ, with ᶠJ (LOCAL) from the reference's Jacobian J (6, nv) and the frame's pose (R, p), over
// the frame's chain supp[0 .. len) (J's other columns are zero, and so are ᶠJ's and G ᶠJ's).
template <class S>
inline void add_turn(const ModelView& mv, int ref, const S* J, const Mat3<S>& R, const Vec3<S>& p, const Force<S>& fa,
                     const int* supp, int len, ContactDerivWork<S>& w, S* R1) {
  if (ref == LOCAL) return;
  const int nv = mv.nv;
  w.scratch.resize(static_cast<size_t>(12) * nv);
  S* JL = w.scratch.data();
  S* GJ = JL + 6 * nv;
  for (int t = 0; t < len; ++t) {
    const int k = supp[t];
    const Vec3<S> om{J[k], J[nv + k], J[2 * nv + k]}, vl{J[3 * nv + k], J[4 * nv + k], J[5 * nv + k]};
    const Vec3<S> wL = mul_transpose(R, om), vL = mul_transpose(R, ref == WORLD ? vl - cross(p, om) : vl);
    Vec3<S> top = cross(fa.n, wL);
    if (ref == WORLD) top += cross(fa.f, vL);
    const Vec3<S> bottom = cross(fa.f, wL);
    const S col[12] = {wL.x, wL.y, wL.z, vL.x, vL.y, vL.z, top.x, top.y, top.z, bottom.x, bottom.y, bottom.z};
    for (int r = 0; r < 6; ++r) JL[r * nv + k] = col[r], GJ[r * nv + k] = col[6 + r];
  }
  for (int ti = 0; ti < len; ++ti) {
    const int i = supp[ti];
    for (int r = 0; r < 6; ++r) {
      const S a = JL[r * nv + i];
      for (int tj = 0; tj < len; ++tj) R1[i * nv + supp[tj]] -= a * GJ[r * nv + supp[tj]];
    }
  }
}

// Whether a contact's force is held in other axes than its frame's, and so turns with q (add_turn; LOCAL: none).
inline bool any_turn(const ContactSpec* specs, int nc) {
  for (int k = 0; k < nc; ++k)
    if (specs[k].ref != LOCAL) return true;
  return false;
}

// x[c, c + B) += Σ_t a_t · rows[t][c, c + B), the B entries held in registers (ltl.hpp's Regs) through all n terms.
template <int B>
inline void add_rows_cols(double* x, const double* const* rows, const double* a, int n, int c) {
  Regs<B> acc;
  acc.load(x + c);
  for (int t = 0; t < n; ++t) {
    Regs<B> y;
    y.load(rows[t] + c);
    for (int h = 0; h < Regs<B>::N; ++h) acc.r[h] = acc.r[h] + a[t] * y.r[h];
  }
  acc.store(x + c);
}

// add_rows_cols on B Packs: B sums at once, each waiting on its own additions only (one sum at a time waits on
// every addition's latency), the same operations entry by entry.
template <int B, class S>
inline void add_rows_block(S* x, const S* const* rows, const S* a, int n, int c) {
  S acc[B];
  for (int j = 0; j < B; ++j) acc[j] = x[c + j];
  for (int t = 0; t < n; ++t) {
    const S* y = rows[t] + c;
    for (int j = 0; j < B; ++j) acc[j] = acc[j] + a[t] * y[j];
  }
  for (int j = 0; j < B; ++j) x[c + j] = acc[j];
}

// C (p, ncols) += A (p, k) B (k, ncols), row-major, in C's first `cols` columns (all when cols < 0); row i of A
// restricted to the columns idx[off[i] .. off[i + 1]) when idx is given (the others zero), every column otherwise.
// Each entry: C_ic + Σ_t A_it B_tc in t's order (a few columns at a time in registers: doubles as Regs, Packs as
// an array of them).
template <class S>
inline void add_product(const S* A, int p, int k, const S* B, int ncols, S* C, const int* idx, const int* off,
                        ContactDerivWork<S>& w, int cols = -1) {
  w.rows.resize(static_cast<size_t>(k)), w.coef.resize(static_cast<size_t>(k));
  for (int i = 0; i < p; ++i) {
    const S* Ai = A + static_cast<size_t>(i) * k;
    int n = 0;
    const int t0 = idx ? off[i] : 0, t1 = idx ? off[i + 1] : k;
    for (int s = t0; s < t1; ++s) {
      const int t = idx ? idx[s] : s;
      w.rows[n] = B + static_cast<size_t>(t) * ncols, w.coef[n++] = Ai[t];
    }
    S* Ci = C + static_cast<size_t>(i) * ncols;
    blocks_of(0, cols < 0 ? ncols : cols, [&](auto Bw, int c) {
      if constexpr (std::is_same_v<S, double>)
        add_rows_cols<Bw()>(Ci, w.rows.data(), w.coef.data(), n, c);
      else
        add_rows_block<Bw()>(Ci, w.rows.data(), w.coef.data(), n, c);
    });
  }
}

// The nonzero columns of the contacts' rows of J: the dofs of each frame's chain (root … its body); and the
// bodies on those chains (w.bodies).
template <class S>
inline void row_supports(const ModelView& mv, const ContactSpec* specs, int nc, int m, ContactDerivWork<S>& w) {
  w.supp.clear();
  w.off.assign(static_cast<size_t>(m) + 1, 0);
  w.on_support.assign(static_cast<size_t>(mv.nb), 0);
  for (int k = 0, row = 0; k < nc; row += specs[k].rows, ++k) {
    const size_t first = w.supp.size();
    for (int b = mv.frame_body[specs[k].frame]; b != -1; b = mv.parent[b]) {
      w.on_support[b] = 1;
      for (int c = 0; c < mv.nv_i[b]; ++c) w.supp.push_back(mv.idx_v[b] + c);
    }
    std::sort(w.supp.begin() + static_cast<std::ptrdiff_t>(first), w.supp.end());
    const size_t len = w.supp.size() - first;
    for (int r = 1; r < specs[k].rows; ++r)  // the contact's other rows: the same columns
      for (size_t s = 0; s < len; ++s) w.supp.push_back(w.supp[first + s]);
    for (int r = 0; r < specs[k].rows; ++r) w.off[row + r + 1] = w.off[row + r] + static_cast<int>(len);
  }
  w.bodies.clear();  // ascending, which is parents first (parent[i] < i)
  for (int b = 0; b < mv.nb; ++b)
    if (w.on_support[b]) w.bodies.push_back(b);
}

// With L = M's factor and J (w.J, m rows): P = M⁻¹ Jᵀ (w.Pt, (nv, m)) and D = J P factored (w.D).
// CONSTRAINT when D is singular (dependent contacts; for a Pack, in some lane).
template <class S>
inline std::int64_t delassus(const ModelView& mv, const int* lambda, int m, double singular_tol,
                             ContactDerivWork<S>& w) {
  const int nv = mv.nv;
  const size_t mm = static_cast<size_t>(m);
  w.Pt.resize(static_cast<size_t>(nv) * mm);
  for (int r = 0; r < m; ++r)
    for (int i = 0; i < nv; ++i) w.Pt[static_cast<size_t>(i) * mm + r] = w.J[static_cast<size_t>(r) * nv + i];
  ltl_solve_rows(mv, lambda, w.L.data(), w.Pt.data(), m);
  w.D.assign(mm * mm, S(0.0));
  add_product(w.J.data(), m, nv, w.Pt.data(), m, w.D.data(), w.supp.data(), w.off.data(), w);
  if (dense_cholesky<S>(w.D.data(), m, singular_tol)) return make_status(CONSTRAINT, ARG_OUT, m);
  return OK;
}

// The free derivatives A (w.X, (nv, ncols)) and R₂ (w.Z, (m, ncols)) of ncols directions → the constrained ones:
// Z ← J A + R₂, ∂λ = −D⁻¹ Z (w.Y, by D's factor), ∂q̈ = A + P ∂λ (in w.X). J A is added in Z's first `free`
// columns only: the caller has put the whole of Z in the others (where A = 1, J A = J).
template <class S>
inline void correct(const ModelView& mv, int m, int ncols, int free, ContactDerivWork<S>& w) {
  const int nv = mv.nv;
  add_product(w.J.data(), m, nv, w.X.data(), ncols, w.Z.data(), w.supp.data(), w.off.data(), w, free);
  w.Y.resize(static_cast<size_t>(m) * ncols);
  for (size_t k = 0; k < w.Y.size(); ++k) w.Y[k] = -w.Z[k];
  w.solved.resize(static_cast<size_t>(m)), w.coef.resize(static_cast<size_t>(m));
  dense_cholesky_solve_rows(w.D.data(), m, w.Y.data(), ncols, w.solved.data(), w.coef.data());
  add_product(w.Pt.data(), nv, m, w.Y.data(), ncols, w.X.data(), nullptr, nullptr, w);
}

// Block b (nv columns) of the rows of T (rows, ncols) into out (rows, nv).
template <class S>
inline void block_out(const S* T, int rows, int ncols, int b, int nv, S* out) {
  for (int r = 0; r < rows; ++r)
    std::copy_n(T + static_cast<size_t>(r) * ncols + static_cast<size_t>(b) * nv, nv, out + static_cast<size_t>(r) * nv);
}

// The contacts' rows J (m, nv) into w.J and their forces λ: on the bodies (w.f, which holds f_ext or zeros), and
// their turn into R1 (nv, nv). The outputs of kinematics_derivatives per contact are left in w.kin when `qd` is
// given (at (q, qd, qdd); qdd may be nullptr without `accelerations`): ∂v/∂q, ∂v/∂q̇ = J, and with `accelerations` a
// point's ∂a^c/∂(q, q̇) or a frame's ∂a/∂(q, q̇); with qd nullptr only J is formed. One world pass serves every
// contact (w.pass over w.bodies, each placed once, not once a contact). `placed`: an earlier call at the same q
// has formed the placements, the columns and J (w.J, and ∂v/∂q̇ in w.kin), which do not depend on q̇; this one
// forms the motion and what depends on it only.
template <class S>
inline void contact_terms(const ModelView& mv, const S* q, const S* qd, const S* qdd, bool accelerations,
                          const S* lam, const ContactSpec* specs, int nc, ContactDerivWork<S>& w, S* R1,
                          bool placed = false) {
  const int nv = mv.nv;
  const size_t blk = static_cast<size_t>(6) * nv;
  w.pass.W.resize(static_cast<size_t>(nv));
  for (const int b : w.bodies) {
    if (!placed) world_place_body(mv, b, q, w.pass);
    if (qd != nullptr) world_move_body(mv, b, qd, qdd, w.pass);
  }
  int row = 0;
  for (int k = 0; k < nc; ++k) {
    const ContactSpec& s = specs[k];
    S* kin = w.kin.data() + 6 * blk * static_cast<size_t>(k);
    S* const J6 = kin + blk;  // ∂v/∂q̇: the frame's Jacobian in its reference
    S* outs[6] = {qd != nullptr ? kin : nullptr, placed ? nullptr : J6, nullptr, nullptr, nullptr, nullptr};
    if (accelerations) {
      const int a = s.rows == 3 ? 4 : 2;
      outs[a] = kin + a * blk, outs[a + 1] = kin + (a + 1) * blk;
    }
    Pose<S> pose;
    frame_motion_derivatives(mv, s.frame, nullptr, s.ref, outs, &pose, w.pass);
    if (!placed)
      for (int r = 0; r < s.rows; ++r)
        std::copy(J6 + (6 - s.rows + r) * nv, J6 + (7 - s.rows + r) * nv, w.J.data() + (row + r) * nv);
    if (lam != nullptr) {
      const Force<S> fa = frame_force(s, lam + row, pose.R, pose.p);
      add_to_body(mv, s.frame, fa, w.f.data());
      if (R1 != nullptr)
        add_turn(mv, s.ref, J6, pose.R, pose.p, fa, w.supp.data() + w.off[row], w.off[row + 1] - w.off[row], w,
                 R1);
    }
    row += s.rows;
  }
}

// The calling thread's workspace with room for nc contacts' frame derivatives and m rows, J's row supports set.
template <class S>
inline ContactDerivWork<S>& workspace(const ModelView& mv, const ContactSpec* specs, int nc, int m) {
  ContactDerivWork<S>& w = thread_workspace<ContactDerivWork<S>>(mv.nb);
  w.kin.resize(static_cast<size_t>(36) * static_cast<size_t>(mv.nv) * static_cast<size_t>(nc));
  w.J.resize(static_cast<size_t>(m) * static_cast<size_t>(mv.nv));
  row_supports(mv, specs, nc, m, w);
  return w;
}

// Each contact row's entries of R₂ in block b (nv columns) of w.Z (m, ncols): f(s, kin, src, z) with s the row's
// contact, kin its frame derivatives (w.kin: six (6, nv) outputs of kinematics_derivatives), src the row's offset in
// one of them, and z the row's nv entries to write.
template <class S, class F>
inline void each_kin_row(const ModelView& mv, const ContactSpec* specs, int nc, int ncols, int b, ContactDerivWork<S>& w,
                         const F& f) {
  const int nv = mv.nv;
  const size_t blk = static_cast<size_t>(6) * nv;
  for (int k = 0, row = 0; k < nc; row += specs[k].rows, ++k) {
    const ContactSpec& s = specs[k];
    const S* kin = w.kin.data() + 6 * blk * static_cast<size_t>(k);
    for (int r = 0; r < s.rows; ++r)
      f(s, kin, static_cast<size_t>(6 - s.rows + r) * nv,
        w.Z.data() + static_cast<size_t>(row + r) * ncols + static_cast<size_t>(b) * nv);
  }
}

// The constrained dynamics' R₂ in block b: the output a_point (a point's rows) or a_frame (a frame's) plus K_d · the
// output v_out (∂a/∂x + K_d ∂v/∂x).
template <class S>
inline void damped_rows(const ModelView& mv, const ContactSpec* specs, int nc, int ncols, int b, int a_point,
                        int a_frame, int v_out, ContactDerivWork<S>& w) {
  const size_t blk = static_cast<size_t>(6) * mv.nv;
  each_kin_row(mv, specs, nc, ncols, b, w, [&](const ContactSpec& s, const S* kin, size_t src, S* z) {
    const S *ka = kin + (s.rows == 3 ? a_point : a_frame) * blk + src, *kv = kin + v_out * blk + src;
    const S kd(s.kd);
    for (int j = 0; j < mv.nv; ++j) z[j] = ka[j] + kd * kv[j];
  });
}

// The impulses' Z in block b: scale · the output `out` (R₂ = ∂(J u)/∂q, or (1 + e) J along v⁻).
template <class S>
inline void scaled_rows(const ModelView& mv, const ContactSpec* specs, int nc, int ncols, int b, int out, double scale,
                        ContactDerivWork<S>& w) {
  const size_t blk = static_cast<size_t>(6) * mv.nv;
  const S sc(scale);
  each_kin_row(mv, specs, nc, ncols, b, w, [&](const ContactSpec&, const S* kin, size_t src, S* z) {
    const S* k = kin + out * blk + src;
    for (int j = 0; j < mv.nv; ++j) z[j] = sc * k[j];
  });
}

// w.R1 (nv, nv) zeroed when some contact's force turns with q (any_turn; contact_terms adds the turns there), else
// nullptr.
template <class S>
inline S* turn_matrix(const ContactSpec* specs, int nc, size_t n, ContactDerivWork<S>& w) {
  if (!any_turn(specs, nc)) return nullptr;
  w.R1.assign(n * n, S(0.0));
  return w.R1.data();
}

}  // namespace contact_deriv

// ∂q̈/∂(q, q̇, τ) (nv, nv) and ∂λ/∂(q, q̇, τ) (m, nv) at the solution (qdd, lam) of the contacts' constrained
// dynamics at (q, q̇, τ, f_ext) (contacts.hpp), into out[0..2] and out[3..5]. Returns OK, SINGULAR, or CONSTRAINT
// (dependent contacts).
template <class S>
std::int64_t contact_dynamics_derivatives(const ModelView& mv, const S* q, const S* qd, const S* f_ext, const S* qdd,
                                          const S* lam, const ContactSpec* specs, int nc, int m, double singular_tol,
                                          S* const* out) {
  using namespace contact_deriv;
  const int nv = mv.nv, w3 = 3 * nv;
  const size_t n = static_cast<size_t>(nv);
  ContactDerivWork<S>& w = workspace<S>(mv, specs, nc, m);
  const int* lambda = dof_tree(mv).lambda.data();
  w.f.assign(static_cast<size_t>(6) * mv.nb, S(0.0));
  if (f_ext) std::copy(f_ext, f_ext + 6 * mv.nb, w.f.begin());
  S* R1 = turn_matrix(specs, nc, n, w);
  contact_terms(mv, q, qd, qdd, true, lam, specs, nc, w, R1);
  w.dq.resize(n * n), w.dv.resize(n * n), w.L.resize(n * n);
  rnea_derivatives(mv, q, qd, qdd, w.f.data(), true, w.dq.data(), w.dv.data(), w.L.data());
  const int bad = ltl_factor(mv, lambda, w.L.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  // R₁ = [∂τ/∂q + turn | ∂τ/∂q̇ | −1] side by side, then A = −M⁻¹ R₁ in place (each block zero off ∂τ/∂q's pattern)
  w.X.resize(n * w3);
  for (int i = 0; i < nv; ++i) {
    S* x = w.X.data() + static_cast<size_t>(i) * w3;
    if (R1)
      for (int j = 0; j < nv; ++j) x[j] = w.dq[i * n + j] + R1[i * n + j];
    else
      std::copy_n(w.dq.data() + i * n, nv, x);
    std::copy_n(w.dv.data() + i * n, nv, x + nv);
    std::fill(x + 2 * nv, x + w3, S(0.0));
    x[2 * nv + i] = S(-1.0);
  }
  ltl_solve_rows_tree_pattern(mv, lambda, w.L.data(), w.X.data(), 3, true);
  // R₂ = [∂a/∂q + K_d ∂v/∂q | ∂a/∂q̇ + K_d ∂v/∂q̇ | 0], the contacts' rows (classical acceleration for a point)
  w.Z.assign(static_cast<size_t>(m) * w3, S(0.0));
  damped_rows(mv, specs, nc, w3, 0, 4, 2, 0, w);
  damped_rows(mv, specs, nc, w3, 1, 5, 3, 1, w);
  if (const std::int64_t st = delassus(mv, lambda, m, singular_tol, w); st != OK) return st;
  correct(mv, m, w3, w3, w);
  for (int b = 0; b < 3; ++b) {
    block_out(w.X.data(), nv, w3, b, nv, out[b]);
    block_out(w.Y.data(), m, w3, b, nv, out[3 + b]);
  }
  return OK;
}

namespace contact_deriv {

// The impulse v⁺ (nv,), Λ (m,) of an impact with the contacts (restitution e), leaving M's factor (w.L), the contacts'
// rows and D = J M⁻¹ Jᵀ's factor in w for the derivatives, which need them dense (the impact alone: contacts.hpp's
// impulse_dynamics, the same equations on M's packed factor, equal to round-off)::
//     Λ = −(1 + e) D⁻¹ J v⁻,   v⁺ = v⁻ + M⁻¹ Jᵀ Λ
// Returns OK, SINGULAR, or CONSTRAINT (dependent contacts).
template <class S>
std::int64_t impulse(const ModelView& mv, const S* q, const S* vm, const ContactSpec* specs, int nc, int m, double e,
                     double singular_tol, S* vp, S* Lam, ContactDerivWork<S>& w) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv);
  const int* lambda = dof_tree(mv).lambda.data();
  w.L.resize(n * n);
  crba(mv, q, w.L.data());
  const int bad = ltl_factor(mv, lambda, w.L.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  contact_terms<S>(mv, q, nullptr, nullptr, false, nullptr, specs, nc, w, nullptr);
  if (const std::int64_t st = delassus(mv, lambda, m, singular_tol, w); st != OK) return st;
  const S minus_1e(-(1.0 + e));
  for (int r = 0; r < m; ++r) {
    S s(0.0);
    for (int t = w.off[r]; t < w.off[r + 1]; ++t) s = s + w.J[static_cast<size_t>(r) * n + w.supp[t]] * vm[w.supp[t]];
    Lam[r] = minus_1e * s;
  }
  dense_cholesky_solve<S>(w.D.data(), m, Lam);
  for (int i = 0; i < nv; ++i) {
    S s = vm[i];
    for (int r = 0; r < m; ++r) s = s + w.Pt[i * static_cast<size_t>(m) + r] * Lam[r];
    vp[i] = s;
  }
  return OK;
}

}  // namespace contact_deriv

// The impulse v⁺ (nv,), Λ (m,) of an impact with the contacts (restitution e) and its derivatives ∂v⁺/∂(q, v⁻)
// (nv, nv), ∂Λ/∂(q, v⁻) (m, nv) into out[0..3], v⁺ and Λ into out[4], out[5]. Returns OK, SINGULAR, or CONSTRAINT.
template <class S>
std::int64_t impulse_dynamics_derivatives(const ModelView& mv, const S* q, const S* vm, const ContactSpec* specs,
                                          int nc, int m, double e, double singular_tol, S* const* out) {
  using namespace contact_deriv;
  const int nv = mv.nv, w2 = 2 * nv;
  const size_t n = static_cast<size_t>(nv);
  ContactDerivWork<S>& w = workspace<S>(mv, specs, nc, m);
  const int* lambda = dof_tree(mv).lambda.data();
  S *vp = out[4], *Lam = out[5];
  if (const std::int64_t st = impulse(mv, q, vm, specs, nc, m, e, singular_tol, vp, Lam, w); st != OK) return st;
  const S se(e);
  // R₁ along q: RNEA at zero velocity without gravity, a = v⁺ − v⁻, with Λ on the bodies, plus the turn;
  // R₂ = ∂(J u)/∂q at u = v⁺ + e v⁻. A = [−M⁻¹ R₁ | 1], R₂ = [∂(J u)/∂q | e J], so Z's v⁻ block J·1 + e J is
  // (1 + e) J whole.
  w.u.resize(n), w.acc.resize(n);
  for (int i = 0; i < nv; ++i) w.u[i] = vp[i] + se * vm[i], w.acc[i] = vp[i] - vm[i];
  w.f.assign(static_cast<size_t>(6) * mv.nb, S(0.0));
  S* R1 = turn_matrix(specs, nc, n, w);
  contact_terms(mv, q, w.u.data(), static_cast<const S*>(nullptr), false, Lam, specs, nc, w, R1, true);
  w.dq.resize(n * n);
  rnea_derivatives(mv, q, static_cast<const S*>(nullptr), w.acc.data(), w.f.data(), false, w.dq.data(),
                   static_cast<S*>(nullptr), static_cast<S*>(nullptr));  // at rest: q̇ = 0
  if (R1)
    for (size_t k = 0; k < n * n; ++k) w.dq[k] = w.dq[k] + R1[k];
  ltl_solve_rows_tree_pattern(mv, lambda, w.L.data(), w.dq.data(), 1, true);
  w.X.resize(n * w2);
  for (int i = 0; i < nv; ++i) {
    S* x = w.X.data() + static_cast<size_t>(i) * w2;
    std::copy_n(w.dq.data() + i * n, nv, x);
    std::fill(x + nv, x + w2, S(0.0));
    x[nv + i] = S(1.0);
  }
  w.Z.resize(static_cast<size_t>(m) * w2);
  scaled_rows(mv, specs, nc, w2, 0, 0, 1.0, w);
  scaled_rows(mv, specs, nc, w2, 1, 1, 1.0 + e, w);
  correct(mv, m, w2, nv, w);
  for (int b = 0; b < 2; ++b) {
    block_out(w.X.data(), nv, w2, b, nv, out[b]);
    block_out(w.Y.data(), m, w2, b, nv, out[2 + b]);
  }
  return OK;
}

}  // namespace fdcore
