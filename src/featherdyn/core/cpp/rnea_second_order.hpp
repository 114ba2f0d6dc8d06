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
// 6 × 6 matrix is formed. The pair's forces are laid out component-major (ForceBlock) so that the innermost
// loop's dot products run as vectors. Entries with the three joints not on one path are zero (a torque's
// derivative along two branches below it has no cross term). Cost: O(nv · depth²) dot products of 6-vectors.
//
// Convention: the tangent fields are fd.integrate's (body-frame on free-flyer, spherical and planar joints),
// the ones the rule X_c S_j = S_c × S_j expresses, so the recursion yields exactly
// d2tau_dq2[i, j, k] = X_k (X_j τ_i) with its bracket on those joints (docs/derivatives.md): no correction.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <initializer_list>
#include <vector>

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

// The motions of a column k the innermost loop reads, as components (w, v): S_k, ψ̇_k, ψ̈_k, ψ̇_k + φ̇_k.
struct ColumnMotions {
  double S[6], ps[6], pd[6], av[6];
};
struct SecondOrderWork {
  std::vector<ColumnMotions> K;
  void resize(size_t) {}
};

FD_INLINE void components(const Motion<double>& m, double* x) {
  x[0] = m.w.x, x[1] = m.w.y, x[2] = m.w.z, x[3] = m.v.x, x[4] = m.v.y, x[5] = m.v.z;
}

// Up to W forces as the columns of a (6, W) block, component-major, each row W doubles held in registers (ltl.hpp's
// Regs: GCC/Clang vector extensions; no vector crosses a call): the W dot products with one motion x are 6 scaled
// rows added, out = Σ_c x_c U[c].
template <int W>
struct ForceBlock {
  double U[6][W] = {};
  FD_INLINE void set(int m, const Force<double>& f) {
    U[0][m] = f.n.x, U[1][m] = f.n.y, U[2][m] = f.n.z, U[3][m] = f.f.x, U[4][m] = f.f.y, U[5][m] = f.f.z;
  }
  FD_INLINE void dots(const double* x, double* out) const {
    Regs<W> acc, row;
    acc.load(U[0]);
    for (int h = 0; h < Regs<W>::N; ++h) acc.r[h] = x[0] * acc.r[h];
    for (int c = 1; c < 6; ++c) {
      row.load(U[c]);
      for (int h = 0; h < Regs<W>::N; ++h) acc.r[h] += x[c] * row.r[h];
    }
    acc.store(out);
  }
};

