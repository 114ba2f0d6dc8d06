// Point and frame contacts in one call: their rows, their drift and the constrained dynamics
// (reference: featherdyn/api/constraints.py, _one for PointContact / FrameContact, and
// featherdyn/algorithms/constrained.py for the solve).
//
//     point contact (3 rows):  J = the linear rows of the frame Jacobian in `ref`,
//                              γ = the classical acceleration of the frame's origin at q̈ = 0, in `ref`
//     frame contact (6 rows):  J = the frame Jacobian in `ref`, γ = the frame's spatial acceleration at q̈ = 0
//     c = −γ − K_d J q̇        (a contact's error e is zero: K_p has nothing to act on)
//
// then M q̈ + h = τ + Jᵀ λ, J q̈ = c on M's LᵀL factor (ltl.hpp). The frame's motion at q̈ = 0 comes from
// one forward pass over the bodies (v_i, a_i in body coordinates, RBDA §5.3 with q̈ = 0):
//
//     ᶠv = ᶠX_b v_b,  ᶠa = ᶠX_b a_b                          (LOCAL)
//     classical: a_lin + ω × v_lin (in the same axes)       LWA: rotate LOCAL by ⁰R_f
//     WORLD: ⁰X_f ᶠa, and for the classical acceleration the body point at the world origin
#pragma once

#include <vector>

#include "crba.hpp"
#include "frames.hpp"
#include "ltl.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// One contact: rows 3 (point) or 6 (frame), the frame index, the reference code, the damping gain K_d.
struct ContactSpec {
  int rows, frame, ref;
  double kd;
};

struct ContactWork {
  std::vector<Mat3<double>> oR;
  std::vector<Vec3<double>> op;
  std::vector<Motion<double>> v, a;
  std::vector<double> J6, J, c, L, th;
  std::vector<int> lambda;
  void resize(size_t nb) {
    if (oR.size() < nb) oR.resize(nb), op.resize(nb), v.resize(nb), a.resize(nb);
  }
};

// The motion of frame `frame` at q̈ = 0 in `ref`: spatial (rows == 6) or classical (rows == 3) acceleration.
inline Motion<double> contact_drift(const ModelView& mv, const ContactWork& w, int frame, int ref, int rows) {
  const int b = mv.frame_body[frame];
  const Mat3<double> Rbf = load9<double>(mv.frame_R + 9 * frame);
  const Vec3<double> pbf = load3<double>(mv.frame_p + 3 * frame);
  const Xform<double> f_X_b{Rbf.transpose(), pbf};
  const Motion<double> vf = f_X_b.apply(w.v[b]), af = f_X_b.apply(w.a[b]);
  const Mat3<double> Rf = w.oR[b] * Rbf;                  // ⁰R_f
  const Vec3<double> pf = w.op[b] + w.oR[b] * pbf;         // ⁰p_f
  if (ref == WORLD) {
    const Xform<double> f_X_0{Rf.transpose(), pf};          // ⁰X_f = f_X_0⁻¹
    const Motion<double> a0 = f_X_0.apply_inverse(af);
    if (rows == 6) return a0;
    const Motion<double> v0 = f_X_0.apply_inverse(vf);
    return {a0.w, a0.v + cross(v0.w, v0.v)};
  }
  Motion<double> out = af;
  if (rows == 3) out.v = af.v + cross(vf.w, vf.v);
  if (ref == LOCAL_WORLD_ALIGNED) out = {Rf * out.w, Rf * out.v};
  return out;
}

// The forward pass at q̈ = 0 (RBDA §5.3): world placements ⁰R_i, ⁰p_i; with qd, body velocities v_i and
// bias accelerations a_i = X_up a_λ + v_i × S_i q̇_i in body coordinates.
inline void contact_pass(const ModelView& mv, const double* q, const double* qd, ContactWork& w) {
  for (int i = 0; i < mv.nb; ++i) {
    const int lam_i = mv.parent[i];
    Mat3<double> R;
    Vec3<double> p;
    place_body(mv, i, q, w.oR.data(), w.op.data(), R, p);
    if (qd == nullptr) continue;
    const Xform<double> X_up{R.transpose(), p};
    const Motion<double> vJ = S_times(mv, i, qd);
    w.v[i] = lam_i == -1 ? vJ : X_up.apply(w.v[lam_i]) + vJ;
    const Motion<double> aJ = cross_motion(w.v[i], vJ);
    w.a[i] = lam_i == -1 ? aJ : X_up.apply(w.a[lam_i]) + aJ;
  }
}

// The frame Jacobian J (6, nv) in `ref` from the forward pass's world placements (frames.hpp's
// frame_jacobian without walking the support again): ⁰J[:, k] = ⁰X_k S_k about the world origin (WORLD)
// or the frame's origin, in world axes, then frame axes for LOCAL.
inline void contact_jacobian(const ModelView& mv, const ContactWork& w, int frame, int ref, double* J) {
  const int nv = mv.nv;
  for (int k = 0; k < 6 * nv; ++k) J[k] = 0.0;
  const int b = mv.frame_body[frame];
  const Mat3<double> Rf = w.oR[b] * load9<double>(mv.frame_R + 9 * frame);
  const Vec3<double> pf = w.op[b] + w.oR[b] * load3<double>(mv.frame_p + 3 * frame);
  const Vec3<double> origin = ref == WORLD ? Vec3<double>{0.0, 0.0, 0.0} : pf;
  for (int i = b; i != -1; i = mv.parent[i]) put_frame_columns(mv, i, w.oR[i], w.op[i], origin, Rf, ref, J);
}

