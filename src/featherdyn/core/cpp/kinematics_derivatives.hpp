// Derivatives of a frame's motion, of the centre of mass and of the centroidal momentum and its rate
// (reference: featherdyn/algorithms/kinematics_derivatives.py, the analytical formulas in world columns;
// Pinocchio's computeForwardKinematicsDerivatives + get{Frame,Point}*Derivatives,
// getCenterOfMassVelocityDerivatives, computeCentroidalDynamicsDerivatives):
//
//     frame f (at a point of it):  v_f, a_f (spatial), a_f^c = [ω̇; a_lin + ω × v_lin]       (frame_derivatives.hpp)
//     centre of mass:              c = Σ m_i ⁰c_i / m,   ċ = Σ ⁰R_i (m_i v_i + ω_i × h_i) / m    (energy.hpp)
//     centroidal:                  h_G = [k_O − c × p; p],   ḣ_G = [k̇_O − c × ṗ; ṗ],
//                                  h_O = Σ ⁰X_i* I_i v_i,   ḣ_O = Σ ⁰X_i* (I_i a_i + v_i ×* I_i v_i)   (a_i: no gravity)
//
// Each value is a template on the scalar; its derivatives come from the template run on Dual numbers
// (derivatives.hpp), DERIV_LANES directions a pass: ∂/∂q along the tangent of fd.integrate, then ∂/∂q̇, ∂/∂q̈.
#pragma once

#include <algorithm>

#include "centroidal.hpp"
#include "energy.hpp"
#include "frame_derivatives.hpp"

namespace fdcore {

// `eval(Q, V, A, T)` on Dual numbers over `blocks` blocks of nv directions — block 0 the tangent of q, 1 q̇, 2 q̈ —
// and `store(block, column, lane, T)` for each direction; T holds `nout` values. qd, qdd may be nullptr (V, A too).
template <class Eval, class Store>
void dual_directions(const ModelView& mv, const double* q, const double* qd, const double* qdd, int blocks, int nout,
                     Eval&& eval, Store&& store) {
  const int nq = mv.nq, nv = mv.nv, ndir = blocks * nv;
  DerivWork<DualK>& w = thread_workspace<DerivWork<DualK>>(mv.nb);
  w.Q.resize(static_cast<size_t>(nq)), w.V.resize(static_cast<size_t>(nv)), w.A.resize(static_cast<size_t>(nv));
  w.T.resize(static_cast<size_t>(nout));
  for (int start = 0; start < ndir; start += DERIV_LANES) {
    for (int k = 0; k < nq; ++k) w.Q[k] = DualK(q[k]);
    for (int k = 0; qd && k < nv; ++k) w.V[k] = DualK(qd[k]);
    for (int k = 0; qdd && k < nv; ++k) w.A[k] = DualK(qdd[k]);
    const int lanes = std::min(DERIV_LANES, ndir - start);
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l;
      if (dir < nv) seed_tangent(mv, q, dir, l, w.Q.data());
      else if (dir < 2 * nv) w.V[dir - nv].d[l] = 1.0;
      else w.A[dir - 2 * nv].d[l] = 1.0;
    }
    eval(w.Q.data(), qd ? w.V.data() : nullptr, qdd ? w.A.data() : nullptr, w.T.data());
    for (int l = 0; l < lanes; ++l) store((start + l) / nv, (start + l) % nv, l, w.T.data());
  }
}

// A frame's (at `point`, or nullptr) motion derivatives in `ref`, (6, nv) row-major each, into out:
// ∂v/∂q, ∂v/∂q̇, ∂a/∂q, ∂a/∂q̇, ∂a^c/∂q, ∂a^c/∂q̇ (∂a/∂q̈ = ∂a^c/∂q̈ = ∂v/∂q̇ = J: not formed twice).
inline void kinematics_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                                   int frame, const double* point, int ref, double* const* out) {
  const int nv = mv.nv;
  dual_directions(
      mv, q, qd, qdd, 2, 18,
      [&](const DualK* Q, const DualK* V, const DualK* A, DualK* T) {
        frame_motion(mv, Q, V, A, frame, ref, T, T + 6, point, T + 12);
      },
      [&](int block, int col, int l, const DualK* T) {
        for (int r = 0; r < 6; ++r) {
          out[block][r * nv + col] = T[r].d[l];
          out[2 + block][r * nv + col] = T[6 + r].d[l];
          out[4 + block][r * nv + col] = T[12 + r].d[l];
        }
      });
}

