// Derivatives of the contacts' constrained dynamics and impulses (reference: featherdyn/algorithms/
// constraint_derivatives.py and api/constraint_derivatives.py, the same equations; docs/derivatives.md,
// "Constrained dynamics and impulses"). Point and frame contacts (contact_spec.hpp); loops take the reference.
//
// The dynamics is the root in (q̈, λ) of F₁ = ID(q, q̇, q̈) − Jᵀλ − τ, F₂ = J q̈ + γ + K_d J q̇; along x (q on
// fd.integrate's tangent, q̇, τ), with R₁ = ∂F₁/∂x and R₂ = ∂F₂/∂x at fixed q̈ and λ:
//
//     ∂λ/∂x = D⁻¹ (J M⁻¹ R₁ − R₂),   ∂q̈/∂x = M⁻¹ (Jᵀ ∂λ/∂x − R₁),   D = J M⁻¹ Jᵀ
//
//   R₁ along q: RNEA's ∂τ/∂q (derivatives.hpp) with the contact forces on the bodies (f_ext + f_c), plus each
//               force's turn with its reference: −ᶠJᵀ G(f_a) ᶠJ, f_a = Bᵀ λ₆ the force in the frame's axes,
//               G = 0 (LOCAL), [[n]×, 0; [f]×, 0] (LOCAL_WORLD_ALIGNED), [[n]×, [f]×; [f]×, 0] (WORLD);
//               along q̇: RNEA's ∂τ/∂q̇; along τ: −1
//   R₂:         the frame's acceleration (classical for a point) and velocity derivatives at q̈ in its reference
//               (kinematics_derivatives.hpp): ∂a/∂x + K_d ∂v/∂x
//
// Impulses (M (v⁺ − v⁻) = JᵀΛ, J v⁺ = −e J v⁻): Λ = −(1 + e) D⁻¹ J v⁻, v⁺ = v⁻ + M⁻¹ Jᵀ Λ; then the same solve
// with R₁ along q from RNEA at zero velocity without gravity (M w − JᵀΛ, w = v⁺ − v⁻) plus the turn, R₂ = ∂(J u)/∂q
// at u = v⁺ + e v⁻, and R₁ = −M, R₂ = e J along v⁻. M⁻¹ is applied through M's LᵀL factor (ltl.hpp), D by its
// Cholesky factor. CONSTRAINT when D is singular (dependent contacts): the caller's reference path takes them.
#pragma once

#include <algorithm>
#include <vector>

#include "contacts.hpp"
#include "crba.hpp"
#include "derivatives.hpp"
#include "frames.hpp"
#include "kinematics_derivatives.hpp"
#include "ltl.hpp"