// q̈ (nv,), λ (m,), and the KKT result for the contacts `specs` at (q, q̇, τ, f_ext); m = Σ rows.
// Returns OK, or a SINGULAR status naming the body whose pivot of M failed.
inline std::int64_t contact_dynamics(const ModelView& mv, const double* q, const double* qd, const double* tau,
                                     const double* f_ext, const ContactSpec* specs, int nc, double mu, int max_iter,
                                     double tol, double singular_tol, double* qdd, double* lam, KktResult& res) {
  const int nb = mv.nb, nv = mv.nv;
  ContactWork& w = thread_workspace<ContactWork>(nb);
  int m = 0;
  for (int k = 0; k < nc; ++k) m += specs[k].rows;
  w.J6.resize(6 * static_cast<size_t>(nv));
  w.J.resize(static_cast<size_t>(m) * nv);
  w.c.resize(m);
  w.L.resize(static_cast<size_t>(nv) * nv);
  w.th.resize(nv);
  w.lambda.resize(nv);
  // 1. the forward pass at q̈ = 0: world placements, body velocities and bias accelerations
  contact_pass(mv, q, qd, w);
  // 2. the rows: J (m, nv) and c = −γ − K_d J q̇
  int row = 0;
  for (int k = 0; k < nc; ++k) {
    const ContactSpec& s = specs[k];
    contact_jacobian(mv, w, s.frame, s.ref, w.J6.data());
    const Motion<double> g = contact_drift(mv, w, s.frame, s.ref, s.rows);
    const double gam[6] = {g.w.x, g.w.y, g.w.z, g.v.x, g.v.y, g.v.z};
    const int first = 6 - s.rows;
    for (int r = 0; r < s.rows; ++r, ++row) {
      const double* src = w.J6.data() + static_cast<size_t>(first + r) * nv;
      double* dst = w.J.data() + static_cast<size_t>(row) * nv;
      double jv = 0.0;
      for (int j = 0; j < nv; ++j) {
        dst[j] = src[j];
        jv += src[j] * qd[j];
      }
      w.c[row] = -gam[first + r] - s.kd * jv;
    }
  }
  // 3. M = Lᵀ L, τ − h, and the Schur complement
  crba(mv, q, w.L.data());
  dof_parents(mv, w.lambda.data());
  const int bad = ltl_factor(mv, w.lambda.data(), w.L.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  rnea(mv, q, qd, static_cast<const double*>(nullptr), f_ext, true, w.th.data());
  for (int j = 0; j < nv; ++j) w.th[j] = tau[j] - w.th[j];
  res = kkt_solve(mv, w.lambda.data(), w.L.data(), w.th.data(), w.J.data(), w.c.data(), m, mu, max_iter, tol,
                  singular_tol, qdd, lam);
  return OK;
}

// Λ = (J M⁻¹ Jᵀ + μ 1)⁻¹ (m, m) for the frames of `specs` (6 rows each, the stacked frame Jacobians J):
// J M⁻¹ Jᵀ on M's factor (ltl.hpp), then the inverse through its Cholesky factor (M is never inverted).
// Returns OK, SINGULAR for M, or LENGTH (ARG_OUT) when J M⁻¹ Jᵀ + μ 1 has a pivot below singular_tol (the
// caller's general path then decides).
inline std::int64_t operational_space_inertia(const ModelView& mv, const double* q, const ContactSpec* specs, int nc,
                                              double mu, double singular_tol, double* Lambda) {
  const int nb = mv.nb, nv = mv.nv, m = 6 * nc;
  ContactWork& w = thread_workspace<ContactWork>(nb);
  w.J.resize(static_cast<size_t>(m) * nv);
  w.L.resize(static_cast<size_t>(nv) * nv);
  w.lambda.resize(nv);
  w.c.resize(static_cast<size_t>(m) * m);
  contact_pass(mv, q, nullptr, w);
  for (int k = 0; k < nc; ++k) contact_jacobian(mv, w, specs[k].frame, specs[k].ref, w.J.data() + 6 * k * nv);
  crba(mv, q, w.L.data());
  dof_parents(mv, w.lambda.data());
  const int bad = ltl_factor(mv, w.lambda.data(), w.L.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
  double* D = w.c.data();
  delassus_from_factor(mv, w.lambda.data(), w.L.data(), w.J.data(), m, D, w.th);
  for (int i = 0; i < m; ++i) D[i * m + i] += mu;
  if (!dense_cholesky(D, m, singular_tol)) return make_status(LENGTH, ARG_OUT, m);
  for (int j = 0; j < m; ++j) {
    double* col = Lambda + static_cast<size_t>(j) * m;  // column j of Λ (Λ is symmetric: written as row j)
    for (int i = 0; i < m; ++i) col[i] = i == j ? 1.0 : 0.0;
    dense_cholesky_solve(D, m, col);
  }
  for (int i = 0; i < m; ++i)  // symmetric to the last bit
    for (int j = 0; j < i; ++j) Lambda[i * m + j] = Lambda[j * m + i] = 0.5 * (Lambda[i * m + j] + Lambda[j * m + i]);
  return OK;
}

}  // namespace fdcore
