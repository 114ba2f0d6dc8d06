// Frame placement and frame Jacobian (reference: featherdyn/algorithms/kinematics.py and
// jacobians.py; RBDA §4.5). Only the support of the frame's body is walked:
//
//     ⁰M_f = ⁰M_body(f) · placement_f
//     ⁰J[:, k] = ⁰X_k S_k      for every joint k from the root to body(f)
//     LOCAL: ᶠX_0 ⁰J      LOCAL_WORLD_ALIGNED: [ω; v − p_f × ω] of each WORLD column
#pragma once

#include "joints.hpp"
#include "scratch.hpp"

namespace fdcore {

enum Reference : int { LOCAL = 0, WORLD = 1, LOCAL_WORLD_ALIGNED = 2 };

template <class S>
struct SupportWork {
  std::vector<int> path;
  std::vector<Mat3<S>> oR;
  std::vector<Vec3<S>> op;
  void resize(size_t nb) {
    if (path.size() < nb) path.resize(nb), oR.resize(nb), op.resize(nb);
  }
};

// The world placements of the bodies from the root to `body` (w.path[0 .. n), root first); returns n.
template <class S>
inline int support_placements(const ModelView& mv, int body, const S* q, SupportWork<S>& w) {
  int n = 0;
  for (int j = body; j != -1; j = mv.parent[j]) ++n;
  int m = n;
  for (int j = body; j != -1; j = mv.parent[j]) w.path[--m] = j;
  // the poses in the parents first (independent: sin, cos), then composed in place (as in rnea.hpp)
  for (int s = 0; s < n; ++s) pose_in_parent(mv, w.path[s], q, w.oR[s], w.op[s]);
  // the running pose carried in registers: stored, it would be read back at once by the next product in other
  // widths than written (a store-forwarding stall per body, 11 % of a panda frame_placement)
  if (n == 0) return 0;
  Mat3<S> R = w.oR[0];
  Vec3<S> p = w.op[0];
  for (int s = 1; s < n; ++s) {
    p = p + R * w.op[s];
    R = R * w.oR[s];
    w.op[s] = p;
    w.oR[s] = R;
  }
  return n;
}

// A frame's world pose: its axes R (columns in world coordinates) and its origin p (kinematics_derivatives'
// optional output, what frame_pose forms).
template <class S>
struct Pose {
  Mat3<S> R;
  Vec3<S> p;
};

// ⁰M_f = (R, p): its rotation R (3, 3) row-major and translation p (3,).
template <class S>
void frame_pose(const ModelView& mv, const S* q, int frame, Mat3<S>& R, Vec3<S>& p) {
  SupportWork<S>& w = thread_workspace<SupportWork<S>>(mv.nb);
  const int body = mv.frame_body[frame];
  R = load9<S>(mv.frame_R + 9 * frame);
  p = load3<S>(mv.frame_p + 3 * frame);
  const int n = support_placements(mv, body, q, w);
  if (n > 0) {
    p = w.op[n - 1] + w.oR[n - 1] * p;
    R = w.oR[n - 1] * R;
  }
}

// A frame's spatial velocity, spatial acceleration (no gravity) and classical acceleration, each (6,) rows [ω; v] in
// `ref` (reference: featherdyn/algorithms/kinematics.py, frame_velocity & co.): its body's motion by kinematics.hpp's
// recursion on the support only (root → body(f)), then moved to the frame (ᶠM_b = placement_f⁻¹):
//
//     LOCAL: ᶠv = [Rᵀ ω_b; Rᵀ (v_b + ω_b × p)]      LOCAL_WORLD_ALIGNED: [⁰R_f ω; ⁰R_f v] of LOCAL's
//     WORLD: ⁰X_f ᶠv = [ω; v + ⁰p_f × ω] of LOCAL_WORLD_ALIGNED's        (the same for the acceleration)
//     classical: [ω̇; a_lin + ω × v_lin], ω and v the frame's in the same reference
//
// vel, acc, acc_classical: any may be nullptr (qdd is read only for the accelerations). A frame on the world
// (body −1) does not move.
template <class S>
void frame_motion(const ModelView& mv, const S* q, const S* qd, const S* qdd, int frame, int ref, S* vel, S* acc,
                  S* acc_classical) {
  SupportWork<S>& w = thread_workspace<SupportWork<S>>(mv.nb);
  const bool accelerations = acc != nullptr || acc_classical != nullptr;
  int n = 0;
  for (int j = mv.frame_body[frame]; j != -1; j = mv.parent[j]) ++n;
  for (int j = mv.frame_body[frame], m = n; j != -1; j = mv.parent[j]) w.path[--m] = j;
  const S z(0.0);
  Motion<S> v{{z, z, z}, {z, z, z}}, a = v;
  Mat3<S> R0 = Mat3<S>::identity();  // ⁰R_b, ⁰p_b of the body reached so far
  Vec3<S> p0{z, z, z};
  for (int s = 0; s < n; ++s) {
    const int i = w.path[s];
    Mat3<S> R;
    Vec3<S> p;
    pose_in_parent(mv, i, q, R, p);
    const Xform<S> X_up{R.transpose(), p};
    const Motion<S> vJ = S_times(mv, i, qd);
    v = s == 0 ? vJ : X_up.apply(v) + vJ;
    if (accelerations) {
      const Motion<S> aJ = S_times(mv, i, qdd) + cross_motion(v, vJ);
      a = s == 0 ? aJ : X_up.apply(a) + aJ;
    }
    p0 = p0 + R0 * p;
    R0 = R0 * R;
  }
  const Mat3<S> Rf = load9<S>(mv.frame_R + 9 * frame);
  const Vec3<S> pf = load3<S>(mv.frame_p + 3 * frame);
  const Mat3<S> R0f = R0 * Rf;
  const Vec3<S> p0f = p0 + R0 * pf;
  auto express = [&](const Motion<S>& m) {  // the body's motion at the frame, in `ref`
    const Motion<S> local{Rf.transpose() * m.w, Rf.transpose() * (m.v + cross(m.w, pf))};
    if (ref == LOCAL) return local;
    const Motion<S> aligned{R0f * local.w, R0f * local.v};
    return ref == LOCAL_WORLD_ALIGNED ? aligned : Motion<S>{aligned.w, aligned.v + cross(p0f, aligned.w)};
  };
  auto store = [](const Motion<S>& m, S* out) {
    out[0] = m.w.x, out[1] = m.w.y, out[2] = m.w.z, out[3] = m.v.x, out[4] = m.v.y, out[5] = m.v.z;
  };
  const Motion<S> vf = express(v);
  if (vel) store(vf, vel);
  if (!accelerations) return;
  const Motion<S> af = express(a);
  if (acc) store(af, acc);
  if (acc_classical) store(Motion<S>{af.w, af.v + cross(vf.w, vf.v)}, acc_classical);
}

// ⁰M_f as a homogeneous matrix H (4, 4), row-major.
template <class S>
void frame_placement(const ModelView& mv, const S* q, int frame, S* H) {
  Mat3<S> R;
  Vec3<S> p;
  frame_pose(mv, q, frame, R, p);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) H[4 * r + c] = R(r, c);
  }
  H[3] = p.x, H[7] = p.y, H[11] = p.z;
  H[12] = H[13] = H[14] = S(0.0);
  H[15] = S(1.0);
}

