// Derivatives of a frame's motion, of the centre of mass and of the centroidal momentum and its rate
// (reference: featherdyn/algorithms/kinematics_derivatives.py, the same formulas line for line; equations in
// docs/derivatives.md; Pinocchio's computeForwardKinematicsDerivatives + get{Frame,Point}*Derivatives,
// jacobianCenterOfMass, getCenterOfMassVelocityDerivatives, computeCentroidalDynamicsDerivatives).
//
// Every quantity in world coordinates at the world origin: s = ⁰S_j the column of dof j (joint k), v_i, a_i
// the bodies' velocities and accelerations (no gravity), I_i their inertias. Moving dof j along the tangent of
// fd.integrate moves k's subtree by exp(ε s); with u = v_λ(k), w = a_λ(k) (zero at a root), z = s × u:
//
//     frame of body b:  ∂v_b/∂q_j = s × (v_b − u),   ∂v_b/∂q̇_j = ∂a_b/∂q̈_j = s,   ∂a_b/∂q̇_j = v_k × s + s × (v_b − u)
//                       ∂a_b/∂q_j = Σ_{i ⪰ k on b's support} s × aJ_i + (s × (v_i − u)) × vJ_i + v_i × (s × vJ_i)
//                       (vJ_i = Σ S q̇, aJ_i = Σ S q̈ over i's own dofs), then the reference and the point;
//     composites:       ∂h_O/∂q_j = s ×* h^C − I^C z,   ∂c/∂q_j = lin(I^C s)/m,   ∂ċ/∂q_j = lin(∂h_O/∂q_j)/m
//                       ∂ḣ_O/∂q_j = s ×* F^C − I^C (s × w) + I^C (z × u) − İ^C z − z ×* h^C
//                       ∂ḣ_O/∂q̇_j = I^C (v_k × s + u × s) + İ^C s + s ×* h^C,   ∂ḣ_O/∂q̈_j = I^C s
//                       about c: [∂k − c × ∂p − ∂c × p; ∂p]
//
// O(nv · depth) for a frame, O(nb + nv) for the composites.
#pragma once

#include <algorithm>
#include <vector>

#include "frames.hpp"
#include "kinematics.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// The world pass's values: placements, columns, velocities and accelerations, their joint parts, and the
// subtree composites (world inertia, momentum, force, inertia rate).
struct WorldPassWork {
  std::vector<Mat3<double>> oR;
  std::vector<Vec3<double>> op;
  std::vector<Motion<double>> W, v, a, vJ, aJ;
  std::vector<RigidInertia<double>> IC;
  std::vector<Force<double>> hC, FC;
  std::vector<ArticulatedInertia<double>> BC;  // İ^C: symmetric, stored as [[A, B], [Bᵀ, C]]
  std::vector<int> path;
  void resize(size_t nb) {
    if (oR.size() < nb) {
      oR.resize(nb), op.resize(nb), v.resize(nb), a.resize(nb), vJ.resize(nb), aJ.resize(nb), IC.resize(nb);
      hC.resize(nb), FC.resize(nb), BC.resize(nb), path.resize(nb);
    }
  }
};

// a − b for motions, and entry r of a 3-vector (the spatial types' operators: spatial.hpp)
inline Motion<double> motion_sub(const Motion<double>& a, const Motion<double>& b) {
  return {a.w - b.w, a.v - b.v};
}
inline double vec_entry(const Vec3<double>& a, int r) { return r == 0 ? a.x : r == 1 ? a.y : a.z; }

