// Derivatives of inverse and forward dynamics (reference: featherdyn/algorithms/; Carpentier &
// Mansard, RSS 2018), in body coordinates.
//
// ∂τ/∂q and ∂τ/∂q̇: the tangent-linear RNEA. q's derivative is taken along the tangent of
// fd.integrate, q ⊕ ε e_j, which moves body k (the joint of direction j, column c of S_k) by
// ᵖM_k exp(ε S_c): so δX_up[k] = −S_c × X_up[k] and, for the bodies i of k's subtree,
//
//     δv_k = −S_c × (X_up[k] v_λ(k)),            δa_k = −S_c × (X_up[k] a_λ(k)) + δv_k × S_k q̇_k
//     δv_i = X_up[i] δv_λ(i),                     δa_i = X_up[i] δa_λ(i) + δv_i × S_i q̇_i
//     δf_i = I_i δa_i + δv_i ×* I_i v_i + v_i ×* I_i δv_i
//     δτ_i = S_iᵀ δF_i,   δF_λ(i) += X_up[i]ᵀ δF_i,   at k: δF_λ(k) += X_up[k]ᵀ (δF_k + S_c ×* F_k)
//
// (F: the forces after RNEA's backward pass), then up the ancestors of k; a q̇ direction starts
// from δv_k = S_c, δa_k = S_c × S_k q̇_k + v_k × S_c. Each direction costs its subtree and its
// support, as the analytical algorithm does.
//
// Forward dynamics: q̈ = ABA(q, q̇, τ) solves RNEA(q, q̇, q̈) = τ, so
//
//     ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (at q̈ = ABA(q, q̇, τ)),   ∂q̈/∂τ = M⁻¹
//
// with M⁻¹'s columns from the ABA template on unit joint forces (no velocity, no gravity): M⁻¹ e_j,
// several columns per pass through the SIMD Pack instantiation. Frame velocities and accelerations
// (frame_derivatives.hpp) are differentiated by running their template on Dual numbers: a value and
// K directional derivatives, whose tangent seeds are the derivatives of q ⊕ ε e_j at ε = 0:
//
//     revolute, prismatic:  δq = e_j
//     spherical (ω in the child frame):           δquat = quat ⊗ (e_c / 2, 0)
//     free-flyer ([ω; v] in the base frame):      δquat = quat ⊗ (e_c / 2, 0)  or  δp = R(quat) e_c
//     planar ([ω, v_x, v_y] in the moving frame): δθ = 1  or  δ(x, y) = R(θ) e_c
#pragma once

#include <algorithm>
#include <vector>

#include "aba.hpp"
#include "crba.hpp"
#include "ltl.hpp"
#include "pack.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// A value and K directional derivatives (dual numbers: ε_k ε_l = 0).
template <int K>
struct Dual {
  double v = 0.0;
  double d[K] = {};
  Dual() = default;
  Dual(double x) : v(x) {}  // NOLINT(google-explicit-constructor): constants convert, as for double
};

