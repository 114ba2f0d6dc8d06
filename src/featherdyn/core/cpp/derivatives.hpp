// Derivatives of inverse and forward dynamics (reference: featherdyn/algorithms/; Carpentier &
// Mansard, RSS 2018).
//
// ∂τ/∂q, ∂τ/∂q̇ (and ∂τ/∂q̈ = M): the analytical algorithm of Carpentier & Mansard, with every quantity of
// a tree in its root body's coordinates (r, as crba.hpp: exact however far the robot is from the origin).
// q's derivative is taken along the tangent of fd.integrate, q ⊕ ε e_j: the column S_j of joint k (ʳS_j in
// r) moves the whole subtree of k rigidly by exp(ε ʳS_j). Seen from the moving subtree, only its parent's
// motion changes, by
//
//     ∂V/∂q_j = v_λ(k) × S_j,     ∂A/∂q_j = a_λ(k) × S_j + v_λ(k) × ∂V/∂q_j,     ∂A/∂q̇_j = ∂V/∂q_j + v_k × S_j
//
// (v, a in r; a with the base acceleration −g), and every body l of the subtree answers with
// I_l ∂A + D_l ∂V, where D_l u = İ_l u + u ×* h_l (İ_l = v_l ×* I_l − I_l v_l×, the inertia's rate;
// h_l = I_l v_l its momentum). With the composites I^C_i = Σ I_l, D^C_i = Σ D_l, F^C_i = Σ f_l over the
// subtree of i, for a row of joint i and a column j of joint k:
//
//     k ∈ support(i):  ∂τ_i/∂q_j = S_iᵀ (I^C_i ∂A/∂q_j + D^C_i ∂V/∂q_j),   ∂τ_i/∂q̇_j = S_iᵀ (I^C_i ∂A/∂q̇_j + D^C_i S_j)
//     i ancestor of k: ∂τ_i/∂q_j = S_iᵀ (S_j ×* F^C_k + I^C_k ∂A/∂q_j + D^C_k ∂V/∂q_j),
//                      ∂τ_i/∂q̇_j = S_iᵀ (I^C_k ∂A/∂q̇_j + D^C_k S_j)
//
// (the rigid rotation of S_i and F^C_i cancels when i moves with k: power is frame-invariant), and
// M_ij = S_iᵀ I^C_i S_j as in CRBA. Each pair (i, j on a path to the root) costs a few 6-vector dot
// products: O(nv · depth) in all.
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
  std::vector<Mat3<S>> R;                  // ʳR_i: body i's axes in its tree's root body
  std::vector<Vec3<S>> p;                  // ʳp_i: body i's origin in the root body
  std::vector<Motion<S>> v, a;             // ʳv_i, ʳa_i (a with the base acceleration −g)
  std::vector<RigidInertia<S>> Yc, Bc;     // composite inertia Σ ʳI_l and its rate Σ ʳİ_l (mass 0)
  std::vector<Force<S>> hc, Fc;            // composite momentum Σ ʳI_l ʳv_l and force Σ ʳf_l
  std::vector<Motion<S>> J, dV, dA, dAv;   // per column: ʳS, ∂V/∂q, ∂A/∂q, ∂A/∂q̇
  void resize(size_t nb) {
    if (R.size() < nb)
      R.resize(nb), p.resize(nb), v.resize(nb), a.resize(nb), Yc.resize(nb), Bc.resize(nb), hc.resize(nb),
          Fc.resize(nb), J.resize(6 * nb), dV.resize(6 * nb), dA.resize(6 * nb), dAv.resize(6 * nb);
  }
};

// The rate İ = v ×* I − I v× of a rigid inertia (m, h, Ī) moving with the twist v = [ω; u], in the same
// (m, h, Ī) form (a rigid body keeps its mass):  ṁ = 0,  ḣ = m u + ω × h,
//     Ī' = [ω]× Ī − Ī [ω]× + 2 (h·u) 1 − (u hᵀ + h uᵀ)      (symmetric: d/dt Σ m (|x|² 1 − x xᵀ), ẋ = u + ω × x)
template <class S>
inline RigidInertia<S> inertia_rate(const RigidInertia<S>& I, const Motion<S>& v) {
  const Vec3<S>& w = v.w;
  const Vec3<S>& u = v.v;
  const Sym3<S>& Y = I.I;
  // A = [ω]× Ī column by column; [ω]× Ī − Ī [ω]× = A + Aᵀ
  const Vec3<S> c0 = cross(w, Vec3<S>{Y.xx, Y.xy, Y.xz}), c1 = cross(w, Vec3<S>{Y.xy, Y.yy, Y.yz}),
                c2 = cross(w, Vec3<S>{Y.xz, Y.yz, Y.zz});
  const Vec3<S>& h = I.h;
  const S two(2.0);
  const S d = two * dot(h, u);
  return {S(0.0), I.m * u + cross(w, h),
          {two * c0.x + d - two * u.x * h.x, c1.x + c0.y - (u.x * h.y + h.x * u.y),
           c2.x + c0.z - (u.x * h.z + h.x * u.z), two * c1.y + d - two * u.y * h.y,
           c2.y + c1.z - (u.y * h.z + h.y * u.z), two * c2.z + d - two * u.z * h.z}};
}

