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
// computed here without an articulated-body pass: M and h = τ(q, q̇, 0) from the kernel's composites, q̈
// from M's tree-sparse factor M = LᵀL, then the accelerations added to the kernel's forces and ∂A/∂q; the
// products with M⁻¹ are solves with the same factor, and M⁻¹ = Zᵀ Z with Z = L⁻ᵀ (tree-sparse).
//
// Frame velocities and accelerations (frame_derivatives.hpp) are differentiated by running their template
// on Dual numbers: a value and K directional derivatives, whose tangent seeds are the derivatives of
// q ⊕ ε e_j at ε = 0:
//
//     revolute, prismatic:  δq = e_j
//     spherical (ω in the child frame):           δquat = quat ⊗ (e_c / 2, 0)
//     free-flyer ([ω; v] in the base frame):      δquat = quat ⊗ (e_c / 2, 0)  or  δp = R(quat) e_c
//     planar ([ω, v_x, v_y] in the moving frame): δθ = 1  or  δ(x, y) = R(θ) e_c
#pragma once

#include <algorithm>
#include <type_traits>
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
  std::vector<RigidInertia<S>> I0;         // ʳI_i (forward dynamics: the forces of the accelerations)
  std::vector<Motion<S>> psi;              // forward dynamics: ψ_i = Σ_support ʳS q̈
  std::vector<Force<S>> G;                 // forward dynamics: I_i ψ_i, summed over subtrees
  bool rest = false;                       // q̇ = 0 (no q̇ given): the velocity terms are zero, not formed
  void resize(size_t nb) {
    if (R.size() < nb)
      R.resize(nb), p.resize(nb), v.resize(nb), a.resize(nb), Yc.resize(nb), Bc.resize(nb), hc.resize(nb),
          Fc.resize(nb), J.resize(6 * nb), dV.resize(6 * nb), dA.resize(6 * nb), dAv.resize(6 * nb),
          I0.resize(nb), psi.resize(nb), G.resize(nb);
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
  void zero_one(int k, int n2) const {
    if (m[k]) std::fill(m[k], m[k] + n2, S(0.0));
  }
  bool has_M() const { return m[2] != nullptr; }
  bool has(int k) const { return m[k] != nullptr; }
  void put(int k, size_t at, const S& x) const { m[k][at] = x; }
};
struct LanesOut {
  double* m[3];          // lane 0's row of each output
  std::int64_t stride;   // between lanes
  void zero_one(int k, int n2) const {
    for (int lane = 0; m[k] && lane < PACK_WIDTH; ++lane) std::fill_n(m[k] + lane * stride, n2, 0.0);
  }
  bool has_M() const { return m[2] != nullptr; }
  bool has(int k) const { return m[k] != nullptr; }
  void put(int k, size_t at, const Pack& x) const {
    for (int lane = 0; lane < PACK_WIDTH; ++lane) m[k][lane * stride + static_cast<std::int64_t>(at)] = x[lane];
  }
};

// The passes of the analytical algorithm (file comment), on the thread's RneaDerivWork. Inverse dynamics'
// derivatives (q̈ given): forward, then pairs with the composites summed on the way. Forward dynamics'
// derivatives (τ given) need q̈ first: forward with q̈ = 0, composites (M and h = C q̇ + g − Jᵀf_ext from the
// same sums), q̈ = M⁻¹ (τ − h) by M's factor, then the accelerations S q̈ added (acceleration pass), then
// the pairs: no articulated-body pass at all.