// (∂²τ/∂q², ∂²τ/∂q̇², ∂²τ/∂q∂q̇, ∂M/∂q) (each (nv, nv, nv) row-major; [i, j, k] = ∂²τ_i/∂x_j∂y_k, q's
// derivatives along fd.integrate's tangent, X_k applied last; dM [i, j, k] = X_k M_ij) of
// τ = RNEA(q, q̇, q̈, f_ext). See the file comment.
inline void rnea_second_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
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
  w2.K.resize(n);
  for (size_t k = 0; k < n; ++k)
    components(J[k], w2.K[k].S), components(dV[k], w2.K[k].ps), components(dA[k], w2.K[k].pd),
        components(dAv[k], w2.K[k].av);
  const SecondOrderOut o{d2q, d2v, dqdv, dM, n};
  for (int i = mv.nb - 1; i >= 0; --i) {  // the composites of i's subtree are complete when i is reached
    const RigidInertia<double>& Ic = w.Yc[i];
    const RigidInertia<double>& Bc = w.Bc[i];  // İ^C (mass 0)
    const F6& hc = w.hc[i];
    const F6& Fc = w.Fc[i];
    for (int p = 0; p < mv.nv_i[i]; ++p) {
      const int ip = mv.idx_v[i] + p;
      const M6 &s = J[ip], &ps = dV[ip];
      // p's operators: r1 = the rate of I^C under s, r3 m = Q3 m + m ×* g3 (r3ᵀ m = Q3 m − m ×* g3), both Q's
      // inertias' rates (symmetric); r4, r5, r7 m = m ×* (a force)
      const RigidInertia<double> Q1 = inertia_rate(Ic, s);
      const RigidInertia<double> Q3 = inertia_rate(Ic, ps) + inertia_rate(Bc, s);
      const F6 Is = Ic * s, g3 = Ic * ps + cross_force(s, hc);
      const F6 Dts = Bc * s - cross_force(s, hc);                                   // D^Cᵀ s
      const F6 f5 = Bc * ps + cross_force(ps, hc) + Ic * dA[ip] + cross_force(s, Fc);
      const F6 f7 = Bc * s + cross_force(s, hc) + Ic * dAv[ip];
      for (int j = i; j != -1; j = mv.parent[j]) {
        for (int qq = 0; qq < mv.nv_i[j]; ++qq) {
          const int jq = mv.idx_v[j] + qq;
          const M6 &Sj = J[jq], &psj = dV[jq];
          const F6 u13 = Q1 * Sj;                                  // r1 S_j
          const F6 u9 = cross_force(Sj, Is);                       // r0 S_j
          const F6 u11 = u13 - u9;                                 // (r1 + r0)ᵀ S_j
          // ψ̇_j = v_λ × S_j vanishes on a root joint (its parent, the world, is still): its terms are not formed
          const bool moving = mv.parent[j] != -1;
          const F6 zero{};
          const F6 Q1ps = moving ? Q1 * psj : zero, Jps = moving ? cross_force(psj, Is) : zero;
          const F6 u8m12 = cross_force(Sj, Dts) - (Q1ps - Jps);    // r4 S_j − (r1 + r0)ᵀ ψ̇_j
          const F6 u4 = u9 + cross_force(s, Ic * Sj);              // r6 S_j
          const F6 u6 = Q1ps + Jps + cross_force(Sj, f7);          // (r1 + r0) ψ̇_j + r7 S_j
          const F6 Q3S = Q3 * Sj, Sg3 = cross_force(Sj, g3);
          const F6 u7 = Q3S + Sg3 + Q1 * dAv[jq];                  // r3 S_j + r1 (ψ̇_j + φ̇_j)
          const F6 u1 = Q3S - Sg3;                                 // r3ᵀ S_j
          const F6 u3 = (moving ? Q3 * psj + cross_force(psj, g3) : zero) + Q1 * dA[jq] + cross_force(Sj, f5);
          // the dot products of the innermost loop, by the motion they pair with
          ForceBlock<8> US;  // S_k with u13, u9, u1, u3, u8m12, u6, u7, u4
          ForceBlock<4> UP;  // ψ̇_k with u11, u8m12, u1
          ForceBlock<2> UD;  // ψ̈_k, and ψ̇_k + φ̇_k, with u9, u13
          const F6* s_forces[8] = {&u13, &u9, &u1, &u3, &u8m12, &u6, &u7, &u4};
          for (int m = 0; m < 8; ++m) US.set(m, *s_forces[m]);
          UP.set(0, u11), UP.set(1, u8m12), UP.set(2, u1);
          UD.set(0, u9), UD.set(1, u13);
          for (int k = j; k != -1; k = mv.parent[k]) {
            for (int rr = 0; rr < mv.nv_i[k]; ++rr) {
              const int kr = mv.idx_v[k] + rr;
              const ColumnMotions& K = w2.K[static_cast<size_t>(kr)];
              double sS[8], sP[4] = {}, sD[2], sA[2];
              US.dots(K.S, sS), UD.dots(K.pd, sD), UD.dots(K.av, sA);
              if (mv.parent[k] != -1) UP.dots(K.ps, sP);  // (ψ̇_k = 0 on a root joint)
              const double p1 = sP[0];                 // ψ̇_kᵀ u11
              const double p2 = sD[0] + sP[1];         // ψ̈_kᵀ u9 + ψ̇_kᵀ u8m12
              const double p4 = sS[0], p5 = sS[1];     // S_kᵀ u13, S_kᵀ u9
              o.at(d2q, ip, jq, kr) = p2;
              o.at(dqdv, ip, kr, jq) = -p1;
              if (j != i) {
                o.at(d2q, jq, kr, ip) = o.at(d2q, jq, ip, kr) = sP[2] + sD[1];
                o.at(dqdv, jq, kr, ip) = p1;
                o.at(dqdv, jq, ip, kr) = sS[2] + sA[1];
                o.at(d2v, jq, kr, ip) = o.at(d2v, jq, ip, kr) = p4 - p5;  // S_kᵀ u11
                o.at(dM, kr, jq, ip) = o.at(dM, jq, kr, ip) = p4;
              }
              if (k == j) {
                o.at(d2v, ip, jq, kr) = -p4;
                continue;
              }
              o.at(d2q, ip, kr, jq) = p2;
              o.at(d2q, kr, ip, jq) = sS[3];
              o.at(d2v, ip, jq, kr) = o.at(d2v, ip, kr, jq) = p5 - p4;
              o.at(dqdv, ip, jq, kr) = sS[4] + sA[0];
              o.at(dqdv, kr, jq, ip) = sS[5];
              o.at(dM, kr, ip, jq) = o.at(dM, ip, kr, jq) = p5;
              if (j != i) {
                o.at(d2q, kr, jq, ip) = o.at(d2q, kr, ip, jq);
                o.at(d2v, kr, ip, jq) = o.at(d2v, kr, jq, ip) = p4 + p5;  // S_kᵀ u10
                o.at(dqdv, kr, ip, jq) = sS[6];
              } else {
                o.at(d2v, kr, jq, ip) = sS[7];
              }
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
}

}  // namespace fdcore
