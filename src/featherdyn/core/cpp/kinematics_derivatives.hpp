// Derivatives of a frame's motion, of the centre of mass and of the centroidal momentum and its rate
// (reference: featherdyn/algorithms/kinematics_derivatives.py, the same formulas but for two, which it forms the
// long way: ∂a_b/∂q_j as the sum below and İ by 6 × 6 products; equations in docs/derivatives.md; Pinocchio's
// computeForwardKinematicsDerivatives + get{Frame,Point}*Derivatives, jacobianCenterOfMass,
// getCenterOfMassVelocityDerivatives, computeCentroidalDynamicsDerivatives).
//
// Every quantity in world coordinates at the world origin: s = ⁰S_j the column of dof j (joint k), v_i, a_i
// the bodies' velocities and accelerations (no gravity), I_i their inertias. Moving dof j along the tangent of
// fd.integrate moves k's subtree by exp(ε s); with u = v_λ(k), w = a_λ(k) (zero at a root), z = s × u:
//
//     frame of body b:  ∂v_b/∂q_j = s × (v_b − u),   ∂v_b/∂q̇_j = ∂a_b/∂q̈_j = s,   ∂a_b/∂q̇_j = v_k × s + s × (v_b − u)
//                       ∂a_b/∂q_j = Σ_{i ⪰ k on b's support} s × aJ_i + (s × (v_i − u)) × vJ_i + v_i × (s × vJ_i)
//                                 = s × (a_b − w) − (s × u) × (v_b − u)      (the sum telescoped: the kernel's form)
//                       (vJ_i = Σ S q̇, aJ_i = Σ S q̈ over i's own dofs), then the reference and the point;
//     composites:       ∂h_O/∂q_j = s ×* h^C − I^C z,   ∂c/∂q_j = lin(I^C s)/m,   ∂ċ/∂q_j = lin(∂h_O/∂q_j)/m
//                       ∂ḣ_O/∂q_j = s ×* F^C − I^C (s × w) + I^C (z × u) − İ^C z − z ×* h^C
//                       ∂ḣ_O/∂q̇_j = I^C (v_k × s + u × s) + İ^C s + s ×* h^C,   ∂ḣ_O/∂q̈_j = I^C s
//                       about c: [∂k − c × ∂p − ∂c × p; ∂p]
//
// O(depth) for a frame (its support's pass, then O(1) a column), O(nb + nv) for the composites.
#pragma once

#include <algorithm>
#include <vector>

#include "frames.hpp"
#include "kinematics.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// İ = v ×* I − I v× of a world inertia I = (m, h, Ī) moving with v = [ω; v_O]: with v× = [[ω×, 0], [v_O×, ω×]] and
// v×* = [[ω×, v_O×], [0, ω×]], İ = [[Ā, [ḣ]×], [[ḣ]×ᵀ, 0]] (m does not change), where
//     ḣ = ω × h + m v_O,   Ā = ω×Ī − Īω× − v_O×h× − h×v_O× = (ω×Ī) + (ω×Ī)ᵀ − (h v_Oᵀ + v_O hᵀ) + 2 (h·v_O) 1
// ([a]×[b]× = b aᵀ − (a·b) 1). Sums of them (the subtrees' İ^C) keep the form.
template <class T>
struct InertiaRate {
  Sym3<T> A;
  Vec3<T> hd;
  // İ z = [Ā z_ω + ḣ × z_v;  z_ω × ḣ]
  Force<T> operator*(const Motion<T>& z) const { return {A * z.w + cross(hd, z.v), cross(z.w, hd)}; }
  InertiaRate& operator+=(const InertiaRate& o) {
    A = A + o.A;
    hd += o.hd;
    return *this;
  }
};