// Forward: poses in the root body, ʳS, ʳv, ʳa (q̈ = 0 when qdd is null), the body inertias, momenta and
// forces, and the columns' ∂V/∂q = v_λ × S,  ∂A/∂q = a_λ × S + v_λ × ∂V/∂q,  ∂A/∂q̇ = ∂V/∂q + v_i × S.
// At rest (qd null: v = 0; with qdd null too, the generalized gravity's and static torque's derivatives, every
// body of a tree moves with its root's acceleration) the momenta, the inertia rates, ∂V/∂q, ∂A/∂q̇ and ∂τ/∂q̇ are
// zero and left unformed, a_i = a_λ + S q̈ and ∂A/∂q = a_λ × S (the impulses' M(q) w, contact_derivatives.hpp).
template <class S>
void rnea_derivatives_forward(const ModelView& mv, RneaDerivWork<S>& w, const S* q, const S* qd, const S* qdd,
                              const S* f_ext, bool gravity) {
  const int nb = mv.nb;
  Mat3<S>* R = w.R.data();
  Vec3<S>* p = w.p.data();
  Motion<S>* V = w.v.data();
  Motion<S>* A = w.a.data();
  Motion<S>* J = w.J.data();
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  const Motion<S> a0 = base_acceleration<S>(mv, gravity);
  w.rest = qd == nullptr;
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
    Motion<S> vJ = zero, aJ = zero;  // Σ S q̇ (not at rest) and Σ S q̈ over i's dofs
    for (int c = 0; c < ki; ++c) {
      const Motion<S>& s = J[iv + c];
      if (!w.rest) vJ = vJ + Motion<S>{qd[iv + c] * s.w, qd[iv + c] * s.v};
      if (qdd) aJ = aJ + Motion<S>{qdd[iv + c] * s.w, qdd[iv + c] * s.v};
    }
    if (w.rest) {
      V[i] = zero;
      A[i] = qdd ? a_lam + aJ : a_lam;
    } else {
      V[i] = v_lam + vJ;
      A[i] = a_lam + aJ + cross_motion(V[i], vJ);
    }
    const Force<S> h = w.rest ? Force<S>{{z, z, z}, {z, z, z}} : oI * V[i];
    Force<S> f = w.rest ? oI * A[i] : oI * A[i] + cross_force(V[i], h);
    if (f_ext) {  // a body-frame force [n; f] in root coordinates: [R n + p × R f; R f]
      const S* fx = f_ext + 6 * i;
      const Vec3<S> Rf = R[i] * Vec3<S>{fx[3], fx[4], fx[5]};
      f = f - Force<S>{R[i] * Vec3<S>{fx[0], fx[1], fx[2]} + cross(p[i], Rf), Rf};
    }
    w.I0[i] = oI;
    w.Yc[i] = oI;
    w.Bc[i] = w.rest ? RigidInertia<S>{z, {z, z, z}, {z, z, z, z, z, z}} : inertia_rate(oI, V[i]);
    w.hc[i] = h;
    w.Fc[i] = f;
    for (int c = 0; c < ki; ++c) {
      const Motion<S>& s = J[iv + c];
      if (w.rest) {
        w.dV[iv + c] = w.dAv[iv + c] = zero;
        w.dA[iv + c] = cross_motion(a_lam, s);
        continue;
      }
      w.dV[iv + c] = cross_motion(v_lam, s);
      w.dA[iv + c] = cross_motion(a_lam, s) + cross_motion(v_lam, w.dV[iv + c]);
      w.dAv[iv + c] = w.dV[iv + c] + cross_motion(V[i], s);
    }
  }
}

// M_ij = S_iᵀ I^C_i S_j for j in i's support (both triangles, + armature), written as output 2 of `out`.
template <class S, class Out>
inline void put_mass_matrix_rows(const ModelView& mv, const RneaDerivWork<S>& w, int i, const Out& out) {
  const int nv = mv.nv;
  const Motion<S>* J = w.J.data();
  for (int c = 0; c < mv.nv_i[i]; ++c) {
    const int row = mv.idx_v[i] + c;
    const Force<S> ar = w.Yc[i] * J[row];
    for (int k = i; k != -1; k = mv.parent[k])
      for (int cc = 0; cc < mv.nv_i[k]; ++cc) {
        const int col = mv.idx_v[k] + cc;
        const S m = col == row && mv.armature ? dot(J[col], ar) + S(mv.armature[row]) : dot(J[col], ar);
        out.put(2, static_cast<size_t>(row) * nv + col, m);
        out.put(2, static_cast<size_t>(col) * nv + row, m);
      }
  }
}

// Backward, forward dynamics: the composites, M (output 2 of `out`, zeroed first) and h = τ(q, q̇, 0) (nv).
template <class S, class Out>
void rnea_derivatives_composites(const ModelView& mv, RneaDerivWork<S>& w, const Out& out, S* h) {
  out.zero_one(2, mv.nv * mv.nv);
  for (int i = mv.nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    put_mass_matrix_rows(mv, w, i, out);
    for (int c = 0; c < mv.nv_i[i]; ++c) h[mv.idx_v[i] + c] = dot(w.J[mv.idx_v[i] + c], w.Fc[i]);
    if (lam != -1) {
      w.Yc[lam] = w.Yc[lam] + w.Yc[i];
      w.Bc[lam] = w.Bc[lam] + w.Bc[i];
      w.hc[lam] += w.hc[i];
      w.Fc[lam] += w.Fc[i];
    }
  }
}