// Body i's world placement, columns ⁰S (into W at its dofs), velocity and acceleration (its parent's done).
inline void world_pass_body(const ModelView& mv, int i, const double* q, const double* qd, const double* qdd,
                            WorldPassWork& w) {
  Mat3<double> R;
  Vec3<double> p;
  place_body(mv, i, q, w.oR.data(), w.op.data(), R, p);
  const Motion<double> zero{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  Motion<double> vJ = zero, aJ = zero;
  for (int c = 0; c < mv.nv_i[i]; ++c) {
    const int j = mv.idx_v[i] + c;
    const Motion<double> s = S_col<double>(mv, i, c);
    const Vec3<double> sw = w.oR[i] * s.w;
    const Motion<double> col{sw, w.oR[i] * s.v + cross(w.op[i], sw)};
    w.W[j] = col;
    vJ = vJ + Motion<double>{qd[j] * col.w, qd[j] * col.v};
    if (qdd) aJ = aJ + Motion<double>{qdd[j] * col.w, qdd[j] * col.v};
  }
  const int lam = mv.parent[i];
  w.vJ[i] = vJ, w.aJ[i] = aJ;
  w.v[i] = lam == -1 ? vJ : w.v[lam] + vJ;
  w.a[i] = (lam == -1 ? aJ : w.a[lam] + aJ) + cross_motion(w.v[i], vJ);
}

// İ = v ×* I − I v× (6 × 6, symmetric) of a world inertia I moving with velocity v.
inline ArticulatedInertia<double> rate_of_inertia(const RigidInertia<double>& I, const Motion<double>& v) {
  ArticulatedInertia<double> r;
  for (int k = 0; k < 6; ++k) {
    auto unit = [&](int at) { return Vec3<double>{at == 0 ? 1.0 : 0.0, at == 1 ? 1.0 : 0.0, at == 2 ? 1.0 : 0.0}; };
    const Motion<double> e{unit(k), unit(k - 3)};  // e_k
    const Force<double> col = cross_force(v, I * e) - I * cross_motion(v, e);
    for (int row = 0; row < 3; ++row) {
      if (k < 3) r.A(row, k) = vec_entry(col.n, row), r.B(k, row) = vec_entry(col.f, row);  // (bottom-left = Bᵀ)
      else r.B(row, k - 3) = vec_entry(col.n, row), r.C(row, k - 3) = vec_entry(col.f, row);
    }
  }
  return r;
}

// A frame's (moved to `point` in its coordinates, or nullptr) motion derivatives in `ref`, (6, nv) row-major
// each, into out: ∂v/∂q, ∂v/∂q̇, ∂a/∂q, ∂a/∂q̇, ∂a^c/∂q, ∂a^c/∂q̇ (a^c = [ω̇; a_lin + ω × v_lin] in `ref`;
// ∂a/∂q̈ = ∂a^c/∂q̈ = ∂v/∂q̇).
inline void kinematics_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                                   int frame, const double* point, int ref, double* const* out) {
  const int nv = mv.nv;
  for (int o = 0; o < 6; ++o) std::fill(out[o], out[o] + 6 * nv, 0.0);
  const int body = mv.frame_body[frame];
  if (body == -1) return;  // a frame fixed to the world does not move
  WorldPassWork& w = thread_workspace<WorldPassWork>(mv.nb);
  w.W.resize(static_cast<size_t>(nv));
  int n = 0;
  for (int j = body; j != -1; j = mv.parent[j]) w.path[n++] = j;
  std::reverse(w.path.begin(), w.path.begin() + n);  // root first
  for (int s = 0; s < n; ++s) world_pass_body(mv, w.path[s], q, qd, qdd, w);
  const Motion<double> vb = w.v[body], ab = w.a[body];
  // the frame (at the point): ⁰M_f = ⁰M_b · placement (· translation), and ᶠX_0 its inverse as a motion transform
  const Mat3<double> Rfb = load9<double>(mv.frame_R + 9 * frame);
  Vec3<double> pfb = load3<double>(mv.frame_p + 3 * frame);
  if (point) pfb = pfb + Rfb * load3<double>(point);
  const Mat3<double> Rf = w.oR[body] * Rfb;
  const Xform<double> fX0{Rf.transpose(), w.op[body] + w.oR[body] * pfb};
  // a world value y and derivative dy of column s, in the reference: (value, derivative)
  auto express = [&](const Motion<double>& y, const Motion<double>* dy, const Motion<double>& s) -> Motion<double> {
    if (ref == WORLD) return dy ? *dy : y;
    const Motion<double> yf = fX0.apply(y);
    if (!dy) return ref == LOCAL ? yf : Motion<double>{Rf * yf.w, Rf * yf.v};
    const Motion<double> sf = fX0.apply(s);
    const Motion<double> d = motion_sub(fX0.apply(*dy), cross_motion(sf, yf));
    if (ref == LOCAL) return d;
    return {Rf * (d.w + cross(sf.w, yf.w)), Rf * (d.v + cross(sf.w, yf.v))};
  };
  const Motion<double> none{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  const Motion<double> vr = express(vb, nullptr, none);
  auto put = [&](double* m, int col, const Motion<double>& x) {
    m[0 * nv + col] = x.w.x, m[1 * nv + col] = x.w.y, m[2 * nv + col] = x.w.z;
    m[3 * nv + col] = x.v.x, m[4 * nv + col] = x.v.y, m[5 * nv + col] = x.v.z;
  };
  auto classical = [&](const Motion<double>& da, const Motion<double>& dv) {  // ∂a + [0; ∂ω × v + ω × ∂v]
    return Motion<double>{da.w, da.v + cross(dv.w, vr.v) + cross(vr.w, dv.v)};
  };
  for (int pos = 0; pos < n; ++pos) {
    const int k = w.path[pos];
    const Motion<double> u = pos > 0 ? w.v[w.path[pos - 1]] : none;
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const int j = mv.idx_v[k] + c;
      const Motion<double> s = w.W[j];
      const Motion<double> dvq = cross_motion(s, motion_sub(vb, u));
      Motion<double> daq = none;
      for (int t = pos; t < n; ++t) {
        const int i = w.path[t];
        daq = daq + cross_motion(s, w.aJ[i]) + cross_motion(cross_motion(s, motion_sub(w.v[i], u)), w.vJ[i]) +
              cross_motion(w.v[i], cross_motion(s, w.vJ[i]));
      }
      const Motion<double> dav = cross_motion(w.v[k], s) + cross_motion(s, motion_sub(vb, u));
      // ∂/∂q moves the frame (express with the column); ∂/∂q̇ does not (a plain change of coordinates)
      const Motion<double> Dvq = express(vb, &dvq, s), Daq = express(ab, &daq, s);
      const Motion<double> Dvv = express(s, nullptr, none), Dav = express(dav, nullptr, none);
      put(out[0], j, Dvq);
      put(out[1], j, Dvv);
      put(out[2], j, Daq);
      put(out[3], j, Dav);
      put(out[4], j, classical(Daq, Dvq));
      put(out[5], j, classical(Dav, Dvv));
    }
  }
}

