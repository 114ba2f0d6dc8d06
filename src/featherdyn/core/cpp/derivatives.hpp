// Derivatives of inverse and forward dynamics (reference: featherdyn/algorithms/, Carpentier &
// Mansard, RSS 2018) by forward-mode differentiation of the RNEA template: the kernel written once
// (rnea.hpp) runs on Dual<K>, a value with K directional derivatives, so K columns of
//
//     ∂τ/∂q  (along the tangent of fd.integrate: q ⊕ ε e_j, v's layout)   and   ∂τ/∂q̇
//
// come out of one pass, exact to round-off (no step size). The tangent seeds are the derivatives of
// q ⊕ ε e_j at ε = 0, joint by joint:
//
//     revolute, prismatic:  δq = e_j
//     spherical (ω in the child frame):           δquat = quat ⊗ (e_c / 2, 0)
//     free-flyer ([ω; v] in the base frame):      δquat = quat ⊗ (e_c / 2, 0)  or  δp = R(quat) e_c
//     planar ([ω, v_x, v_y] in the moving frame): δθ = 1  or  δ(x, y) = R(θ) e_c
//
// and ∂τ/∂q̈ = M (CRBA). Forward dynamics: q̈ = ABA(q, q̇, τ) solves RNEA(q, q̇, q̈) = τ, so
//
//     ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (at q̈ = ABA(q, q̇, τ)),   ∂q̈/∂τ = M⁻¹
//
// with M⁻¹'s columns from the ABA template on unit joint forces (no velocity, no gravity): M⁻¹ e_j,
// several columns per pass through the SIMD Pack instantiation.
#pragma once

#include <algorithm>
#include <vector>

#include "aba.hpp"
#include "crba.hpp"
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

// ∂τ/∂q and ∂τ/∂q̇ (nv, nv) row-major: column j is the derivative along direction j.
inline void rnea_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
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

// q̈ = ABA(q, q̇, τ) and ∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹ (nv, nv) each; `scratch` holds 2 nv² doubles;
// rnea_derivs and minverse: the two kernels above as compiled for the CPU's instruction set.
// Returns −1, or the joint whose articulated inertia is singular.
template <class RneaDerivs, class Minverse>
int aba_derivatives(const ModelView& mv, const double* q, const double* qd, const double* tau, const double* f_ext,
                    bool gravity, double* qdd, double* dq, double* dv, double* Minv, double* scratch,
                    RneaDerivs rnea_derivs, Minverse minverse) {
  const int nv = mv.nv;
  const int bad = aba(mv, q, qd, tau, f_ext, gravity, qdd);
  if (bad >= 0) return bad;
  const int bad_inv = minverse(mv, q, Minv);
  if (bad_inv >= 0) return bad_inv;
  double* tq = scratch;
  double* tv = scratch + static_cast<size_t>(nv) * nv;
  rnea_derivs(mv, q, qd, qdd, f_ext, gravity, tq, tv);
  for (int r = 0; r < nv; ++r) {
    for (int c = 0; c < nv; ++c) {
      double sq = 0.0, sv = 0.0;
      for (int k = 0; k < nv; ++k) {
        sq += Minv[r * nv + k] * tq[k * nv + c];
        sv += Minv[r * nv + k] * tv[k * nv + c];
      }
      dq[r * nv + c] = -sq;
      dv[r * nv + c] = -sv;
    }
  }
  return -1;
}

}  // namespace fdcore