template <int K>
inline Dual<K> operator+(const Dual<K>& a, const Dual<K>& b) {
  Dual<K> r(a.v + b.v);
  for (int k = 0; k < K; ++k) r.d[k] = a.d[k] + b.d[k];
  return r;
}
template <int K>
inline Dual<K> operator-(const Dual<K>& a, const Dual<K>& b) {
  Dual<K> r(a.v - b.v);
  for (int k = 0; k < K; ++k) r.d[k] = a.d[k] - b.d[k];
  return r;
}
template <int K>
inline Dual<K> operator-(const Dual<K>& a) {
  Dual<K> r(-a.v);
  for (int k = 0; k < K; ++k) r.d[k] = -a.d[k];
  return r;
}
template <int K>
inline Dual<K> operator*(const Dual<K>& a, const Dual<K>& b) {
  Dual<K> r(a.v * b.v);
  for (int k = 0; k < K; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}
template <int K>
inline Dual<K> operator/(const Dual<K>& a, const Dual<K>& b) {
  const double inv = 1.0 / b.v;
  Dual<K> r(a.v * inv);
  for (int k = 0; k < K; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * inv;
  return r;
}
template <int K>
inline Dual<K>& operator+=(Dual<K>& a, const Dual<K>& b) { return a = a + b; }
template <int K>
inline Dual<K>& operator-=(Dual<K>& a, const Dual<K>& b) { return a = a - b; }
template <int K>
inline Dual<K>& operator*=(Dual<K>& a, const Dual<K>& b) { return a = a * b; }

// d sin θ = cos θ dθ,   d cos θ = −sin θ dθ
template <int K>
inline void sin_cos(const Dual<K>& x, Dual<K>& s, Dual<K>& c) {
  double sv, cv;
  sin_cos(x.v, sv, cv);
  s = Dual<K>(sv);
  c = Dual<K>(cv);
  for (int k = 0; k < K; ++k) s.d[k] = cv * x.d[k], c.d[k] = -sv * x.d[k];
}

// Lanes per pass of the derivative kernels.
constexpr int DERIV_LANES = 8;
using DualK = Dual<DERIV_LANES>;

// Seed lane `lane` of Q with the tangent direction j of fd.integrate at q (see the file comment).
inline void seed_tangent(const ModelView& mv, const double* q, int j, int lane, DualK* Q) {
  int i = 0;
  while (!(mv.idx_v[i] <= j && j < mv.idx_v[i] + mv.nv_i[i])) ++i;
  const int c = j - mv.idx_v[i], iq = mv.idx_q[i];
  // quat ⊗ (a, 0) with a = e_k / 2 for the quaternion (x, y, z, w) at q[at]: (w a + u × a, −u·a)
  auto rotate_seed = [&](int at, int k) {
    const double u[3] = {q[at], q[at + 1], q[at + 2]}, w = q[at + 3];
    double a[3] = {0.0, 0.0, 0.0};
    a[k] = 0.5;
    Q[at + 0].d[lane] = w * a[0] + (u[1] * a[2] - u[2] * a[1]);
    Q[at + 1].d[lane] = w * a[1] + (u[2] * a[0] - u[0] * a[2]);
    Q[at + 2].d[lane] = w * a[2] + (u[0] * a[1] - u[1] * a[0]);
    Q[at + 3].d[lane] = -(u[0] * a[0] + u[1] * a[1] + u[2] * a[2]);
  };
  switch (mv.jtype[i]) {
    case REVOLUTE:
    case PRISMATIC:
      Q[iq].d[lane] = 1.0;
      return;
    case SPHERICAL:
      rotate_seed(iq, c);
      return;
    case FREE_FLYER:
      if (c < 3) {
        rotate_seed(iq + 3, c);
      } else {
        const Mat3<double> R = quat_to_matrix(q + iq + 3);
        for (int r = 0; r < 3; ++r) Q[iq + r].d[lane] = R(r, c - 3);
      }
      return;
    default: {  // PLANAR: q = [x, y, θ], v = [ω, v_x, v_y]
      if (c == 0) {
        Q[iq + 2].d[lane] = 1.0;
      } else {
        double s, co;
        sin_cos(q[iq + 2], s, co);
        Q[iq + 0].d[lane] = c == 1 ? co : -s;
        Q[iq + 1].d[lane] = c == 1 ? s : co;
      }
    }
  }
}

template <class S>
struct DerivWork {
  std::vector<S> Q, V, A, F, T;
  void resize(size_t) {}
};

template <class S>
struct RneaDerivWork {
  std::vector<Xform<S>> X_up;
  std::vector<RigidInertia<S>> I;
  std::vector<Motion<S>> v, a, vJ, dv, da;
  std::vector<Force<S>> F, dF;
  std::vector<char> in_subtree;
  void resize(size_t nb) {
    if (X_up.size() < nb)
      X_up.resize(nb), I.resize(nb), v.resize(nb), a.resize(nb), vJ.resize(nb), dv.resize(nb), da.resize(nb),
          F.resize(nb), dF.resize(nb), in_subtree.resize(nb);
  }
};

// A root joint's direction S_c whose seeds δv_k = 0 (no parent velocity) and δa_k = −S_c × (X_up a₀) vanish:
// its column of ∂τ/∂q is zero (a root has no parent to receive S_c ×* F). Only exact zeros count.
inline bool moves_nothing(const Motion<double>& Sc, const Motion<double>& xa) {
  const Motion<double> u = cross_motion(Sc, xa);
  return u.w.x == 0.0 && u.w.y == 0.0 && u.w.z == 0.0 && u.v.x == 0.0 && u.v.y == 0.0 && u.v.z == 0.0;
}
template <class S>
inline bool moves_nothing(const Motion<S>&, const Motion<S>&) {
  return false;
}

// ∂τ/∂q and ∂τ/∂q̇ (nv, nv) row-major (column j: the derivative along direction j), by the tangent-linear
// RNEA of the file comment.
template <class S>
void rnea_derivatives(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* f_ext, bool gravity,
                      S* dtau_dq, S* dtau_dv) {
  const int nb = mv.nb, nv = mv.nv;
  RneaDerivWork<S>& w = thread_workspace<RneaDerivWork<S>>(nb);
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  const Motion<S> a0 = base_acceleration<S>(mv, gravity);
  // the nominal RNEA, keeping X_up, v, a, S q̇ and the accumulated forces F
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i];
    w.X_up[i] = joint_X_up(mv, i, q);
    w.I[i] = body_inertia<S>(mv, i);
    w.vJ[i] = S_times(mv, i, qd);
    w.v[i] = lam == -1 ? w.vJ[i] : w.X_up[i].apply(w.v[lam]) + w.vJ[i];
    w.a[i] = w.X_up[i].apply(lam == -1 ? a0 : w.a[lam]) + S_times(mv, i, qdd) + cross_motion(w.v[i], w.vJ[i]);
    w.F[i] = w.I[i] * w.a[i] + cross_force(w.v[i], w.I[i] * w.v[i]);
    if (f_ext) {
      const S* fx = f_ext + 6 * i;
      w.F[i] = w.F[i] - Force<S>{{fx[0], fx[1], fx[2]}, {fx[3], fx[4], fx[5]}};
    }
  }
  for (int i = nb - 1; i >= 0; --i)
    if (mv.parent[i] != -1) w.F[mv.parent[i]] += w.X_up[i].apply_transpose(w.F[i]);
  for (int k = 0; k < nv * nv; ++k) dtau_dq[k] = dtau_dv[k] = z;

  S col[6];
  for (int k = 0; k < nb; ++k) {
    const int lam_k = mv.parent[k];
    char* sub = w.in_subtree.data();
    sub[k] = 1;
    for (int i = k + 1; i < nb; ++i) sub[i] = mv.parent[i] >= k && sub[mv.parent[i]];
    const Motion<S> xv = lam_k == -1 ? zero : w.X_up[k].apply(w.v[lam_k]);
    const Motion<S> xa = w.X_up[k].apply(lam_k == -1 ? a0 : w.a[lam_k]);
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const Motion<S> Sc = S_col<S>(mv, k, c);
      const int j = mv.idx_v[k] + c;
      for (int wrt_v = 0; wrt_v < 2; ++wrt_v) {
        S* out = wrt_v ? dtau_dv : dtau_dq;
        if (!wrt_v && lam_k == -1 && moves_nothing(Sc, xa)) continue;  // e.g. a root free-flyer's translations
        // forward over the subtree of k
        for (int i = k; i < nb; ++i) {
          if (!sub[i]) continue;
          if (i == k) {
            if (wrt_v) {
              w.dv[k] = Sc;
              w.da[k] = cross_motion(Sc, w.vJ[k]) + cross_motion(w.v[k], Sc);
            } else {
              const Motion<S> u = cross_motion(Sc, xv);
              w.dv[k] = Motion<S>{-u.w, -u.v};
              const Motion<S> ua = cross_motion(Sc, xa);
              w.da[k] = Motion<S>{-ua.w, -ua.v} + cross_motion(w.dv[k], w.vJ[k]);
            }
          } else {
            const int lam = mv.parent[i];
            w.dv[i] = w.X_up[i].apply(w.dv[lam]);
            w.da[i] = w.X_up[i].apply(w.da[lam]) + cross_motion(w.dv[i], w.vJ[i]);
          }
          const RigidInertia<S>& I = w.I[i];
          w.dF[i] = I * w.da[i] + cross_force(w.dv[i], I * w.v[i]) + cross_force(w.v[i], I * w.dv[i]);
        }
        // backward over the subtree, then up the ancestors of k
        for (int i = nb - 1; i > k; --i) {
          if (!sub[i]) continue;
          St_times(mv, i, w.dF[i], col);
          for (int r = 0; r < mv.nv_i[i]; ++r) out[(mv.idx_v[i] + r) * nv + j] = col[r];
          w.dF[mv.parent[i]] += w.X_up[i].apply_transpose(w.dF[i]);
        }
        St_times(mv, k, w.dF[k], col);
        for (int r = 0; r < mv.nv_i[k]; ++r) out[(mv.idx_v[k] + r) * nv + j] = col[r];
        if (lam_k == -1) continue;
        Force<S> G = w.X_up[k].apply_transpose(wrt_v ? w.dF[k] : w.dF[k] + cross_force(Sc, w.F[k]));
        for (int i = lam_k; i != -1; i = mv.parent[i]) {
          St_times(mv, i, G, col);
          for (int r = 0; r < mv.nv_i[i]; ++r) out[(mv.idx_v[i] + r) * nv + j] = col[r];
          if (mv.parent[i] != -1) G = w.X_up[i].apply_transpose(G);
        }
      }
    }
  }
}

