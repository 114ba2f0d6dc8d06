// Second-order derivatives of inverse dynamics, analytically (reference: featherdyn/algorithms/second_order.py;
// docs/derivatives.md, "Second order"; Singh, Russell & Wensing, "Analytical Second-Order Partial Derivatives
// of Rigid-Body Inverse Dynamics", IROS 2022).
//
// The quantities of the first order (derivatives.hpp, its forward pass reused as is), all in the root body's
// coordinates: per column j of joint k, S_j, ψ̇_j = v_λ(k) × S_j (∂V/∂q_j), ψ̈_j = a_λ(k) × S_j + v_λ(k) × ψ̇_j
// (∂A/∂q_j), φ̇_j = v_k × S_j (so ∂A/∂q̇_j = ψ̇_j + φ̇_j); per body the composites over its subtree I^C, the
// force F^C and D^C u = İ^C u + u ×* h^C (İ the inertia's rate, h the momentum). Moving q along the tangent
// X_c of a column c of a joint on the path moves the columns below it rigidly:
//
//     X_c S_j = S_c × S_j        (c's joint an ancestor of j's, or the same joint: fd.integrate's tangent fields
//                                 are the body-frame ones, so this holds between any two columns of one joint)
//
// and likewise I^C, F^C, h^C, ψ̇, ψ̈ pick up their own rigid-motion terms. Differentiating the first order's
// expressions (∂τ_i/∂q_j = S_iᵀ (I^C ψ̈_j + D^C ψ̇_j) …) once more with these rules gives, for three columns
// whose joints lie on one path, p of the deepest joint, q of a joint on its path and r above that
// (joint(r) ⪯ joint(q) ⪯ joint(p)), every entry of the four tensors as dot products of S_r, ψ̇_r, ψ̈_r,
// ψ̇_r + φ̇_r with a dozen forces formed per pair (p, q) from the operators of p (s = S_p, I = I^C_p, D = D^C_p):
//
//     r1 m = s ×* (I m) − I (s × m) = Q1 m           Q1 = the rate of I under s (inertia_rate: symmetric)
//     r0 m = m ×* (I s)                              (antisymmetric)
//     r3 m = ψ̇ ×* (I m) − I (ψ̇ × m) + m ×* (I ψ̇) + s ×* (D m) − D (s × m) = Q3 m + m ×* g3,
//            Q3 = the rate of I under ψ̇ + the rate of İ^C under s,   g3 = I ψ̇ + s ×* h^C,   r3ᵀ m = Q3 m − m ×* g3
//
// (D m = İ^C m + m ×* h^C, and s ×* (m ×* h) − (s × m) ×* h = m ×* (s ×* h)). Singh et al. write these, and
// r4 … r7 (m ↦ m ×* a force), as 6 × 6 matrices; here each is applied as an inertia or a cross product, and no
// 6 × 6 matrix is formed. The columns q of p's path are taken PACK_WIDTH at a time, one a lane (pack.hpp): their
// forces are formed and dotted with each r's motions as vectors, each lane the operations of one column. Entries
// with the three joints not on one path are zero (a torque's derivative along two branches below it has no cross
// term). Cost: O(nv · depth²) dot products of 6-vectors.
//
// Convention: the tangent fields are fd.integrate's (body-frame on free-flyer, spherical and planar joints),
// the ones the rule X_c S_j = S_c × S_j expresses, so the recursion yields exactly
// d2tau_dq2[i, j, k] = X_k (X_j τ_i) with its bracket on those joints (docs/derivatives.md): no correction.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <vector>

#include "checks.hpp"  // all_below
#include "derivatives.hpp"
#include "scratch.hpp"