namespace fdcore {

struct ContactDerivWork {
  std::vector<double> f, dq, dv, M, L, kin, J, R2q, R2v, JL, MJ, D, Dinv, G, Gt, K, JtT, R1t, Xt, Yt;
  std::vector<int> lambda;
  void resize(size_t) {}
};

namespace contact_deriv {

// f_a = Bᵀ λ₆: contact s's force (its rows of λ₆, the rest zero) in the frame's axes, about its origin.
inline Force<double> frame_force(const ContactSpec& s, const double* lam, const Mat3<double>& R, const Vec3<double>& p) {
  double l6[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int r = 0; r < s.rows; ++r) l6[6 - s.rows + r] = lam[r];
  Vec3<double> n{l6[0], l6[1], l6[2]};
  const Vec3<double> f{l6[3], l6[4], l6[5]};
  if (s.ref == LOCAL) return {n, f};
  if (s.ref == WORLD) n = n - cross(p, f);  // about the world origin → about the frame's
  return {mul_transpose(R, n), mul_transpose(R, f)};
}

// f_a added to the external force (nb, 6) of the frame's body: [R n + p × R f; R f], (R, p) the frame in the body.
inline void add_to_body(const ModelView& mv, int frame, const Force<double>& fa, double* f) {
  const int b = mv.frame_body[frame];
  if (b < 0) return;
  const Mat3<double> R = load9<double>(mv.frame_R + 9 * frame);
  const Vec3<double> p = load3<double>(mv.frame_p + 3 * frame), ff = R * fa.f, n = R * fa.n + cross(p, ff);
  double* o = f + 6 * b;
  o[0] += n.x, o[1] += n.y, o[2] += n.z, o[3] += ff.x, o[4] += ff.y, o[5] += ff.z;
}

// R₁ −= ᶠJᵀ G(f_a) ᶠJ, with ᶠJ (LOCAL) from the reference's Jacobian J (6, nv) and the frame's pose (R, p).
inline void add_turn(const ModelView& mv, int ref, const double* J, const Mat3<double>& R, const Vec3<double>& p,
                     const Force<double>& fa, ContactDerivWork& w, double* R1) {
  if (ref == LOCAL) return;
  const int nv = mv.nv;
  w.JL.resize(static_cast<size_t>(12) * nv);
  double* JL = w.JL.data();
  double* GJ = JL + 6 * nv;
  for (int k = 0; k < nv; ++k) {
    const Vec3<double> om{J[k], J[nv + k], J[2 * nv + k]}, vl{J[3 * nv + k], J[4 * nv + k], J[5 * nv + k]};
    const Vec3<double> wL = mul_transpose(R, om), vL = mul_transpose(R, ref == WORLD ? vl - cross(p, om) : vl);
    Vec3<double> top = cross(fa.n, wL);
    if (ref == WORLD) top += cross(fa.f, vL);
    const Vec3<double> bottom = cross(fa.f, wL);
    const double col[12] = {wL.x, wL.y, wL.z, vL.x, vL.y, vL.z, top.x, top.y, top.z, bottom.x, bottom.y, bottom.z};
    for (int r = 0; r < 6; ++r) JL[r * nv + k] = col[r], GJ[r * nv + k] = col[6 + r];
  }
  for (int i = 0; i < nv; ++i)
    for (int r = 0; r < 6; ++r) {
      const double a = JL[r * nv + i];
      if (a == 0.0) continue;
      for (int j = 0; j < nv; ++j) R1[i * nv + j] -= a * GJ[r * nv + j];
    }
}

// C (r, c) = A (r, k) B (k, c), or C −= A B with `sub`; row-major, the innermost loop over C's contiguous row.
inline void matmul(const double* A, const double* B, int r, int k, int c, double* C, bool sub = false) {
  for (int i = 0; i < r; ++i) {
    double* Ci = C + static_cast<size_t>(i) * c;
    if (!sub) std::fill(Ci, Ci + c, 0.0);
    for (int t = 0; t < k; ++t) {
      const double a = sub ? -A[static_cast<size_t>(i) * k + t] : A[static_cast<size_t>(i) * k + t];
      if (a == 0.0) continue;
      const double* Bt = B + static_cast<size_t>(t) * c;
      for (int j = 0; j < c; ++j) Ci[j] += a * Bt[j];
    }
  }
}

// Aᵀ: (r, c) → (c, r).
inline void transpose(const double* A, int r, int c, double* At) {
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) At[static_cast<size_t>(j) * r + i] = A[static_cast<size_t>(i) * c + j];
}

// From M (w.M) and J (w.J, m rows): the KKT system's inverse blocks
//     D⁻¹ (m, m),   G = D⁻¹ J M⁻¹ (m, nv),   K = M⁻¹ − M⁻¹ Jᵀ D⁻¹ J M⁻¹ (nv, nv, symmetric)
// so that ∂q̈ = −K R₁ − Gᵀ R₂ and ∂λ = G R₁ − D⁻¹ R₂ (the file comment's solve). M⁻¹ by M's LᵀL factor (its columns
// solved from the unit vectors), D by its Cholesky factor. Returns OK, SINGULAR for M, CONSTRAINT for D.
inline std::int64_t factor(const ModelView& mv, int m, double singular_tol, ContactDerivWork& w) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), mm = static_cast<size_t>(m);
  w.lambda.resize(n);
  dof_parents(mv, w.lambda.data());
  w.L = w.M;
  const int bad = ltl_factor(mv, w.lambda.data(), w.L.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  w.K.assign(n * n, 0.0);  // M⁻¹ first, row by row (M⁻¹ is symmetric)
  for (int i = 0; i < nv; ++i) {
    double* x = w.K.data() + i * n;
    x[i] = 1.0;
    ltl_solve_Lt(mv, w.lambda.data(), w.L.data(), x);
    ltl_solve_L(mv, w.lambda.data(), w.L.data(), x);
  }
  w.MJ.resize(mm * n);
  matmul(w.J.data(), w.K.data(), m, nv, nv, w.MJ.data());  // J M⁻¹
  w.D.resize(mm * mm), w.Dinv.resize(mm * mm), w.G.resize(mm * n), w.Gt.resize(mm * n);
  w.JtT.resize(n * mm);
  transpose(w.J.data(), m, nv, w.JtT.data());
  matmul(w.MJ.data(), w.JtT.data(), m, nv, m, w.D.data());  // D = J M⁻¹ Jᵀ
  if (dense_cholesky<double>(w.D.data(), m, singular_tol)) return make_status(CONSTRAINT, ARG_OUT, m);
  dense_cholesky_inverse<double>(w.D.data(), m, w.G.data(), w.Dinv.data());  // (G as scratch)
  matmul(w.Dinv.data(), w.MJ.data(), m, m, nv, w.G.data());
  transpose(w.G.data(), m, nv, w.Gt.data());  // Gᵀ = M⁻¹ Jᵀ D⁻¹ (nv, m)
  matmul(w.Gt.data(), w.MJ.data(), nv, m, nv, w.K.data(), true);  // K = M⁻¹ − Gᵀ (J M⁻¹)
  return OK;
}