// Forward, forward dynamics: the accelerations ψ_i = ψ_λ + S_i q̈_i added where the forward pass had q̈ = 0:
// ∂A/∂q_j += ψ_λ × S_j, and body i's force by I_i ψ_i (G, summed over subtrees by the pairs pass).
template <class S>
void rnea_derivatives_accelerations(const ModelView& mv, RneaDerivWork<S>& w, const S* qdd) {
  const S z(0.0);
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i];
    const Motion<S> psi_lam = lam == -1 ? Motion<S>{{z, z, z}, {z, z, z}} : w.psi[lam];
    Motion<S> psi = psi_lam;
    for (int c = 0; c < mv.nv_i[i]; ++c) {
      const Motion<S>& s = w.J[iv + c];
      psi = psi + Motion<S>{qdd[iv + c] * s.w, qdd[iv + c] * s.v};
      if (lam != -1) w.dA[iv + c] = w.dA[iv + c] + cross_motion(psi_lam, s);
    }
    w.psi[i] = psi;
    w.G[i] = w.I0[i] * psi;
  }
}

// Backward: the rows of i against the columns of its support and the rows of its strict ancestors
// against the columns of i (outputs 0 and 1 of `out`, zeroed first; 1 skipped when `out` has none). sum_composites: the composites are
// summed here (inverse dynamics; M too when `out` has it); otherwise they are there already and only
// the forces of the acceleration pass are summed into F^C.
template <class S, class Out>
void rnea_derivatives_pairs(const ModelView& mv, RneaDerivWork<S>& w, const Out& out, bool sum_composites) {
  const int nv = mv.nv;
  const Motion<S>* J = w.J.data();
  const Motion<S>* dV = w.dV.data();
  const Motion<S>* dA = w.dA.data();
  const Motion<S>* dAv = w.dAv.data();
  out.zero_one(0, nv * nv);
  out.zero_one(1, nv * nv);
  const bool with_dv = out.has(1);  // ∂τ/∂q̇ wanted (not at rest: the static torque's derivatives)
  const bool with_M = sum_composites && out.has_M();
  if (with_M) out.zero_one(2, nv * nv);
  for (int i = mv.nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i], iv = mv.idx_v[i], ki = mv.nv_i[i];
    if (!sum_composites) w.Fc[i] += w.G[i];
    const RigidInertia<S>& Yc = w.Yc[i];
    const RigidInertia<S>& Bc = w.Bc[i];
    const Force<S>& hc = w.hc[i];
    if (with_M) put_mass_matrix_rows(mv, w, i, out);
    for (int c = 0; c < ki; ++c) {
      const int row = iv + c;
      const Motion<S>& s = J[row];
      // rows of i:  ∂τ_i/∂q_j = (I^C S_i)ᵀ ∂A/∂q_j + (D^Cᵀ S_i)ᵀ ∂V/∂q_j,  D^C u = İ^C u + u ×* h^C
      const Force<S> ar = Yc * s;
      const size_t r0 = static_cast<size_t>(row) * nv;
      if (w.rest) {  // D^C = 0 and ∂V/∂q = 0: the rows are (I^C S_i)ᵀ ∂A/∂q_j, the columns S_rᵀ (S_j ×* F^C + I^C ∂A/∂q_j)
        for (int k = i; k != -1; k = mv.parent[k])
          for (int cc = 0; cc < mv.nv_i[k]; ++cc) out.put(0, r0 + mv.idx_v[k] + cc, dot(dA[mv.idx_v[k] + cc], ar));
        if (lam == -1) continue;
        const Force<S> Fq = cross_force(s, w.Fc[i]) + Yc * dA[row];
        for (int k = lam; k != -1; k = mv.parent[k])
          for (int cc = 0; cc < mv.nv_i[k]; ++cc)
            out.put(0, static_cast<size_t>(mv.idx_v[k] + cc) * nv + row, dot(J[mv.idx_v[k] + cc], Fq));
        continue;
      }
      const Force<S> br = Bc * s - cross_force(s, hc);
      for (int k = i; k != -1; k = mv.parent[k]) {
        const int kv = mv.idx_v[k];
        for (int cc = 0; cc < mv.nv_i[k]; ++cc) {
          const int col = kv + cc;
          out.put(0, r0 + col, dot(dA[col], ar) + dot(dV[col], br));
          if (with_dv) out.put(1, r0 + col, dot(dAv[col], ar) + dot(J[col], br));
        }
      }
      if (lam == -1) continue;
      // column of i, rows of the ancestors:  ∂τ_r/∂q_j = ʳS_rᵀ (S_j ×* F^C + I^C ∂A/∂q_j + D^C ∂V/∂q_j)
      const Force<S> Fq = cross_force(s, w.Fc[i]) + Yc * dA[row] + Bc * dV[row] + cross_force(dV[row], hc);
      if (!with_dv) {
        for (int k = lam; k != -1; k = mv.parent[k])
          for (int cc = 0; cc < mv.nv_i[k]; ++cc)
            out.put(0, static_cast<size_t>(mv.idx_v[k] + cc) * nv + row, dot(J[mv.idx_v[k] + cc], Fq));
        continue;
      }
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
    if (lam == -1) continue;
    if (sum_composites) {
      w.Yc[lam] = w.Yc[lam] + Yc;
      w.Bc[lam] = w.Bc[lam] + Bc;
      w.hc[lam] += hc;
      w.Fc[lam] += w.Fc[i];
    } else {
      w.G[lam] += w.G[i];
    }
  }
}

