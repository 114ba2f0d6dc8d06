// A frame's spatial velocity and acceleration, and their derivatives (reference:
// featherdyn/algorithms/kinematics.py frame_velocity / frame_acceleration; Pinocchio's
// getFrameVelocityDerivatives / getFrameAccelerationDerivatives), along the frame's support only:
//
//     v_k = X_up[k] v_λ(k) + S_k q̇_k,   a_k = X_up[k] a_λ(k) + S_k q̈_k + v_k × S_k q̇_k   (no gravity)
//     LOCAL: ᶠv = ᶠX_b v_b     WORLD: ⁰X_f ᶠv     LOCAL_WORLD_ALIGNED: [R_f ω; R_f v]   (same for a)
//
// The derivatives come from the same template run on Dual numbers (derivatives.hpp): ∂/∂q along the
// tangent of fd.integrate, ∂/∂q̇ and ∂/∂q̈, DERIV_LANES directions a pass.
#pragma once

#include "derivatives.hpp"
#include "frames.hpp"

namespace fdcore {

template <class S>
struct FrameMotionWork {
  std::vector<int> path;
  void resize(size_t nb) {
    if (path.size() < nb) path.resize(nb);
  }
};

// vel (6,) and, when qdd is given, acc (6,) of frame `frame` in `ref`.
template <class S>
void frame_motion(const ModelView& mv, const S* q, const S* qd, const S* qdd, int frame, int ref, S* vel, S* acc) {
  const S z(0.0);
  Motion<S> v{{z, z, z}, {z, z, z}}, a = v;
  Mat3<S> oR;
  Vec3<S> op{z, z, z};
  const int body = mv.frame_body[frame];
  std::vector<int>& path = thread_workspace<FrameMotionWork<S>>(mv.nb).path;
  int n = 0;
  for (int j = body; j != -1; j = mv.parent[j]) path[n++] = j;
  for (int s = n - 1; s >= 0; --s) {
    const int k = path[s];
    Mat3<S> R;
    Vec3<S> p;
    pose_in_parent(mv, k, q, R, p);
    const Xform<S> X_up{R.transpose(), p};
    const Motion<S> vJ = S_times(mv, k, qd);
    if (s == n - 1) {
      oR = R;
      op = p;
      v = vJ;
      if (qdd) a = S_times(mv, k, qdd) + cross_motion(v, vJ);
    } else {
      op = op + oR * p;
      oR = oR * R;
      v = X_up.apply(v) + vJ;
      if (qdd) a = X_up.apply(a) + S_times(mv, k, qdd) + cross_motion(v, vJ);
    }
  }
  const Mat3<S> Rfb = load9<S>(mv.frame_R + 9 * frame);
  const Vec3<S> pfb = load3<S>(mv.frame_p + 3 * frame);
  const Mat3<S> Rf = n ? oR * Rfb : Rfb;
  const Vec3<S> pf = n ? op + oR * pfb : pfb;
  auto express = [&](const Motion<S>& m, S* out) {
    if (n == 0) {  // a frame fixed to the world does not move
      for (int r = 0; r < 6; ++r) out[r] = z;
      return;
    }
    const Motion<S> loc{mul_transpose(Rfb, m.w), mul_transpose(Rfb, m.v - cross(pfb, m.w))};  // ᶠX_b m
    Motion<S> e = loc;
    if (ref != LOCAL) {
      const Vec3<S> w = Rf * loc.w;
      e = ref == WORLD ? Motion<S>{w, Rf * loc.v + cross(pf, w)} : Motion<S>{w, Rf * loc.v};
    }
    out[0] = e.w.x, out[1] = e.w.y, out[2] = e.w.z, out[3] = e.v.x, out[4] = e.v.y, out[5] = e.v.z;
  };
  express(v, vel);
  if (qdd) express(a, acc);
}

// ∂v_f/∂q, ∂v_f/∂q̇ and, when qdd is given, ∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈: (6, nv) row-major each.
inline void frame_motion_derivatives(const ModelView& mv, const double* q, const double* qd, const double* qdd,
                                     int frame, int ref, double* dv_dq, double* dv_dv, double* da_dq, double* da_dv,
                                     double* da_da) {
  const int nq = mv.nq, nv = mv.nv, ndir = (qdd ? 3 : 2) * nv;
  DerivWork<DualK>& w = thread_workspace<DerivWork<DualK>>(mv.nb);
  w.Q.resize(nq), w.V.resize(nv), w.A.resize(nv), w.T.resize(12);
  for (int start = 0; start < ndir; start += DERIV_LANES) {
    for (int k = 0; k < nq; ++k) w.Q[k] = DualK(q[k]);
    for (int k = 0; k < nv; ++k) w.V[k] = DualK(qd[k]);
    for (int k = 0; qdd && k < nv; ++k) w.A[k] = DualK(qdd[k]);
    const int lanes = std::min(DERIV_LANES, ndir - start);
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l;
      if (dir < nv) seed_tangent(mv, q, dir, l, w.Q.data());
      else if (dir < 2 * nv) w.V[dir - nv].d[l] = 1.0;
      else w.A[dir - 2 * nv].d[l] = 1.0;
    }
    frame_motion(mv, w.Q.data(), w.V.data(), qdd ? w.A.data() : nullptr, frame, ref, w.T.data(), w.T.data() + 6);
    for (int l = 0; l < lanes; ++l) {
      const int dir = start + l, block = dir / nv, col = dir % nv;
      double* vout = block == 0 ? dv_dq : block == 1 ? dv_dv : nullptr;
      double* aout = !qdd ? nullptr : block == 0 ? da_dq : block == 1 ? da_dv : da_da;
      for (int r = 0; r < 6; ++r) {
        if (vout) vout[r * nv + col] = w.T[r].d[l];
        if (aout) aout[r * nv + col] = w.T[6 + r].d[l];
      }
    }
  }
}

}  // namespace fdcore