// ∂τ/∂q and ∂τ/∂q̇ (nv, nv) row-major by forward-mode differentiation of the RNEA template on Dual
// numbers: an independent check of the tangent-linear algorithm (tests), eight directions a pass.
inline void rnea_derivatives_dual(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                             const double* f_ext, bool gravity, double* dtau_dq, double* dtau_dv) {
  const int nq = mv.nq, nv = mv.nv, nf = 6 * mv.nb;
  DerivWork<DualK>& w = thread_workspace<DerivWork<DualK>>(mv.nb);
  w.Q.resize(nq), w.V.resize(nv), w.A.resize(nv), w.T.resize(nv);
  w.F.resize(f_ext ? nf : 0);
  for (int k = 0; k < nv; ++k) w.A[k] = DualK(qdd[k]);
  for (int k = 0; f_ext && k < nf; ++k) w.F[k] = DualK(f_ext[k]);
  for (int start = 0; start < 2 * nv; start += DERIV_LANES) {
    for (int k = 0; k < nq; ++k) w.Q[k] = DualK(q[k]);
    for (int k = 0; k < nv; ++k) w.V[k] = DualK(qd[k]);
    const int lanes = std::min(DERIV_LANES, 2 * nv - start);
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l;
      if (dir < nv) seed_tangent(mv, q, dir, l, w.Q.data());
      else w.V[dir - nv].d[l] = 1.0;
    }
    rnea(mv, w.Q.data(), w.V.data(), w.A.data(), f_ext ? w.F.data() : nullptr, gravity, w.T.data());
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l;
      double* out = dir < nv ? dtau_dq + dir : dtau_dv + (dir - nv);
      for (int r = 0; r < nv; ++r) out[r * nv] = w.T[r].d[l];
    }
  }
}