// ∂τ/∂q, ∂τ/∂q̇ and (when `out` has it) ∂τ/∂q̈ = M at (q, q̇, q̈), written through `out`.
template <class S, class Out>
void rnea_derivatives_to(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* f_ext, bool gravity,
                         const Out& out) {
  RneaDerivWork<S>& w = thread_workspace<RneaDerivWork<S>>(mv.nb);
  rnea_derivatives_forward(mv, w, q, qd, qdd, f_ext, gravity);
  rnea_derivatives_pairs(mv, w, out, true);
}

// q̈ = FD(q, q̇, τ) and ∂τ/∂q, ∂τ/∂q̇ at it, without ABA: M (output 2 of `out`) and h from the composites,
// then solve(h, qdd) (q̈ = M⁻¹ (τ − h) by M's factor, in place of M; −1, or a singular joint's body,
// which stops here), then the accelerations and the pairs (outputs 0 and 1).
template <class S, class Out, class Solve>
int forward_dynamics_derivatives_to(const ModelView& mv, const S* q, const S* qd, const S* f_ext, bool gravity,
                                    const Out& out, S* h, S* qdd, const Solve& solve) {
  RneaDerivWork<S>& w = thread_workspace<RneaDerivWork<S>>(mv.nb);
  rnea_derivatives_forward(mv, w, q, qd, static_cast<const S*>(nullptr), f_ext, gravity);
  rnea_derivatives_composites(mv, w, out, h);
  const int bad = solve(h, qdd);
  if (bad >= 0) return bad;
  rnea_derivatives_accelerations(mv, w, qdd);
  rnea_derivatives_pairs(mv, w, out, false);
  return -1;
}

// The same on plain arrays: ∂τ/∂q, ∂τ/∂q̇ (nv, nv) row-major and M (nv, nv) when not null.
template <class S>
void rnea_derivatives(const ModelView& mv, const S* q, const S* qd, const S* qdd, const S* f_ext, bool gravity,
                      S* dtau_dq, S* dtau_dv, S* M = nullptr) {
  rnea_derivatives_to(mv, q, qd, qdd, f_ext, gravity, StateOut<S>{{dtau_dq, dtau_dv, M}});
}

// The Dual state (Q, V) of a pass over the directions [start, start + lanes) of (q along the tangent, then q̇):
// q and q̇ as constants, lane l seeded along direction start + l (below nv: q's tangent, from nv: q̇'s); the lanes.
inline int seed_state_directions(const ModelView& mv, const double* q, const double* qd, int start, DualK* Q,
                                 DualK* V) {
  const int nv = mv.nv;
  for (int k = 0; k < mv.nq; ++k) Q[k] = DualK(q[k]);
  for (int k = 0; k < nv; ++k) V[k] = DualK(qd[k]);
  const int lanes = std::min(DERIV_LANES, 2 * nv - start);
  for (int l = 0; l < lanes; ++l) {
    const int dir = start + l;
    if (dir < nv) seed_tangent(mv, q, dir, l, Q);
    else V[dir - nv].d[l] = 1.0;
  }
  return lanes;
}