// Where the derivative kernel writes ∂τ/∂q, ∂τ/∂q̇ and M (each (nv, nv) row-major; M optional): the
// arrays of one state, or, for a Pack, each lane straight into its own row of the batch's outputs (no
// packed copy of three nv² blocks to scatter afterwards).
template <class S>
struct StateOut {
  S* m[3];
  void zero(int n2) const {
    for (int k = 0; k < 3; ++k)
      if (m[k]) std::fill(m[k], m[k] + n2, S(0.0));
  }
  bool has_M() const { return m[2] != nullptr; }
  void put(int k, size_t at, const S& x) const { m[k][at] = x; }
};
struct LanesOut {
  double* m[3];          // lane 0's row of each output
  std::int64_t stride;   // between lanes
  void zero(int n2) const {
    for (int k = 0; k < 3; ++k)
      for (int lane = 0; k < 3 && m[k] && lane < PACK_WIDTH; ++lane) std::fill_n(m[k] + lane * stride, n2, 0.0);
  }
  bool has_M() const { return m[2] != nullptr; }
  void put(int k, size_t at, const Pack& x) const {
    for (int lane = 0; lane < PACK_WIDTH; ++lane) m[k][lane * stride + static_cast<std::int64_t>(at)] = x[lane];
  }
};

// ∂τ/∂q, ∂τ/∂q̇ and (when wanted) ∂τ/∂q̈ = M, written through `out`: the analytical algorithm of
// the file comment, in the coordinates of each tree's root body.
template <class S, class Out>
void rnea_derivatives_to(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* f_ext, bool gravity,
                         const Out& out) {
  const int nb = mv.nb, nv = mv.nv;
  RneaDerivWork<S>& w = thread_workspace<RneaDerivWork<S>>(nb);
  Mat3<S>* R = w.R.data();
  Vec3<S>* p = w.p.data();
  Motion<S>* V = w.v.data();
  Motion<S>* A = w.a.data();
  Motion<S>* J = w.J.data();
  Motion<S>* dV = w.dV.data();
  Motion<S>* dA = w.dA.data();
  Motion<S>* dAv = w.dAv.data();
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  const Motion<S> a0 = base_acceleration<S>(mv, gravity);

  // forward: poses in the root body, ʳS, ʳv, ʳa, the body inertias, momenta and forces, and the columns'
  // ∂V/∂q = v_λ × S,  ∂A/∂q = a_λ × S + v_λ × ∂V/∂q,  ∂A/∂q̇ = ∂V/∂q + v_i × S
  for (int i = 0; i < nb; ++i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i], ki = mv.nv_i[i];
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    Motion<S> v_lam = zero, a_lam;
    RigidInertia<S> oI;
    if (lam == -1) {  // a root body: its own coordinates; the world's acceleration −g seen from it
      R[i] = Mat3<S>::identity();
      p[i] = Vec3<S>{z, z, z};
      a_lam = joint_X_up(mv, i, q).apply(a0);
      oI = I;
      for (int c = 0; c < ki; ++c) J[iv + c] = S_col<S>(mv, i, c);
    } else {
      Mat3<S> Rp;
      Vec3<S> pp;
      pose_in_parent(mv, i, q, Rp, pp);
      if (mv.parent[lam] == -1) {
        R[i] = Rp;
        p[i] = pp;
      } else {
        R[i] = R[lam] * Rp;
        p[i] = p[lam] + R[lam] * pp;
      }
      v_lam = V[lam];
      a_lam = A[lam];
      oI = transform_to_parent(Xform<S>{R[i].transpose(), p[i]}, I);
      for (int c = 0; c < ki; ++c) {
        const Motion<S> s = S_col<S>(mv, i, c);
        const Vec3<S> wr = R[i] * s.w;
        J[iv + c] = {wr, R[i] * s.v + cross(p[i], wr)};
      }
    }
    Motion<S> vJ = zero, aJ = zero;
    for (int c = 0; c < ki; ++c) {
      const Motion<S>& s = J[iv + c];
      const S x = qd[iv + c], y = qdd[iv + c];
      vJ = vJ + Motion<S>{x * s.w, x * s.v};
      aJ = aJ + Motion<S>{y * s.w, y * s.v};
    }
    V[i] = v_lam + vJ;
    A[i] = a_lam + aJ + cross_motion(V[i], vJ);
    const Force<S> h = oI * V[i];
    Force<S> f = oI * A[i] + cross_force(V[i], h);
    if (f_ext) {  // a body-frame force [n; f] in root coordinates: [R n + p × R f; R f]
      const S* fx = f_ext + 6 * i;
      const Vec3<S> Rf = R[i] * Vec3<S>{fx[3], fx[4], fx[5]};
      f = f - Force<S>{R[i] * Vec3<S>{fx[0], fx[1], fx[2]} + cross(p[i], Rf), Rf};
    }
    w.Yc[i] = oI;
    w.Bc[i] = inertia_rate(oI, V[i]);
    w.hc[i] = h;
    w.Fc[i] = f;
    for (int c = 0; c < ki; ++c) {
      const Motion<S>& s = J[iv + c];
      dV[iv + c] = cross_motion(v_lam, s);
      dA[iv + c] = cross_motion(a_lam, s) + cross_motion(v_lam, dV[iv + c]);
      dAv[iv + c] = dV[iv + c] + cross_motion(V[i], s);
    }
  }

  out.zero(nv * nv);
  const bool with_M = out.has_M();
  // backward: when body i's composites are complete, the rows of i against the columns of its support,
  // and the rows of its strict ancestors against the columns of i
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i], ki = mv.nv_i[i];
    const RigidInertia<S>& Yc = w.Yc[i];
    const RigidInertia<S>& Bc = w.Bc[i];
    const Force<S>& hc = w.hc[i];
    for (int c = 0; c < ki; ++c) {
      const int row = iv + c;
      const Motion<S>& s = J[row];
      // rows of i:  ∂τ_i/∂q_j = (I^C S_i)ᵀ ∂A/∂q_j + (D^Cᵀ S_i)ᵀ ∂V/∂q_j,  D^C u = İ^C u + u ×* h^C
      const Force<S> ar = Yc * s;
      const Force<S> br = Bc * s - cross_force(s, hc);
      const size_t r0 = static_cast<size_t>(row) * nv;
      for (int k = i; k != -1; k = mv.parent[k]) {
        const int kv = mv.idx_v[k];
        for (int cc = 0; cc < mv.nv_i[k]; ++cc) {
          const int col = kv + cc;
          out.put(0, r0 + col, dot(dA[col], ar) + dot(dV[col], br));
          out.put(1, r0 + col, dot(dAv[col], ar) + dot(J[col], br));
          if (with_M) {
            const S m = col == row && mv.armature ? dot(J[col], ar) + S(mv.armature[row]) : dot(J[col], ar);
            out.put(2, r0 + col, m);
            out.put(2, static_cast<size_t>(col) * nv + row, m);
          }
        }
      }
      if (lam == -1) continue;
      // column of i, rows of the ancestors:  ∂τ_r/∂q_j = ʳS_rᵀ (S_j ×* F^C + I^C ∂A/∂q_j + D^C ∂V/∂q_j)
      const Force<S> Fq = cross_force(s, w.Fc[i]) + Yc * dA[row] + Bc * dV[row] + cross_force(dV[row], hc);
      const Force<S> Fv = Yc * dAv[row] + Bc * s + cross_force(s, hc);
      for (int k = lam; k != -1; k = mv.parent[k]) {
        const int kv = mv.idx_v[k];
        for (int cc = 0; cc < mv.nv_i[k]; ++cc) {
          const size_t at = static_cast<size_t>(kv + cc) * nv + row;
          out.put(0, at, dot(J[kv + cc], Fq));
          out.put(1, at, dot(J[kv + cc], Fv));
        }
      }
    }
    if (lam != -1) {
      w.Yc[lam] = w.Yc[lam] + Yc;
      w.Bc[lam] = w.Bc[lam] + Bc;
      w.hc[lam] += hc;
      w.Fc[lam] += w.Fc[i];
    }
  }
}