// M⁻¹ (nv, nv) row-major: ABA on unit joint forces e_j, no velocity, no gravity, PACK_WIDTH columns a
// pass. Returns −1, or the joint whose articulated inertia is singular.
inline int mass_matrix_inverse(const ModelView& mv, const double* q, double* Minv) {
  const int nq = mv.nq, nv = mv.nv;
  DerivWork<Pack>& w = thread_workspace<DerivWork<Pack>>(mv.nb);
  w.Q.resize(nq), w.V.resize(nv), w.A.resize(nv), w.T.resize(nv);
  for (int k = 0; k < nq; ++k) w.Q[k] = Pack(q[k]);
  for (int k = 0; k < nv; ++k) w.V[k] = Pack(0.0);
  for (int start = 0; start < nv; start += PACK_WIDTH) {
    for (int k = 0; k < nv; ++k) w.A[k] = Pack(0.0);
    const int lanes = std::min(PACK_WIDTH, nv - start);
    for (int l = 0; l < lanes; ++l) w.A[start + l].set(l, 1.0);
    const int bad = aba(mv, w.Q.data(), w.V.data(), w.A.data(), static_cast<const Pack*>(nullptr), false, w.T.data());
    if (bad >= 0) return bad;
    for (int l = 0; l < lanes; ++l)
      for (int r = 0; r < nv; ++r) Minv[r * nv + start + l] = w.T[r][l];
  }
  // M⁻¹ is symmetric: the mean of the two triangles removes the round-off asymmetry
  for (int r = 0; r < nv; ++r)
    for (int c = r + 1; c < nv; ++c) Minv[r * nv + c] = Minv[c * nv + r] = 0.5 * (Minv[r * nv + c] + Minv[c * nv + r]);
  return -1;
}