// ∂τ/∂q and ∂τ/∂q̇ (nv, nv) row-major by forward-mode differentiation of the RNEA template on Dual
// numbers: an independent check of the analytical algorithm (tests), eight directions a pass.
inline void rnea_derivatives_dual(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                             const double* f_ext, bool gravity, double* dtau_dq, double* dtau_dv) {
  const int nq = mv.nq, nv = mv.nv, nf = 6 * mv.nb;
  DerivWork<DualK>& w = thread_workspace<DerivWork<DualK>>(mv.nb);
  w.Q.resize(nq), w.V.resize(nv), w.A.resize(nv), w.T.resize(nv);
  w.F.resize(f_ext ? nf : 0);
  for (int k = 0; k < nv; ++k) w.A[k] = DualK(qdd[k]);
  for (int k = 0; f_ext && k < nf; ++k) w.F[k] = DualK(f_ext[k]);
  for (int start = 0; start < 2 * nv; start += DERIV_LANES) {
    const int lanes = seed_state_directions(mv, q, qd, start, w.Q.data(), w.V.data());
    rnea(mv, w.Q.data(), w.V.data(), w.A.data(), f_ext ? w.F.data() : nullptr, gravity, w.T.data());
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l;
      double* out = dir < nv ? dtau_dq + dir : dtau_dv + (dir - nv);
      for (int r = 0; r < nv; ++r) out[r * nv] = w.T[r].d[l];
    }
  }
}

// The factor-and-solve steps of the forward-dynamics derivatives (ltl.hpp's factor and sweeps, and M⁻¹ from
// the factor), templated on the scalar so that one state (double), each lane of a batch (double) and packed
// lanes (Pack) run the same operations: every lane is bit-identical to its one-state result.

// M⁻¹ (nv, nv) row-major from M's factor: M⁻¹ = Zᵀ Z with Z = L⁻ᵀ, whose column a is nonzero only on a's
// ancestor dofs (solving Lᵀ z = e_a climbs the ancestors), so
//
//     row a of M⁻¹ = Σ_{i ∈ anc(a) ∪ {a}} Z_ia · (row i of Z)        (Σ depth · nv products)
//
// The nonzero terms of M⁻¹_ab and M⁻¹_ba are the same products (the common ancestors, deepest first)
// in the same order: M⁻¹ comes out exactly symmetric. Z: nv² scratch.
template <class S>
void minv_from_factor(const ModelView& mv, const int* lambda, const S* L, S* Minv, S* Z) {
  const int nv = mv.nv;
  // Row i of Z is nonzero only on i's subtree, the columns [i, end_i) when the numbering is depth-first:
  // only those are cleared and read (the products skipped would add zero).
  const int* end = subtree_ends(lambda, nv);
  auto row_end = [&](int i) { return end ? end[i] : nv; };
  for (int i = 0; i < nv; ++i)
    std::fill(Z + static_cast<size_t>(i) * nv + (end ? i : 0), Z + static_cast<size_t>(i) * nv + row_end(i), S(0.0));
  for (int a = 0; a < nv; ++a) {  // column a of Z: Lᵀ z = e_a
    Z[static_cast<size_t>(a) * nv + a] = S(1.0);
    for (int k = a; k != -1; k = lambda[k]) {
      S& zk = Z[static_cast<size_t>(k) * nv + a];
      zk = zk / L[k * nv + k];
      for (int i = lambda[k]; i != -1; i = lambda[i]) Z[static_cast<size_t>(i) * nv + a] -= L[k * nv + i] * zk;
    }
  }
  for (int a = 0; a < nv; ++a) {  // the upper triangle b ≥ a, mirrored
    S* row = Minv + static_cast<size_t>(a) * nv;
    std::fill(row + a, row + nv, S(0.0));
    for (int i = a; i != -1; i = lambda[i]) {
      const S zia = Z[static_cast<size_t>(i) * nv + a];
      const S* zi = Z + static_cast<size_t>(i) * nv;
      const int e = row_end(i);
      for (int b = a; b < e; ++b) row[b] += zia * zi[b];
    }
    for (int b = a + 1; b < nv; ++b) Minv[static_cast<size_t>(b) * nv + a] = row[b];
  }
}

// M⁻¹ (nv, nv) row-major: CRBA's M, its tree-sparse factor, then Zᵀ Z (minv_from_factor) — O(nv · depth)
// per row, where ABA on the nv unit forces would repeat the articulated-body pass nv times. Returns −1, or
// the joint whose pivot is not positive (M singular).
inline int mass_matrix_inverse(const ModelView& mv, const double* q, double* Minv) {
  const int nv = mv.nv;
  const size_t n2 = static_cast<size_t>(nv) * nv;
  thread_local std::vector<double> L, Z;
  L.resize(n2), Z.resize(n2);
  const int* lambda = dof_tree(mv).lambda.data();
  crba(mv, q, L.data());
  const int bad_dof = ltl_factor(mv, lambda, L.data());
  if (bad_dof >= 0) return dof_body(mv, bad_dof);
  minv_from_factor(mv, lambda, L.data(), Minv, Z.data());
  return -1;
}