// The world pass's values: placements, columns, velocities and accelerations, and the subtree
// composites (world inertia, momentum, force, inertia rate).
template <class T>
struct WorldPassWork {
  std::vector<Mat3<T>> oR;
  std::vector<Vec3<T>> op;
  std::vector<Motion<T>> W, v, a;
  std::vector<RigidInertia<T>> IC;
  std::vector<Force<T>> hC, FC;
  std::vector<InertiaRate<T>> BC;  // İ^C
  std::vector<int> path;
  void resize(size_t nb) {
    if (oR.size() < nb) {
      oR.resize(nb), op.resize(nb), v.resize(nb), a.resize(nb), IC.resize(nb);
      hC.resize(nb), FC.resize(nb), BC.resize(nb), path.resize(nb);
    }
  }
};

// a − b for motions, and entry r of a 3-vector (the spatial types' operators: spatial.hpp)
template <class T>
inline Motion<T> motion_sub(const Motion<T>& a, const Motion<T>& b) {
  return {a.w - b.w, a.v - b.v};
}
template <class T>
inline T vec_entry(const Vec3<T>& a, int r) { return r == 0 ? a.x : r == 1 ? a.y : a.z; }

// Body i's world placement and columns ⁰S (into W at its dofs), its parent's placed.
template <class T>
inline void world_place_body(const ModelView& mv, int i, const T* q, WorldPassWork<T>& w) {
  Mat3<T> R;
  Vec3<T> p;
  place_body(mv, i, q, w.oR.data(), w.op.data(), R, p);
  for (int c = 0; c < mv.nv_i[i]; ++c) {
    const Motion<T> s = S_col<T>(mv, i, c);
    const Vec3<T> sw = w.oR[i] * s.w;
    w.W[mv.idx_v[i] + c] = Motion<T>{sw, w.oR[i] * s.v + cross(w.op[i], sw)};
  }
}