// The world pass over every body and the composites I^C, h^C, F^C, İ^C (qdd nullptr: F^C, İ^C not needed).
inline WorldPassWork& world_composites(const ModelView& mv, const double* q, const double* qd, const double* qdd) {
  WorldPassWork& w = thread_workspace<WorldPassWork>(mv.nb);
  w.W.resize(static_cast<size_t>(mv.nv));
  for (int i = 0; i < mv.nb; ++i) {
    world_pass_body(mv, i, q, qd, qdd, w);
    const RigidInertia<double> I = transform_to_parent(Xform<double>{w.oR[i].transpose(), w.op[i]},
                                                       body_inertia<double>(mv, i));
    w.IC[i] = I;
    w.hC[i] = I * w.v[i];
    if (qdd) {
      w.FC[i] = I * w.a[i] + cross_force(w.v[i], w.hC[i]);
      w.BC[i] = rate_of_inertia(I, w.v[i]);
    }
  }
  for (int i = mv.nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    if (lam == -1) continue;
    w.IC[lam] = w.IC[lam] + w.IC[i];
    w.hC[lam] += w.hC[i];
    if (qdd) w.FC[lam] += w.FC[i], w.BC[lam] += w.BC[i];
  }
  return w;
}

// ∂c/∂q and ∂ċ/∂q (3, nv) row-major; `mass` the tree's total mass (> 0).
inline void center_of_mass_derivatives(const ModelView& mv, const double* q, const double* qd, double mass,
                                       double* dc_dq, double* dcd_dq) {
  const int nv = mv.nv;
  WorldPassWork& w = world_composites(mv, q, qd, nullptr);
  const Motion<double> none{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  for (int k = 0; k < mv.nb; ++k) {
    const int lam = mv.parent[k];
    const Motion<double> u = lam == -1 ? none : w.v[lam];
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const int j = mv.idx_v[k] + c;
      const Motion<double> s = w.W[j];
      const Force<double> Is = w.IC[k] * s;
      const Force<double> dh = cross_force(s, w.hC[k]) - w.IC[k] * cross_motion(s, u);
      for (int r = 0; r < 3; ++r) dc_dq[r * nv + j] = vec_entry(Is.f, r) / mass, dcd_dq[r * nv + j] = vec_entry(dh.f, r) / mass;
    }
  }
}

// ∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈ (6, nv) row-major each, rows [k; p] about the centre of mass in world
// axes, into out; `mass` > 0.
inline void centroidal_dynamics_derivatives(const ModelView& mv, const double* q, const double* qd,
                                            const double* qdd, double mass, double* const* out) {
  const int nv = mv.nv;
  WorldPassWork& w = world_composites(mv, q, qd, qdd);
  Vec3<double> mc{0.0, 0.0, 0.0}, p{0.0, 0.0, 0.0}, pd{0.0, 0.0, 0.0};
  for (int i = 0; i < mv.nb; ++i) {
    if (mv.parent[i] != -1) continue;
    mc = mc + w.IC[i].h, p = p + w.hC[i].f, pd = pd + w.FC[i].f;
  }
  const Vec3<double> c = (1.0 / mass) * mc;
  const Motion<double> none{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  auto put = [&](double* m, int col, const Force<double>& d, const Vec3<double>& dc, const Vec3<double>& pv) {
    const Vec3<double> k = d.n - cross(c, d.f) - cross(dc, pv);
    m[0 * nv + col] = k.x, m[1 * nv + col] = k.y, m[2 * nv + col] = k.z;
    m[3 * nv + col] = d.f.x, m[4 * nv + col] = d.f.y, m[5 * nv + col] = d.f.z;
  };
  const Vec3<double> zero{0.0, 0.0, 0.0};
  for (int k = 0; k < mv.nb; ++k) {
    const int lam = mv.parent[k];
    const Motion<double> u = lam == -1 ? none : w.v[lam], a_lam = lam == -1 ? none : w.a[lam];
    const RigidInertia<double>& IC = w.IC[k];
    for (int col = 0; col < mv.nv_i[k]; ++col) {
      const int j = mv.idx_v[k] + col;
      const Motion<double> s = w.W[j], z = cross_motion(s, u);
      const Force<double> Is = IC * s;
      const Vec3<double> dc = (1.0 / mass) * Is.f;
      const Force<double> dh = cross_force(s, w.hC[k]) - IC * z;
      const Force<double> dhd_q = cross_force(s, w.FC[k]) - IC * cross_motion(s, a_lam) + IC * cross_motion(z, u) -
                                  w.BC[k] * z - cross_force(z, w.hC[k]);
      const Force<double> dhd_v =
          IC * (cross_motion(w.v[k], s) + cross_motion(u, s)) + w.BC[k] * s + cross_force(s, w.hC[k]);
      put(out[0], j, dh, dc, p);
      put(out[1], j, dhd_q, dc, pd);
      put(out[2], j, dhd_v, zero, pd);
      put(out[3], j, Is, zero, pd);
    }
  }
}

}  // namespace fdcore