// ∂c/∂q and ∂ċ/∂q (3, nv) row-major; `mass` the tree's total mass (> 0).
inline void center_of_mass_derivatives(const ModelView& mv, const double* q, const double* qd, double mass,
                                       double* dc_dq, double* dcd_dq) {
  const int nv = mv.nv;
  dual_directions(
      mv, q, qd, nullptr, 1, 6,
      [&](const DualK* Q, const DualK* V, const DualK*, DualK* T) { center_of_mass(mv, Q, V, mass, T, T + 3); },
      [&](int, int col, int l, const DualK* T) {
        for (int r = 0; r < 3; ++r) dc_dq[r * nv + col] = T[r].d[l], dcd_dq[r * nv + col] = T[3 + r].d[l];
      });
}

// h_G (6,) and ḣ_G (6,), rows [k; p] in world axes about the centre of mass (the file comment); `mass` > 0.
template <class S>
void centroidal_momentum_rate(const ModelView& mv, const S* q, const S* qd, const S* qdd, double mass, S* h,
                              S* hdot) {
  FkWork<S>& w = thread_workspace<FkWork<S>>(mv.nb);
  Mat3<S>* oR = w.oR.data();
  Vec3<S>* op = w.op.data();
  Motion<S>* v = w.v.data();
  Motion<S>* a = w.a.data();
  const S z(0.0);
  Vec3<S> mc{z, z, z};
  Force<S> hO{{z, z, z}, {z, z, z}}, fO = hO;
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i];
    Mat3<S> R;
    Vec3<S> p;
    place_body(mv, i, q, oR, op, R, p);
    const Xform<S> X_up{R.transpose(), p};
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up.apply(v[lam]) + vJ;
    const Motion<S> aJ = S_times(mv, i, qdd) + cross_motion(v[i], vJ);
    a[i] = lam == -1 ? aJ : X_up.apply(a[lam]) + aJ;
    const RigidInertia<S> I = body_inertia<S>(mv, i);
    const Force<S> hb = I * v[i];
    const Force<S> fb = I * a[i] + cross_force(v[i], hb);
    auto to_world = [&](const Force<S>& f) {  // ⁰X_i* f
      const Vec3<S> f0 = oR[i] * f.f;
      return Force<S>{oR[i] * f.n + cross(op[i], f0), f0};
    };
    hO += to_world(hb);
    fO += to_world(fb);
    mc += S(mv.mass[i]) * op[i] + oR[i] * load3<S>(mv.h + 3 * i);
  }
  const Vec3<S> c = (S(1.0) / S(mass)) * mc;
  const Vec3<S> k = hO.n - cross(c, hO.f), kd = fO.n - cross(c, fO.f);
  h[0] = k.x, h[1] = k.y, h[2] = k.z, h[3] = hO.f.x, h[4] = hO.f.y, h[5] = hO.f.z;
  hdot[0] = kd.x, hdot[1] = kd.y, hdot[2] = kd.z, hdot[3] = fO.f.x, hdot[4] = fO.f.y, hdot[5] = fO.f.z;
}

// ∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈ (6, nv) row-major each, into out; `mass` > 0.
inline void centroidal_dynamics_derivatives(const ModelView& mv, const double* q, const double* qd,
                                            const double* qdd, double mass, double* const* out) {
  const int nv = mv.nv;
  dual_directions(
      mv, q, qd, qdd, 3, 12,
      [&](const DualK* Q, const DualK* V, const DualK* A, DualK* T) {
        centroidal_momentum_rate(mv, Q, V, A, mass, T, T + 6);
      },
      [&](int block, int col, int l, const DualK* T) {
        for (int r = 0; r < 6; ++r) {
          if (block == 0) out[0][r * nv + col] = T[r].d[l];
          out[1 + block][r * nv + col] = T[6 + r].d[l];
        }
      });
}

}  // namespace fdcore