// Body i's world velocity and acceleration (qdd nullptr: no q̈ term) from its columns, its parent's moved.
template <class T>
inline void world_move_body(const ModelView& mv, int i, const T* qd, const T* qdd, WorldPassWork<T>& w) {
  const Motion<T> zero{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  Motion<T> vJ = zero, aJ = zero;
  for (int c = 0; c < mv.nv_i[i]; ++c) {
    const int j = mv.idx_v[i] + c;
    const Motion<T>& col = w.W[j];
    vJ = vJ + Motion<T>{qd[j] * col.w, qd[j] * col.v};
    if (qdd) aJ = aJ + Motion<T>{qdd[j] * col.w, qdd[j] * col.v};
  }
  const int lam = mv.parent[i];
  w.v[i] = lam == -1 ? vJ : w.v[lam] + vJ;
  w.a[i] = (lam == -1 ? aJ : w.a[lam] + aJ) + cross_motion(w.v[i], vJ);
}

// Body i's placement, columns, velocity and acceleration (its parent's done).
template <class T>
inline void world_pass_body(const ModelView& mv, int i, const T* q, const T* qd, const T* qdd, WorldPassWork<T>& w) {
  world_place_body(mv, i, q, w);
  world_move_body(mv, i, qd, qdd, w);
}

// The bodies from the root to `body` (−1: none) into path, root first; returns how many.
inline int support_path(const ModelView& mv, int body, int* path) {
  int n = 0;
  for (int j = body; j != -1; j = mv.parent[j]) path[n++] = j;
  std::reverse(path, path + n);
  return n;
}

template <class T>
inline InertiaRate<T> rate_of_inertia(const RigidInertia<T>& I, const Motion<T>& v) {
  const Mat3<T> Ib = I.I.full();
  Mat3<T> wI;  // ω×Ī, column by column
  for (int c = 0; c < 3; ++c) {
    const Vec3<T> col = cross(v.w, Vec3<T>{Ib(0, c), Ib(1, c), Ib(2, c)});
    wI(0, c) = col.x, wI(1, c) = col.y, wI(2, c) = col.z;
  }
  const T h[3] = {I.h.x, I.h.y, I.h.z}, u[3] = {v.v.x, v.v.y, v.v.z};
  const T diag = T(2.0) * dot(I.h, v.v);
  auto entry = [&](int a, int b) {
    const T x = wI(a, b) + wI(b, a) - (h[a] * u[b] + u[a] * h[b]);
    return a == b ? x + diag : x;
  };
  return {{entry(0, 0), entry(0, 1), entry(0, 2), entry(1, 1), entry(1, 2), entry(2, 2)}, cross(v.w, I.h) + I.m * v.v};
}

// kinematics_derivatives' outputs from a world pass already in w over the frame's support: the placements and
// columns, and the velocities and accelerations unless ∂v/∂q̇ is the only output (then they are not read).
template <class T>
inline void frame_motion_derivatives(const ModelView& mv, int frame, const double* point, int ref, T* const* out,
                                     Pose<T>* pose, WorldPassWork<T>& w) {
  const int nv = mv.nv;
  for (int o = 0; o < 6; ++o)
    if (out[o]) std::fill(out[o], out[o] + 6 * nv, T(0.0));
  const int body = mv.frame_body[frame];
  if (body == -1) {  // a frame fixed to the world does not move
    if (pose) {
      pose->R = load9<T>(mv.frame_R + 9 * frame), pose->p = load3<T>(mv.frame_p + 3 * frame);
      if (point) pose->p = pose->p + pose->R * load3<T>(point);
    }
    return;
  }
  const int n = support_path(mv, body, w.path.data());
  const bool moving = out[0] || out[2] || out[3] || out[4] || out[5];
  const Motion<T> none{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  const Motion<T> vb = moving ? w.v[body] : none, ab = moving ? w.a[body] : none;
  // the frame (at the point): ⁰M_f = ⁰M_b · placement (· translation), and ᶠX_0 its inverse as a motion transform
  const Mat3<T> Rfb = load9<T>(mv.frame_R + 9 * frame);
  Vec3<T> pfb = load3<T>(mv.frame_p + 3 * frame);
  if (point) pfb = pfb + Rfb * load3<T>(point);
  const Mat3<T> Rf = w.oR[body] * Rfb;
  const Xform<T> fX0{Rf.transpose(), w.op[body] + w.oR[body] * pfb};
  if (pose) pose->R = Rf, pose->p = fX0.r;
  // In the frame's coordinates (LOCAL's; in WORLD the world's own): a value x as x_f = ᶠX₀ x, and the derivative of
  // a world value y along column s as ᶠX₀ ∂y − s_f × y_f (the frame moves with s); then in the reference. The body's
  // velocity and acceleration are moved once, each column once.
  const bool world = ref == WORLD;
  auto local = [&](const Motion<T>& x) { return world ? x : fX0.apply(x); };
  auto in_ref = [&](const Motion<T>& xf) {  // a value
    return world || ref == LOCAL ? xf : Motion<T>{Rf * xf.w, Rf * xf.v};
  };
  auto moved = [&](const Motion<T>& dyf, const Motion<T>& yf, const Motion<T>& sf) -> Motion<T> {  // a derivative
    if (world) return dyf;
    const Motion<T> d = motion_sub(dyf, cross_motion(sf, yf));
    if (ref == LOCAL) return d;
    return {Rf * (d.w + cross(sf.w, yf.w)), Rf * (d.v + cross(sf.w, yf.v))};
  };
  const Motion<T> vf = local(vb), af = local(ab), vr = in_ref(vf);
  auto put = [&](T* m, int col, const Motion<T>& x) {
    m[0 * nv + col] = x.w.x, m[1 * nv + col] = x.w.y, m[2 * nv + col] = x.w.z;
    m[3 * nv + col] = x.v.x, m[4 * nv + col] = x.v.y, m[5 * nv + col] = x.v.z;
  };
  auto classical = [&](const Motion<T>& da, const Motion<T>& dv) {  // ∂a + [0; ∂ω × v + ω × ∂v]
    return Motion<T>{da.w, da.v + cross(dv.w, vr.v) + cross(vr.w, dv.v)};
  };
  Motion<T> Dvq = none, Dvv = none, Daq = none, Dav = none;
  for (int pos = 0; pos < n; ++pos) {
    const int k = w.path[pos];
    const Motion<T> u = moving && pos > 0 ? w.v[w.path[pos - 1]] : none;
    const Motion<T> wk = moving && pos > 0 ? w.a[w.path[pos - 1]] : none;
    const Motion<T> vbu = motion_sub(vb, u);
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const int j = mv.idx_v[k] + c;
      const Motion<T> s = w.W[j], sf = local(s);
      // ∂/∂q moves the frame (`moved`, with the column); ∂/∂q̇ does not (a plain change of coordinates)
      if (out[0] || out[4]) Dvq = moved(local(cross_motion(s, vbu)), vf, sf);
      if (out[1] || out[5]) Dvv = in_ref(sf);
      if (out[2] || out[4]) {
        // the header's sum over i, telescoped (Jacobi: (s × v_i) × vJ_i + v_i × (s × vJ_i) = s × (v_i × vJ_i),
        // and a_i − a_λ(i) = aJ_i + v_i × vJ_i): ∂a_b/∂q_j = s × (a_b − a_λ(k)) − (s × u) × (v_b − u), O(1)
        const Motion<T> daq = motion_sub(cross_motion(s, motion_sub(ab, wk)), cross_motion(cross_motion(s, u), vbu));
        Daq = moved(local(daq), af, sf);
      }
      if (out[3] || out[5]) Dav = in_ref(local(cross_motion(w.v[k], s) + cross_motion(s, vbu)));
      if (out[0]) put(out[0], j, Dvq);
      if (out[1]) put(out[1], j, Dvv);
      if (out[2]) put(out[2], j, Daq);
      if (out[3]) put(out[3], j, Dav);
      if (out[4]) put(out[4], j, classical(Daq, Dvq));
      if (out[5]) put(out[5], j, classical(Dav, Dvv));
    }
  }
}

// A frame's (moved to `point` in its coordinates, or nullptr) motion derivatives in `ref`, (6, nv) row-major
// each, into out: ∂v/∂q, ∂v/∂q̇, ∂a/∂q, ∂a/∂q̇, ∂a^c/∂q, ∂a^c/∂q̇ (a^c = [ω̇; a_lin + ω × v_lin] in `ref`;
// ∂a/∂q̈ = ∂a^c/∂q̈ = ∂v/∂q̇). An output given as nullptr is not formed. With `pose`, the frame's (at the point's)
// world axes and origin there as well (frames.hpp's frame_pose, from the same pass).
template <class T>
inline void kinematics_derivatives(const ModelView& mv, const T* q, const T* qd, const T* qdd, int frame,
                                   const double* point, int ref, T* const* out, Pose<T>* pose = nullptr) {
  WorldPassWork<T>& w = thread_workspace<WorldPassWork<T>>(mv.nb);
  w.W.resize(static_cast<size_t>(mv.nv));
  const int n = support_path(mv, mv.frame_body[frame], w.path.data());
  for (int s = 0; s < n; ++s) world_pass_body(mv, w.path[s], q, qd, qdd, w);
  frame_motion_derivatives(mv, frame, point, ref, out, pose, w);
}

// The world pass over every body and the composites I^C, h^C, F^C, İ^C (qdd nullptr: F^C, İ^C not needed).
template <class T>
inline WorldPassWork<T>& world_composites(const ModelView& mv, const T* q, const T* qd, const T* qdd) {
  WorldPassWork<T>& w = thread_workspace<WorldPassWork<T>>(mv.nb);
  w.W.resize(static_cast<size_t>(mv.nv));
  for (int i = 0; i < mv.nb; ++i) {
    world_pass_body(mv, i, q, qd, qdd, w);
    const RigidInertia<T> I = transform_to_parent(Xform<T>{w.oR[i].transpose(), w.op[i]},
                                                       body_inertia<T>(mv, i));
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
template <class T>
inline void center_of_mass_derivatives(const ModelView& mv, const T* q, const T* qd, double mass, T* dc_dq,
                                       T* dcd_dq) {
  const int nv = mv.nv;
  WorldPassWork<T>& w = world_composites<T>(mv, q, qd, nullptr);
  const Motion<T> none{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  for (int k = 0; k < mv.nb; ++k) {
    const int lam = mv.parent[k];
    const Motion<T> u = lam == -1 ? none : w.v[lam];
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const int j = mv.idx_v[k] + c;
      const Motion<T> s = w.W[j];
      const Force<T> Is = w.IC[k] * s;
      const Force<T> dh = cross_force(s, w.hC[k]) - w.IC[k] * cross_motion(s, u);
      for (int r = 0; r < 3; ++r) dc_dq[r * nv + j] = vec_entry(Is.f, r) / T(mass), dcd_dq[r * nv + j] = vec_entry(dh.f, r) / T(mass);
    }
  }
}

// ∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈ (6, nv) row-major each, rows [k; p] about the centre of mass in world
// axes, into out; `mass` > 0.
template <class T>
inline void centroidal_dynamics_derivatives(const ModelView& mv, const T* q, const T* qd, const T* qdd, double mass,
                                            T* const* out) {
  const int nv = mv.nv;
  WorldPassWork<T>& w = world_composites(mv, q, qd, qdd);
  Vec3<T> mc{T(0.0), T(0.0), T(0.0)}, p{T(0.0), T(0.0), T(0.0)}, pd{T(0.0), T(0.0), T(0.0)};
  for (int i = 0; i < mv.nb; ++i) {
    if (mv.parent[i] != -1) continue;
    mc = mc + w.IC[i].h, p = p + w.hC[i].f, pd = pd + w.FC[i].f;
  }
  const Vec3<T> c = T(1.0 / mass) * mc;
  const Motion<T> none{{T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  auto put = [&](T* m, int col, const Force<T>& d, const Vec3<T>& dc, const Vec3<T>& pv) {
    const Vec3<T> k = d.n - cross(c, d.f) - cross(dc, pv);
    m[0 * nv + col] = k.x, m[1 * nv + col] = k.y, m[2 * nv + col] = k.z;
    m[3 * nv + col] = d.f.x, m[4 * nv + col] = d.f.y, m[5 * nv + col] = d.f.z;
  };
  const Vec3<T> zero{T(0.0), T(0.0), T(0.0)};
  for (int k = 0; k < mv.nb; ++k) {
    const int lam = mv.parent[k];
    const Motion<T> u = lam == -1 ? none : w.v[lam], a_lam = lam == -1 ? none : w.a[lam];
    const RigidInertia<T>& IC = w.IC[k];
    for (int col = 0; col < mv.nv_i[k]; ++col) {
      const int j = mv.idx_v[k] + col;
      const Motion<T> s = w.W[j], z = cross_motion(s, u);
      const Force<T> Is = IC * s;
      const Vec3<T> dc = T(1.0 / mass) * Is.f;
      const Force<T> dh = cross_force(s, w.hC[k]) - IC * z;
      const Force<T> dhd_q = cross_force(s, w.FC[k]) - IC * cross_motion(s, a_lam) + IC * cross_motion(z, u) -
                                  w.BC[k] * z - cross_force(z, w.hC[k]);
      const Force<T> dhd_v =
          IC * (cross_motion(w.v[k], s) + cross_motion(u, s)) + w.BC[k] * s + cross_force(s, w.hC[k]);
      put(out[0], j, dh, dc, p);
      put(out[1], j, dhd_q, dc, pd);
      put(out[2], j, dhd_v, zero, pd);
      put(out[3], j, Is, zero, pd);
    }
  }
}

}  // namespace fdcore