// ∂q̈ X (nv, nv) and ∂λ Y (m, nv) of one pair (R₁, R₂) with `factor`'s blocks: X = −K R₁ − Gᵀ R₂, Y = G R₁ − D⁻¹ R₂.
// R₁ nullptr: R₁ = s 1 (X = −s K, Y = s G); `r1_is_mass`: R₁ = s M (K M = 1 − Gᵀ J, G M = D⁻¹ J). R₂ may be nullptr.
inline void solve_pair(const ModelView& mv, int m, const double* R1, double s, bool r1_is_mass, const double* R2,
                       ContactDerivWork& w, double* X, double* Y) {
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv), nn = n * n, mn = static_cast<size_t>(m) * n;
  if (R1 != nullptr) {  // by R₁ᵀ on the left: its zeros (dofs on different branches) skipped, then transposed
    w.R1t.resize(nn), w.Xt.resize(nn), w.Yt.resize(mn);
    transpose(R1, nv, nv, w.R1t.data());
    matmul(w.R1t.data(), w.K.data(), nv, nv, nv, w.Xt.data());  // (K R₁)ᵀ = R₁ᵀ K (K symmetric)
    matmul(w.R1t.data(), w.Gt.data(), nv, nv, m, w.Yt.data());  // (G R₁)ᵀ = R₁ᵀ Gᵀ
    for (int i = 0; i < nv; ++i)
      for (int j = 0; j < nv; ++j) X[i * n + j] = -w.Xt[j * n + i];
    transpose(w.Yt.data(), nv, m, Y);
  } else if (r1_is_mass) {  // X = −s (1 − Gᵀ J), Y = s D⁻¹ J
    matmul(w.Gt.data(), w.J.data(), nv, m, nv, X);
    for (size_t k = 0; k < nn; ++k) X[k] *= s;
    for (int i = 0; i < nv; ++i) X[i * n + i] -= s;
    matmul(w.Dinv.data(), w.J.data(), m, m, nv, Y);
    for (size_t k = 0; k < mn; ++k) Y[k] *= s;
  } else {
    for (size_t k = 0; k < nn; ++k) X[k] = -s * w.K[k];
    for (size_t k = 0; k < mn; ++k) Y[k] = s * w.G[k];
  }
  if (R2 != nullptr) {
    matmul(w.Gt.data(), R2, nv, m, nv, X, true);
    matmul(w.Dinv.data(), R2, m, m, nv, Y, true);
  }
}

