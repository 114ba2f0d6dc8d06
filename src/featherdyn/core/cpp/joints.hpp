// The joint models (featherdyn/joints.py): the joint transform, the motion subspace S_i and
// its transpose, for each joint type. S is constant in successor coordinates for every type
// here, so c_J = Ṡ q̇ = 0 (RBDA table 4.1).
//
//   joint        q                       v                  pose(q) in the joint frame        S
//   revolute     θ                       θ̇                  (Rodrigues(a, θ), 0)              [a; 0]
//   prismatic    d                       ḋ                  (1, d a)                          [0; a]
//   spherical    quaternion (x, y, z, w) ω (child frame)     (R(quat), 0)                      [1; 0]
//   free-flyer   [p, quat]               [ω; v] (child)      (R(quat), p)                      1₆
//   planar       [x, y, θ]               [ω, vx, vy]         (Rodrigues(n, θ), x e1 + y e2)    [[n,0,0],[0,e1,e2]]
#pragma once

#include <cmath>

#include "model_view.hpp"
#include "trig.hpp"
#include "spatial.hpp"

namespace fdcore {

template <class S>
FD_INLINE Vec3<S> load3(const double* p) {
  return {S(p[0]), S(p[1]), S(p[2])};
}
template <class S>
FD_INLINE Mat3<S> load9(const double* p) {
  Mat3<S> R;
  for (int k = 0; k < 9; ++k) R.m[k] = S(p[k]);
  return R;
}

// Xtree_R · Rodrigues(a, θ) = Xtree_R + sin θ · Xtree_R [a]× + (1 − cos θ) · Xtree_R [a]×²  (revolute, planar)
template <class S>
FD_INLINE Mat3<S> rotate_about_axis(const ModelView& mv, int i, const Mat3<S>& Rt, const S& theta) {
  S s, c;
  sin_cos(theta, s, c);  // trig.hpp: the same operations for double and Pack
  const S c1 = S(1.0) - c;
  const double* K = mv.RK + 9 * i;
  const double* K2 = mv.RK2 + 9 * i;
  Mat3<S> R;
  for (int k = 0; k < 9; ++k) R.m[k] = Rt.m[k] + s * S(K[k]) + c1 * S(K2[k]);
  return R;
}

// R(q) for q = (x, y, z, w), with the factor 2 taken as 2 / |q|² (featherdyn.rotation.quat_to_matrix)
template <class S>
FD_INLINE Mat3<S> quat_to_matrix(const S* q) {
  const S x = q[0], y = q[1], z = q[2], w = q[3];
  const S two = S(2.0) / (x * x + y * y + z * z + w * w);
  const S one(1.0);
  return {{one - two * (y * y + z * z), two * (x * y - w * z), two * (x * z + w * y),
           two * (x * y + w * z), one - two * (x * x + z * z), two * (y * z - w * x),
           two * (x * z - w * y), two * (y * z + w * x), one - two * (x * x + y * y)}};
}

// The pose (R, p) of body i in its parent for q (the whole configuration): Xtree_i · pose_J(q_i).
template <class S>
FD_INLINE void pose_in_parent(const ModelView& mv, int i, const S* q, Mat3<S>& R, Vec3<S>& p) {
  const Mat3<S> Rt = load9<S>(mv.Xtree_R + 9 * i);
  const Vec3<S> pt = load3<S>(mv.Xtree_p + 3 * i);
  const S* qi = q + mv.idx_q[i];
  switch (mv.jtype[i]) {
    case REVOLUTE:
      R = rotate_about_axis(mv, i, Rt, qi[0]);
      p = pt;
      break;
    case PRISMATIC:
      R = Rt;
      p = pt + Rt * (qi[0] * load3<S>(mv.axis + 3 * i));
      break;
    case SPHERICAL:
      R = Rt * quat_to_matrix(qi);
      p = pt;
      break;
    case FREE_FLYER:
      R = Rt * quat_to_matrix(qi + 3);
      p = pt + Rt * Vec3<S>{qi[0], qi[1], qi[2]};
      break;
    default: {  // PLANAR
      const double* B = mv.basis + 9 * i;
      const Vec3<S> e1{S(B[0]), S(B[3]), S(B[6])}, e2{S(B[1]), S(B[4]), S(B[7])};
      R = rotate_about_axis(mv, i, Rt, qi[2]);
      p = pt + Rt * (qi[0] * e1 + qi[1] * e2);
    }
  }
}

// X_up[i] = ⁱX_λ(i) = plux(Rᵀ, p) for the pose (R, p) of body i in its parent.
template <class S>
FD_INLINE Xform<S> joint_X_up(const ModelView& mv, int i, const S* q) {
  Mat3<S> R;
  Vec3<S> p;
  pose_in_parent(mv, i, q, R, p);
  return {R.transpose(), p};
}

// Column j of S_i as a motion.
template <class S>
FD_INLINE Motion<S> S_col(const ModelView& mv, int i, int j) {
  const S z(0.0), one(1.0);
  const Vec3<S> zero{z, z, z};
  switch (mv.jtype[i]) {
    case REVOLUTE:
      return {load3<S>(mv.axis + 3 * i), zero};
    case PRISMATIC:
      return {zero, load3<S>(mv.axis + 3 * i)};
    case SPHERICAL:
    case FREE_FLYER: {
      Motion<S> e{zero, zero};
      Vec3<S>& part = j < 3 ? e.w : e.v;
      const int k = j % 3;
      (k == 0 ? part.x : k == 1 ? part.y : part.z) = one;
      return e;
    }
    default: {  // PLANAR
      const double* B = mv.basis + 9 * i;
      if (j == 0) return {load3<S>(mv.axis + 3 * i), zero};
      return {zero, {S(B[j - 1]), S(B[3 + j - 1]), S(B[6 + j - 1])}};
    }
  }
}

// v_J = S_i x_i for a joint-space rate x (x points at the whole vector).
template <class S>
FD_INLINE Motion<S> S_times(const ModelView& mv, int i, const S* x) {
  const S* xi = x + mv.idx_v[i];
  const S z(0.0);
  switch (mv.jtype[i]) {
    case REVOLUTE:
      return {xi[0] * load3<S>(mv.axis + 3 * i), {z, z, z}};
    case PRISMATIC:
      return {{z, z, z}, xi[0] * load3<S>(mv.axis + 3 * i)};
    case SPHERICAL:
      return {{xi[0], xi[1], xi[2]}, {z, z, z}};
    case FREE_FLYER:
      return {{xi[0], xi[1], xi[2]}, {xi[3], xi[4], xi[5]}};
    default: {  // PLANAR
      Motion<S> m{xi[0] * load3<S>(mv.axis + 3 * i), {z, z, z}};
      for (int j = 1; j < 3; ++j) m.v += xi[j] * S_col<S>(mv, i, j).v;
      return m;
    }
  }
}

// out[0 .. nv_i) = S_iᵀ f
template <class S>
FD_INLINE void St_times(const ModelView& mv, int i, const Force<S>& f, S* out) {
  switch (mv.jtype[i]) {
    case REVOLUTE:
      out[0] = dot(load3<S>(mv.axis + 3 * i), f.n);
      return;
    case PRISMATIC:
      out[0] = dot(load3<S>(mv.axis + 3 * i), f.f);
      return;
    case SPHERICAL:
      out[0] = f.n.x;
      out[1] = f.n.y;
      out[2] = f.n.z;
      return;
    case FREE_FLYER:
      out[0] = f.n.x;
      out[1] = f.n.y;
      out[2] = f.n.z;
      out[3] = f.f.x;
      out[4] = f.f.y;
      out[5] = f.f.z;
      return;
    default:  // PLANAR
      for (int j = 0; j < 3; ++j) out[j] = dot(S_col<S>(mv, i, j), f);
  }
}

}  // namespace fdcore