// The same on plain arrays: ∂τ/∂q, ∂τ/∂q̇ (nv, nv) row-major and M (nv, nv) when not null.
template <class S>
void rnea_derivatives(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* f_ext, bool gravity,
                      S* dtau_dq, S* dtau_dv, S* M = nullptr) {
  rnea_derivatives_to(mv, q, qd, qdd, f_ext, gravity, StateOut<S>{{dtau_dq, dtau_dv, M}});
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

// M⁻¹ (nv, nv) row-major from M's tree-sparse factor M = LᵀL (ltl.hpp): M⁻¹ = Zᵀ Z with Z = L⁻ᵀ, whose
// column a is nonzero only on a's ancestor dofs (solving Lᵀ z = e_a climbs the ancestors), so
//
//     row a of M⁻¹ = Σ_{i ∈ anc(a) ∪ {a}} Z_ia · (row i of Z)        (Σ depth · nv products)
//
// The nonzero terms of M⁻¹_ab and M⁻¹_ba are the same products (the common ancestors, deepest first)
// in the same order: M⁻¹ comes out exactly symmetric. Z: nv² scratch.
inline void minv_from_factor(const ModelView& mv, const int* lambda, const double* L, double* Minv, double* Z) {
  const int nv = mv.nv;
  const size_t n2 = static_cast<size_t>(nv) * nv;
  for (size_t k = 0; k < n2; ++k) Z[k] = 0.0, Minv[k] = 0.0;
  for (int a = 0; a < nv; ++a) {  // column a of Z: Lᵀ z = e_a
    Z[static_cast<size_t>(a) * nv + a] = 1.0;
    for (int k = a; k != -1; k = lambda[k]) {
      double& zk = Z[static_cast<size_t>(k) * nv + a];
      zk = zk / L[k * nv + k];
      for (int i = lambda[k]; i != -1; i = lambda[i]) Z[static_cast<size_t>(i) * nv + a] -= L[k * nv + i] * zk;
    }
  }
  for (int a = 0; a < nv; ++a) {
    double* row = Minv + static_cast<size_t>(a) * nv;
    for (int i = a; i != -1; i = lambda[i]) {
      const double zia = Z[static_cast<size_t>(i) * nv + a];
      const double* zi = Z + static_cast<size_t>(i) * nv;
      for (int b = 0; b < nv; ++b) row[b] += zia * zi[b];
    }
  }
}

// q̈ = ABA(q, q̇, τ) and ∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹ (nv, nv) each; `scratch` holds
// aba_derivatives_scratch(nv) doubles. The products with M⁻¹ are solves with M's tree-sparse factor
// (ltl.hpp: M = LᵀL; ∂τ/∂q and ∂τ/∂q̇ side by side, one (nv, 2 nv) block of rows per sweep), M⁻¹ itself
// is Zᵀ Z (minv_from_factor): never a dense product. Returns −1, or the joint whose articulated inertia
// is singular.
inline size_t aba_derivatives_scratch(int nv) { return 3 * static_cast<size_t>(nv) * nv; }

// The second half of aba_derivatives, once M (in L) and ∂τ/∂q, ∂τ/∂q̇ (in dq, dv) are there: factor M,
// dq ← −M⁻¹ dq, dv ← −M⁻¹ dv, Minv ← M⁻¹. X: 2 nv² scratch. Returns −1, or the body of a failed pivot.
inline int aba_derivatives_from_rnea(const ModelView& mv, const int* lambda_d, double* L, double* dq, double* dv,
                                     double* Minv, double* X) {
  const int nv = mv.nv;
  const int bad_dof = ltl_factor(mv, lambda_d, L);
  if (bad_dof >= 0) return dof_body(mv, bad_dof);
  for (int r = 0; r < nv; ++r) {  // [∂τ/∂q  ∂τ/∂q̇] (nv, 2 nv), then −M⁻¹ times it
    double* x = X + 2 * static_cast<size_t>(r) * nv;
    const double* tq = dq + static_cast<size_t>(r) * nv;
    const double* tv = dv + static_cast<size_t>(r) * nv;
    for (int c = 0; c < nv; ++c) x[c] = -tq[c], x[nv + c] = -tv[c];
  }
  ltl_solve_Lt_rows(mv, lambda_d, L, X, 2 * nv);
  ltl_solve_L_rows(mv, lambda_d, L, X, 2 * nv);
  for (int r = 0; r < nv; ++r) {
    const double* x = X + 2 * static_cast<size_t>(r) * nv;
    double* oq = dq + static_cast<size_t>(r) * nv;
    double* ov = dv + static_cast<size_t>(r) * nv;
    for (int c = 0; c < nv; ++c) oq[c] = x[c], ov[c] = x[nv + c];
  }
  minv_from_factor(mv, lambda_d, L, Minv, X);  // Z in X
  return -1;
}

inline int aba_derivatives(const ModelView& mv, const int* lambda_d, const double* q, const double* qd,
                           const double* tau, const double* f_ext, bool gravity, double* qdd, double* dq, double* dv,
                           double* Minv, double* scratch) {
  const int bad = aba(mv, q, qd, tau, f_ext, gravity, qdd);
  if (bad >= 0) return bad;
  double* L = scratch;  // M, then its factor
  rnea_derivatives(mv, q, qd, qdd, f_ext, gravity, dq, dv, L);
  return aba_derivatives_from_rnea(mv, lambda_d, L, dq, dv, Minv, scratch + static_cast<size_t>(mv.nv) * mv.nv);
}

}  // namespace fdcore