// The columns of joint k (world pose R, p) in the Jacobian J (6, nv) of a frame at (Rf, ·): ⁰X_k S_k about
// `origin` (the world origin for WORLD, the frame's origin otherwise), in world axes, frame axes for LOCAL.
template <class S>
FD_INLINE void put_frame_columns(const ModelView& mv, int k, const Mat3<S>& R, const Vec3<S>& p, const Vec3<S>& origin,
                              const Mat3<S>& Rf, int ref, S* J) {
  const int nv = mv.nv;
  const Vec3<S> d = p - origin;
  const S z(0.0);
  const int jt = mv.jtype[k];
  for (int c = 0; c < mv.nv_i[k]; ++c) {
    // ω = R S_ω, v = R S_v + d × ω; S's columns are unit vectors or an axis with a zero half, whose products
    // are written out (a free flyer's six columns are R's columns: no matrix-vector products of zeros). d × ω
    // stays where ω = 0: with an overflowed d it is NaN, as in the reference, which then names the overflow.
    Vec3<S> om, vel;
    if (jt == REVOLUTE) {
      om = R * load3<S>(mv.axis + 3 * k);
      vel = cross(d, om);
    } else if (jt == PRISMATIC) {
      om = {z, z, z};
      vel = R * load3<S>(mv.axis + 3 * k) + cross(d, om);
    } else if (jt == SPHERICAL || jt == FREE_FLYER) {
      const int e = c % 3;
      const Vec3<S> Re{R(0, e), R(1, e), R(2, e)};
      om = c < 3 ? Re : Vec3<S>{z, z, z};
      vel = c < 3 ? cross(d, om) : Re + cross(d, om);
    } else {
      const Motion<S> Sc = S_col<S>(mv, k, c);
      om = R * Sc.w;
      vel = R * Sc.v + cross(d, om);
    }
    if (ref == LOCAL) {
      om = mul_transpose(Rf, om);
      vel = mul_transpose(Rf, vel);
    }
    const int col = mv.idx_v[k] + c;
    J[0 * nv + col] = om.x, J[1 * nv + col] = om.y, J[2 * nv + col] = om.z;
    J[3 * nv + col] = vel.x, J[4 * nv + col] = vel.y, J[5 * nv + col] = vel.z;
  }
}

// J (6, nv) row-major, rows [ω; v], in the reference frame `ref`.
template <class S>
void frame_jacobian(const ModelView& mv, const S* q, int frame, int ref, S* J) {
  SupportWork<S>& w = thread_workspace<SupportWork<S>>(mv.nb);
  const int nv = mv.nv;
  for (int k = 0; k < 6 * nv; ++k) J[k] = S(0.0);
  const int body = mv.frame_body[frame];
  const int n = support_placements(mv, body, q, w);
  if (n == 0) return;  // a frame fixed to the world does not move
  const Mat3<S> Rf = w.oR[n - 1] * load9<S>(mv.frame_R + 9 * frame);
  const Vec3<S> pf = w.op[n - 1] + w.oR[n - 1] * load3<S>(mv.frame_p + 3 * frame);
  const S z(0.0);
  const Vec3<S> origin = ref == WORLD ? Vec3<S>{z, z, z} : pf;
  for (int s = 0; s < n; ++s) put_frame_columns(mv, w.path[s], w.oR[s], w.op[s], origin, Rf, ref, J);
}

}  // namespace fdcore