// The contacts' rows J (m, nv) into w.J and their forces λ: on the bodies (w.f, which holds f_ext or zeros), and
// their turn into R1 (nv, nv). `kin` (6 outputs of kinematics_derivatives per contact) is left in w.kin when
// `qd` is given (at (q, qd, qdd)); with qd nullptr only J is formed (frame_jacobian).
inline void contact_terms(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                          const double* lam, const ContactSpec* specs, int nc, ContactDerivWork& w, double* R1) {
  const int nv = mv.nv;
  const size_t blk = static_cast<size_t>(6) * nv;
  int row = 0;
  for (int k = 0; k < nc; ++k) {
    const ContactSpec& s = specs[k];
    double* kin = w.kin.data() + 6 * blk * static_cast<size_t>(k);
    double* const outs[6] = {kin, kin + blk, kin + 2 * blk, kin + 3 * blk, kin + 4 * blk, kin + 5 * blk};
    if (qd != nullptr) {
      kinematics_derivatives(mv, q, qd, qdd, s.frame, nullptr, s.ref, outs);
    } else {
      frame_jacobian(mv, q, s.frame, s.ref, outs[1]);
    }
    for (int r = 0; r < s.rows; ++r)
      std::copy(outs[1] + (6 - s.rows + r) * nv, outs[1] + (7 - s.rows + r) * nv, w.J.data() + (row + r) * nv);
    if (lam != nullptr) {
      Mat3<double> R;
      Vec3<double> p;
      frame_pose(mv, q, s.frame, R, p);
      const Force<double> fa = frame_force(s, lam + row, R, p);
      add_to_body(mv, s.frame, fa, w.f.data());
      if (R1 != nullptr) add_turn(mv, s.ref, outs[1], R, p, fa, w, R1);
    }
    row += s.rows;
  }
}

// The calling thread's workspace with room for nc contacts' frame derivatives and m rows.
inline ContactDerivWork& workspace(const ModelView& mv, int nc, int m) {
  ContactDerivWork& w = thread_workspace<ContactDerivWork>(mv.nb);
  w.kin.resize(static_cast<size_t>(36) * static_cast<size_t>(mv.nv) * static_cast<size_t>(nc));
  w.J.resize(static_cast<size_t>(m) * static_cast<size_t>(mv.nv));
  return w;
}

}  // namespace contact_deriv

// ∂q̈/∂(q, q̇, τ) (nv, nv) and ∂λ/∂(q, q̇, τ) (m, nv) at the solution (qdd, lam) of the contacts' constrained
// dynamics at (q, q̇, τ, f_ext) (contacts.hpp). Returns OK, SINGULAR, or CONSTRAINT (dependent contacts).
inline std::int64_t contact_dynamics_derivatives(const ModelView& mv, const double* q, const double* qd,
                                                 const double* f_ext, const double* qdd, const double* lam,
                                                 const ContactSpec* specs, int nc, int m, double singular_tol,
                                                 double* const* out) {
  using namespace contact_deriv;
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv);
  ContactDerivWork& w = workspace(mv, nc, m);
  w.f.assign(static_cast<size_t>(6) * mv.nb, 0.0);
  if (f_ext) std::copy(f_ext, f_ext + 6 * mv.nb, w.f.begin());
  w.dq.assign(n * n, 0.0);  // the turn first; RNEA's ∂τ/∂q added below
  contact_terms(mv, q, qd, qdd, lam, specs, nc, w, w.dq.data());
  w.dv.resize(n * n), w.M.resize(n * n);
  {
    thread_local std::vector<double> dq;
    dq.resize(n * n);
    rnea_derivatives(mv, q, qd, qdd, w.f.data(), true, dq.data(), w.dv.data(), w.M.data());
    for (size_t k = 0; k < n * n; ++k) w.dq[k] += dq[k];
  }
  // R₂ = ∂a/∂x + K_d ∂v/∂x, the contacts' rows of the frame derivatives (classical acceleration for a point)
  w.R2q.resize(static_cast<size_t>(m) * n), w.R2v.resize(static_cast<size_t>(m) * n);
  const size_t blk = static_cast<size_t>(6) * nv;
  for (int k = 0, row = 0; k < nc; row += specs[k].rows, ++k) {
    const ContactSpec& s = specs[k];
    const double* kin = w.kin.data() + 6 * blk * static_cast<size_t>(k);
    const double *a_q = kin + (s.rows == 3 ? 4 : 2) * blk, *a_v = kin + (s.rows == 3 ? 5 : 3) * blk;
    for (int r = 0; r < s.rows; ++r) {
      const size_t src = static_cast<size_t>(6 - s.rows + r) * n, dst = static_cast<size_t>(row + r) * n;
      for (int j = 0; j < nv; ++j) {
        w.R2q[dst + j] = a_q[src + j] + s.kd * kin[src + j];
        w.R2v[dst + j] = a_v[src + j] + s.kd * kin[blk + src + j];
      }
    }
  }
  FD_TRY(contact_deriv::factor(mv, m, singular_tol, w));
  solve_pair(mv, m, w.dq.data(), 0.0, false, w.R2q.data(), w, out[0], out[3]);
  solve_pair(mv, m, w.dv.data(), 0.0, false, w.R2v.data(), w, out[1], out[4]);
  solve_pair(mv, m, nullptr, -1.0, false, nullptr, w, out[2], out[5]);
  return OK;
}