namespace fdcore {

// The four tensors (nv, nv, nv) row-major, [a, b, c] at (a nv + b) nv + c, written entry by entry.
struct SecondOrderOut {
  double *d2q, *d2v, *dqdv, *dM;
  size_t n;
  double& at(double* t, int a, int b, int c) const {
    return t[(static_cast<size_t>(a) * n + static_cast<size_t>(b)) * n + static_cast<size_t>(c)];
  }
};

// The motions of a column k the innermost loop reads, as components (w, v) in one array: S_k, ψ̇_k, ψ̈_k,
// ψ̇_k + φ̇_k at 0, 6, 12, 18.
struct ColumnMotions {
  double x[24];
  const double* S() const { return x; }
  const double* ps() const { return x + 6; }
  const double* pd() const { return x + 12; }
  const double* av() const { return x + 18; }
};
struct SecondOrderWork {
  std::vector<ColumnMotions> K;
  void resize(size_t) {}
};

FD_INLINE void components(const Motion<double>& m, double* x) {
  x[0] = m.w.x, x[1] = m.w.y, x[2] = m.w.z, x[3] = m.v.x, x[4] = m.v.y, x[5] = m.v.z;
}

// Bounds under which no entry overflows. A pair's force (u… below) is a sum of at most 20 products (u4's: the 4
// of u9 and the 2 · 5 + 2 · 3 of s ×* (I^C S_j); an inertia times a motion has at most 5 per component, a cross
// product 4), each of one of p's operators' numbers (Q1, Q3, I^C, I^C s, g3, D^Cᵀ s, f5, f7: below 2^500) and one
// or two motion components (S, ψ̇, ψ̈, ψ̇ + φ̇ of any column: below 2^170), so below 20 · 2^840 < 2^845; an entry
// is one dot product of a force with a motion, or two summed: below 2 · 6 · 2^845 · 2^170 < 2^1019, and float64's
// largest is just under 2^1024. The bits of 2^e are (e + 1023) · 2^52.
constexpr std::uint64_t OPERATOR_BOUND = std::uint64_t{500 + 1023} << 52,
                        MOTION_BOUND = std::uint64_t{170 + 1023} << 52;

FD_INLINE void components(const Force<double>& f, double* x) {
  x[0] = f.n.x, x[1] = f.n.y, x[2] = f.n.z, x[3] = f.f.x, x[4] = f.f.y, x[5] = f.f.z;
}
FD_INLINE void components(const RigidInertia<double>& I, double* x) {
  x[0] = I.m, x[1] = I.h.x, x[2] = I.h.y, x[3] = I.h.z, x[4] = I.I.xx, x[5] = I.I.xy, x[6] = I.I.xz,
  x[7] = I.I.yy, x[8] = I.I.yz, x[9] = I.I.zz;
}

// p's operators (see the file comment), the same for every column q on its path: s = S_p, I = I^C_p, Q1, Q3,
// I s, g3, D^Cᵀ s, and f5, f7 (the forces r5, r7 take the cross product with).
template <class S>
struct PairOperators {
  Motion<S> s;
  RigidInertia<S> I, Q1, Q3;
  Force<S> Is, g3, Dts, f5, f7;
};

// The forces of the pair (p, q) that the innermost loop dots with r's motions, from p's operators and q's
// motions S_q, ψ̇_q, ψ̈_q, ψ̇_q + φ̇_q: for a Pack of columns q, lane by lane the operations of one column.
template <class S>
struct PairForces {
  Force<S> u13, u9, u11, u8m12, u4, u6, u7, u1, u3;
};
template <class S>
FD_INLINE PairForces<S> pair_forces(const PairOperators<S>& o, const Motion<S>& Sq, const Motion<S>& psq,
                                    const Motion<S>& pdq, const Motion<S>& avq) {
  PairForces<S> u;
  u.u13 = o.Q1 * Sq;                                     // r1 S_q
  u.u9 = cross_force(Sq, o.Is);                          // r0 S_q
  u.u11 = u.u13 - u.u9;                                  // (r1 + r0)ᵀ S_q
  const Force<S> Q1ps = o.Q1 * psq, Jps = cross_force(psq, o.Is);
  u.u8m12 = cross_force(Sq, o.Dts) - (Q1ps - Jps);       // r4 S_q − (r1 + r0)ᵀ ψ̇_q
  u.u4 = u.u9 + cross_force(o.s, o.I * Sq);              // r6 S_q
  u.u6 = Q1ps + Jps + cross_force(Sq, o.f7);             // (r1 + r0) ψ̇_q + r7 S_q
  const Force<S> Q3S = o.Q3 * Sq, Sg3 = cross_force(Sq, o.g3);
  u.u7 = Q3S + Sg3 + o.Q1 * avq;                         // r3 S_q + r1 (ψ̇_q + φ̇_q)
  u.u1 = Q3S - Sg3;                                      // r3ᵀ S_q
  u.u3 = o.Q3 * psq + cross_force(psq, o.g3) + o.Q1 * pdq + cross_force(Sq, o.f5);  // r3 ψ̇_q + r1 ψ̈_q + r5 S_q
  return u;
}

FD_INLINE Vec3<Pack> lanes_of(const Vec3<double>& a) { return {a.x, a.y, a.z}; }
FD_INLINE Motion<Pack> lanes_of(const Motion<double>& m) { return {lanes_of(m.w), lanes_of(m.v)}; }
FD_INLINE Force<Pack> lanes_of(const Force<double>& f) { return {lanes_of(f.n), lanes_of(f.f)}; }
FD_INLINE RigidInertia<Pack> lanes_of(const RigidInertia<double>& I) {
  return {I.m, lanes_of(I.h), {I.I.xx, I.I.xy, I.I.xz, I.I.yy, I.I.yz, I.I.zz}};
}
// The 15 dot products of r's motions (K) with the pair forces (u), on the first L lanes: product k's lane l at
// e[k PACK_WIDTH + l]. Each is a sum in the order of the components, m[0] f[0] + m[1] f[1] + …, so a lane gives
// the same bits at any L. The caller takes L = PACK_WIDTH / 2 for 512-bit packs while the other half's columns
// are below r (their entries are not written): AMD's Zen 4 runs a 512-bit operation as two 256-bit ones, so the
// half costs half (2026-12-01: panda's call −3 … −8 % there); a 128-bit half of a 256-bit pack saved nothing.
template <size_t L>
FD_INLINE void pair_dots(const ColumnMotions& K, bool moving, const PairForces<Pack>& u, double* e) {
  typedef double V __attribute__((vector_size(8 * L)));
  const auto dot = [&](size_t slot, const double* m, const Force<Pack>& f) {
    const Pack* c[6] = {&f.n.x, &f.n.y, &f.n.z, &f.f.x, &f.f.y, &f.f.z};  // the first L lanes of each
    V d, x;
    std::memcpy(&x, &c[0]->v, sizeof x), d = (V{} + m[0]) * x;
    for (size_t h = 1; h < 6; ++h) std::memcpy(&x, &c[h]->v, sizeof x), d += (V{} + m[h]) * x;
    std::memcpy(e + slot * PACK_WIDTH, &d, sizeof d);
  };
  // S_rᵀ u13, u9, u1, u3, u8m12, u6, u7, u4; ψ̇_rᵀ u11, u8m12, u1; ψ̈_rᵀ u9, u13; (ψ̇_r + φ̇_r)ᵀ u9, u13
  dot(0, K.S(), u.u13), dot(1, K.S(), u.u9), dot(2, K.S(), u.u1), dot(3, K.S(), u.u3), dot(4, K.S(), u.u8m12);
  dot(5, K.S(), u.u6), dot(6, K.S(), u.u7), dot(7, K.S(), u.u4);
  if (moving) {
    dot(8, K.ps(), u.u11), dot(9, K.ps(), u.u8m12), dot(10, K.ps(), u.u1);
  } else {  // ψ̇ = 0 on a root joint
    for (size_t slot = 8; slot < 11; ++slot) std::memset(e + slot * PACK_WIDTH, 0, L * sizeof(double));
  }
  dot(11, K.pd(), u.u9), dot(12, K.pd(), u.u13), dot(13, K.av(), u.u9), dot(14, K.av(), u.u13);
}

// A path's columns: i's first, then its ancestors' (each joint's in order), with where each one's joint's columns
// start and end in it, and whether that joint has a parent (ψ̇ = 0 on a root joint).
struct SecondOrderPath {
  std::vector<int> column, first, end;
  std::vector<unsigned char> moving;
  void resize(size_t) {}
};

// (∂²τ/∂q², ∂²τ/∂q̇², ∂²τ/∂q∂q̇, ∂M/∂q) (each (nv, nv, nv) row-major; [i, j, k] = ∂²τ_i/∂x_j∂y_k, q's
// derivatives along fd.integrate's tangent, X_k applied last; dM [i, j, k] = X_k M_ij) of
// τ = RNEA(q, q̇, q̈, f_ext). See the file comment. Returns whether every factor was within the bounds above, so
// that every entry is finite (all_below, which a NaN fails); false: the caller scans the outputs.
inline bool rnea_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                                    const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                    double* dM) {
  using F6 = Force<double>;
  using M6 = Motion<double>;
  const size_t n = static_cast<size_t>(mv.nv), n3 = n * n * n;
  for (double* t : {d2q, d2v, dqdv, dM}) std::fill(t, t + n3, 0.0);
  RneaDerivWork<double>& w = thread_workspace<RneaDerivWork<double>>(mv.nb);
  rnea_derivatives_forward(mv, w, q, qd, qdd, f_ext, gravity);  // S, ψ̇ (dV), ψ̈ (dA), ψ̇ + φ̇ (dAv), the bodies'
  const M6* J = w.J.data();
  const M6* dV = w.dV.data();
  const M6* dA = w.dA.data();
  const M6* dAv = w.dAv.data();
  SecondOrderWork& w2 = thread_workspace<SecondOrderWork>(mv.nb);
  SecondOrderPath& path = thread_workspace<SecondOrderPath>(mv.nb);
  w2.K.resize(n);
  bool bounded = true;
  for (size_t k = 0; k < n; ++k) {
    double* x = w2.K[k].x;
    components(J[k], x), components(dV[k], x + 6), components(dA[k], x + 12), components(dAv[k], x + 18);
    bounded &= all_below(x, 24, MOTION_BOUND);
  }
  for (std::vector<int>* v : {&path.column, &path.first, &path.end}) v->resize(n);
  path.moving.resize(n);
  static constexpr double no_motion[24] = {};  // the lanes past a path's end
  const SecondOrderOut o{d2q, d2v, dqdv, dM, n};
  for (int i = mv.nb - 1; i >= 0; --i) {  // the composites of i's subtree are complete when i is reached
    const RigidInertia<double>& Ic = w.Yc[i];
    const RigidInertia<double>& Bc = w.Bc[i];  // İ^C (mass 0)
    const F6& hc = w.hc[i];
    const F6& Fc = w.Fc[i];
    size_t np = 0;  // i's path, i's columns first, then its ancestors' (each joint's in order)
    for (int j = i; j != -1; j = mv.parent[j]) {
      const size_t start = np;
      for (int c = 0; c < mv.nv_i[j]; ++c, ++np)
        path.column[np] = mv.idx_v[j] + c, path.first[np] = static_cast<int>(start);
      for (size_t t = start; t < np; ++t) path.end[t] = static_cast<int>(np), path.moving[t] = mv.parent[j] != -1;
    }
    const size_t ni = static_cast<size_t>(mv.nv_i[i]);
    for (int p = 0; p < mv.nv_i[i]; ++p) {
      const int ip = mv.idx_v[i] + p;
      const M6 &s = J[ip], &ps = dV[ip];
      // p's operators: Q1 = the rate of I^C under s, Q3 = the rates of I^C under ψ̇ and of İ^C under s (both
      // symmetric: r3 m = Q3 m + m ×* g3, r3ᵀ m = Q3 m − m ×* g3); r4, r5, r7 m = m ×* (a force)
      PairOperators<double> op{s, Ic, inertia_rate(Ic, s), inertia_rate(Ic, ps) + inertia_rate(Bc, s), Ic * s,
                               {}, Bc * s - cross_force(s, hc), {}, {}};  // Dts = D^Cᵀ s
      op.g3 = Ic * ps + cross_force(s, hc);
      op.f5 = Bc * ps + cross_force(ps, hc) + Ic * dA[ip] + cross_force(s, Fc);
      op.f7 = Bc * s + cross_force(s, hc) + Ic * dAv[ip];
      double numbers[60];
      components(op.Q1, numbers), components(op.Q3, numbers + 10), components(Ic, numbers + 20);
      components(op.Is, numbers + 30), components(op.g3, numbers + 36), components(op.Dts, numbers + 42);
      components(op.f5, numbers + 48), components(op.f7, numbers + 54);
      bounded &= all_below(numbers, 60, OPERATOR_BOUND);
      const PairOperators<Pack> lanes{lanes_of(op.s), lanes_of(op.I), lanes_of(op.Q1), lanes_of(op.Q3),
                                      lanes_of(op.Is), lanes_of(op.g3), lanes_of(op.Dts), lanes_of(op.f5),
                                      lanes_of(op.f7)};
      // PACK_WIDTH columns q at a time (lanes past the path's end: no motion), their forces, then for each r
      // on the joint of the first or above, every lane's dot products, and each lane whose q is on r's path
      // writes its entries
      for (size_t t0 = 0; t0 < np; t0 += PACK_WIDTH) {
        const double* x[PACK_WIDTH];
        for (size_t l = 0; l < PACK_WIDTH; ++l)
          x[l] = t0 + l < np ? w2.K[static_cast<size_t>(path.column[t0 + l])].x : no_motion;
        Motion<Pack> m[4];
        for (size_t h = 0; h < 4; ++h)
          m[h] = {{load_lanes(x, 6 * h), load_lanes(x, 6 * h + 1), load_lanes(x, 6 * h + 2)},
                  {load_lanes(x, 6 * h + 3), load_lanes(x, 6 * h + 4), load_lanes(x, 6 * h + 5)}};
        const PairForces<Pack> u = pair_forces(lanes, m[0], m[1], m[2], m[3]);
        const size_t tn = std::min(np, t0 + PACK_WIDTH);
        // the lanes from t0 + H on are below r until r reaches their joint (a path lists descendants first)
        constexpr size_t H = PACK_WIDTH >= 8 ? PACK_WIDTH / 2 : PACK_WIDTH;  // see pair_dots
        const size_t r_all = t0 + H < np ? static_cast<size_t>(path.first[t0 + H]) : np;
        for (size_t r = static_cast<size_t>(path.first[t0]); r < np; ++r) {
          const int kr = path.column[r];
          double e[15 * PACK_WIDTH];  // r's 15 dot products with each lane's forces (pair_dots)
          if (r < r_all)
            pair_dots<H>(w2.K[static_cast<size_t>(kr)], path.moving[r], u, e);
          else
            pair_dots<PACK_WIDTH>(w2.K[static_cast<size_t>(kr)], path.moving[r], u, e);
          for (size_t t = t0; t < tn; ++t) {  // q = path.column[t], on joint j: j == i for t < ni
            if (r < static_cast<size_t>(path.first[t])) continue;  // r below q's joint
            const int jq = path.column[t];
            const double* el = e + (t - t0);  // this lane's: S_rᵀ u13 at el[0], …, (ψ̇_r + φ̇_r)ᵀ u13 at el[14 W]
            constexpr size_t W = PACK_WIDTH;
            const double p1 = el[8 * W];                // ψ̇_rᵀ u11
            const double p2 = el[11 * W] + el[9 * W];   // ψ̈_rᵀ u9 + ψ̇_rᵀ u8m12
            const double p4 = el[0], p5 = el[W];        // S_rᵀ u13, S_rᵀ u9
            o.at(d2q, ip, jq, kr) = p2;
            o.at(dqdv, ip, kr, jq) = -p1;
            if (t >= ni) {  // j above i
              o.at(d2q, jq, kr, ip) = o.at(d2q, jq, ip, kr) = el[10 * W] + el[12 * W];
              o.at(dqdv, jq, kr, ip) = p1;
              o.at(dqdv, jq, ip, kr) = el[2 * W] + el[14 * W];
              o.at(d2v, jq, kr, ip) = o.at(d2v, jq, ip, kr) = p4 - p5;  // S_rᵀ u11
              o.at(dM, kr, jq, ip) = o.at(dM, jq, kr, ip) = p4;
            }
            if (r < static_cast<size_t>(path.end[t])) {  // r on j's joint
              o.at(d2v, ip, jq, kr) = -p4;
              continue;
            }
            o.at(d2q, ip, kr, jq) = p2;
            o.at(d2q, kr, ip, jq) = el[3 * W];
            o.at(d2v, ip, jq, kr) = o.at(d2v, ip, kr, jq) = p5 - p4;
            o.at(dqdv, ip, jq, kr) = el[4 * W] + el[13 * W];
            o.at(dqdv, kr, jq, ip) = el[5 * W];
            o.at(dM, kr, ip, jq) = o.at(dM, ip, kr, jq) = p5;
            if (t >= ni) {
              o.at(d2q, kr, jq, ip) = o.at(d2q, kr, ip, jq);
              o.at(d2v, kr, ip, jq) = o.at(d2v, kr, jq, ip) = p4 + p5;  // S_rᵀ u10
              o.at(dqdv, kr, ip, jq) = el[6 * W];
            } else {
              o.at(d2v, kr, jq, ip) = el[7 * W];
            }
          }
        }
      }
    }
    const int lam = mv.parent[i];
    if (lam == -1) continue;
    w.Yc[lam] = w.Yc[lam] + Ic;
    w.Bc[lam] = w.Bc[lam] + Bc;
    w.hc[lam] += hc;
    w.Fc[lam] += Fc;
  }
  return bounded;
}

}  // namespace fdcore