// q̈ = FD(q, q̇, τ) and ∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹ (nv, nv) each; `scratch` holds
// aba_derivatives_scratch(nv) doubles. No articulated-body pass: M and h come from the derivative kernel's
// composites, q̈ = M⁻¹ (τ − h) from M's tree-sparse factor (M = LᵀL), and the products with M⁻¹ are solves
// with the same factor (∂τ/∂q and ∂τ/∂q̇ side by side, one (nv, 2 nv) block of rows per sweep); M⁻¹ itself
// is Zᵀ Z (minv_from_factor): never a dense product. Returns −1, or the joint whose pivot is not positive
// (M singular).
inline size_t aba_derivatives_scratch(int nv) { return 3 * static_cast<size_t>(nv) * nv + 2 * static_cast<size_t>(nv); }

// x ← M⁻¹ (τ − h) with L = M's factor (ltl_factor on M in place first; −1, or the failed pivot's body).
template <class S>
int factor_and_solve(const ModelView& mv, const int* lambda, S* L, const S* tau, const S* h, S* x) {
  const int bad_dof = ltl_factor(mv, lambda, L);
  if (bad_dof >= 0) return dof_body(mv, bad_dof);
  for (int k = 0; k < mv.nv; ++k) x[k] = tau[k] - h[k];
  ltl_solve_Lt(mv, lambda, L, x);
  ltl_solve_L(mv, lambda, L, x);
  return -1;
}

// The second half of aba_derivatives, once L holds M's factor and dq, dv hold ∂τ/∂q, ∂τ/∂q̇:
// dq ← −M⁻¹ dq, dv ← −M⁻¹ dv, Minv ← M⁻¹. X: 2 nv² scratch. The solves negate as they go (ltl_sweeps'
// negate: M⁻¹ (−dq) operation for operation, up to the sign of a zero). The columns are independent, so the
// layout is free: Packs solve each matrix in place; one state solves [dq dv] side by side in X (rows twice
// as long run faster there).
template <class S>
void aba_derivatives_solves(const ModelView& mv, const int* lambda_d, const S* L, S* dq, S* dv, S* Minv, S* X) {
  const int nv = mv.nv;
  if constexpr (std::is_same_v<S, double>) {
    for (int r = 0; r < nv; ++r) {
      std::copy_n(dq + static_cast<size_t>(r) * nv, nv, X + 2 * static_cast<size_t>(r) * nv);
      std::copy_n(dv + static_cast<size_t>(r) * nv, nv, X + (2 * static_cast<size_t>(r) + 1) * nv);
    }
    ltl_solve_rows_tree_pattern(mv, lambda_d, L, X, 2, true);  // ∂τ/∂q and ∂τ/∂q̇: zero off each row's paths
    for (int r = 0; r < nv; ++r) {
      std::copy_n(X + 2 * static_cast<size_t>(r) * nv, nv, dq + static_cast<size_t>(r) * nv);
      std::copy_n(X + (2 * static_cast<size_t>(r) + 1) * nv, nv, dv + static_cast<size_t>(r) * nv);
    }
  } else {
    ltl_solve_rows_tree_pattern(mv, lambda_d, L, dq, 1, true);
    ltl_solve_rows_tree_pattern(mv, lambda_d, L, dv, 1, true);
  }
  minv_from_factor(mv, lambda_d, L, Minv, X);  // Z in X
}

inline int aba_derivatives(const ModelView& mv, const int* lambda_d, const double* q, const double* qd,
                           const double* tau, const double* f_ext, bool gravity, double* qdd, double* dq, double* dv,
                           double* Minv, double* scratch) {
  const size_t n2 = static_cast<size_t>(mv.nv) * mv.nv;
  double* L = scratch;  // M, then its factor
  double* X = scratch + n2;
  double* h = scratch + 3 * n2;
  const int bad = forward_dynamics_derivatives_to(
      mv, q, qd, f_ext, gravity, StateOut<double>{{dq, dv, L}}, h, qdd,
      [&](const double* hh, double* x) { return factor_and_solve(mv, lambda_d, L, tau, hh, x); });
  if (bad >= 0) return bad;
  aba_derivatives_solves(mv, lambda_d, L, dq, dv, Minv, X);
  return -1;
}

}  // namespace fdcore