// The impulse v⁺ (nv,), Λ (m,) of an impact with the contacts (restitution e) and its derivatives ∂v⁺/∂(q, v⁻)
// (nv, nv), ∂Λ/∂(q, v⁻) (m, nv) into out[0..3], v⁺ and Λ into out[4], out[5]. Returns OK, SINGULAR, or CONSTRAINT.
inline std::int64_t impulse_dynamics_derivatives(const ModelView& mv, const double* q, const double* vm,
                                                 const ContactSpec* specs, int nc, int m, double e,
                                                 double singular_tol, double* const* out) {
  using namespace contact_deriv;
  const int nv = mv.nv;
  const size_t n = static_cast<size_t>(nv);
  ContactDerivWork& w = workspace(mv, nc, m);
  w.M.resize(n * n);
  crba(mv, q, w.M.data());
  contact_terms(mv, q, nullptr, nullptr, nullptr, specs, nc, w, nullptr);
  FD_TRY(contact_deriv::factor(mv, m, singular_tol, w));
  // Λ = −(1 + e) D⁻¹ J v⁻,  v⁺ = v⁻ + M⁻¹ Jᵀ Λ
  double *vp = out[4], *L = out[5];
  for (int r = 0; r < m; ++r) {
    double s = 0.0;
    for (int i = 0; i < nv; ++i) s += w.J[static_cast<size_t>(r) * n + i] * vm[i];
    L[r] = -(1.0 + e) * s;
  }
  dense_cholesky_solve<double>(w.D.data(), m, L);
  for (int i = 0; i < nv; ++i) {
    double s = vm[i];
    for (int r = 0; r < m; ++r) s += w.MJ[static_cast<size_t>(r) * n + i] * L[r];
    vp[i] = s;
  }
  // R₁ along q: RNEA at zero velocity without gravity, a = w, with Λ on the bodies, plus the turn; R₂ = ∂(J u)/∂q
  thread_local std::vector<double> u, acc, zero, dq;
  u.resize(n), acc.resize(n), zero.assign(n, 0.0), dq.resize(n * n);
  for (int i = 0; i < nv; ++i) u[i] = vp[i] + e * vm[i], acc[i] = vp[i] - vm[i];
  w.f.assign(static_cast<size_t>(6) * mv.nb, 0.0);
  w.dq.assign(n * n, 0.0);
  contact_terms(mv, q, u.data(), zero.data(), L, specs, nc, w, w.dq.data());
  rnea_derivatives(mv, q, zero.data(), acc.data(), w.f.data(), false, dq.data(), static_cast<double*>(nullptr),
                   static_cast<double*>(nullptr));
  for (size_t k = 0; k < n * n; ++k) w.dq[k] += dq[k];
  w.R2q.resize(static_cast<size_t>(m) * n), w.R2v.resize(static_cast<size_t>(m) * n);
  const size_t blk = static_cast<size_t>(6) * nv;
  for (int k = 0, row = 0; k < nc; row += specs[k].rows, ++k) {
    const double* kin = w.kin.data() + 6 * blk * static_cast<size_t>(k);
    for (int r = 0; r < specs[k].rows; ++r) {
      const size_t src = static_cast<size_t>(6 - specs[k].rows + r) * n, dst = static_cast<size_t>(row + r) * n;
      for (int j = 0; j < nv; ++j) w.R2q[dst + j] = kin[src + j], w.R2v[dst + j] = e * kin[blk + src + j];
    }
  }
  solve_pair(mv, m, w.dq.data(), 0.0, false, w.R2q.data(), w, out[0], out[2]);
  solve_pair(mv, m, nullptr, -1.0, true, w.R2v.data(), w, out[1], out[3]);
  return OK;
}

}  // namespace fdcore