// q̈ = ABA(q, q̇, τ) and ∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹ (nv, nv) each; `scratch` holds 3 nv² + nv doubles;
// rnea_derivs: the tangent-linear RNEA as compiled for the CPU's instruction set. The products with M⁻¹ are
// solves with M's tree-sparse factor (ltl.hpp: M = LᵀL, each column O(nv · depth)), never a dense M⁻¹ product.
// Returns −1, or the joint whose articulated inertia is singular.
template <class RneaDerivs>
int aba_derivatives(const ModelView& mv, const int* lambda_d, const double* q, const double* qd, const double* tau,
                    const double* f_ext, bool gravity, double* qdd, double* dq, double* dv, double* Minv,
                    double* scratch, RneaDerivs rnea_derivs) {
  const int nv = mv.nv;
  const size_t n2 = static_cast<size_t>(nv) * nv;
  const int bad = aba(mv, q, qd, tau, f_ext, gravity, qdd);
  if (bad >= 0) return bad;
  double* L = scratch;
  double* tq = scratch + n2;
  double* tv = scratch + 2 * n2;
  double* col = scratch + 3 * n2;
  crba(mv, q, L);
  const int bad_dof = ltl_factor(mv, lambda_d, L);
  if (bad_dof >= 0) return dof_body(mv, bad_dof);
  rnea_derivs(mv, q, qd, qdd, f_ext, gravity, tq, tv);
  // −M⁻¹ ∂τ/∂q, −M⁻¹ ∂τ/∂q̇, M⁻¹ 1: the two sweeps on all columns of each at once (ltl.hpp)
  const size_t nn = static_cast<size_t>(nv) * nv;
  for (size_t k = 0; k < nn; ++k) dq[k] = -tq[k], dv[k] = -tv[k], Minv[k] = 0.0;
  for (int k = 0; k < nv; ++k) Minv[static_cast<size_t>(k) * nv + k] = 1.0;
  for (double* X : {dq, dv, Minv}) {
    ltl_solve_Lt_rows(mv, lambda_d, L, X, nv);
    ltl_solve_L_rows(mv, lambda_d, L, X, nv);
  }
  (void)col;
  return -1;
}

}  // namespace fdcore
