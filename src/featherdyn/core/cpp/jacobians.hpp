// Joint Jacobians and the time variation of a frame Jacobian (reference: featherdyn/algorithms/
// jacobians.py; RBDA §4.5; Pinocchio's computeJointJacobians and getFrameJacobianTimeVariation):
//
//     ⁰J[:, k] = ⁰X_k S_k                     (every joint, world coordinates)
//     ⁰v_k = Σ_{j ∈ support(k)} ⁰X_j S_j q̇_j   (body k's spatial velocity in world coordinates)
//     WORLD:   ⁰J̇[:, k] = ⁰v_k × ⁰J[:, k]
//     LOCAL:   ᶠJ̇ = ᶠX_0 ⁰J̇ − ᶠv × ᶠJ,         ᶠv = ᶠX_0 ⁰v_body(f)
//     LWA:     J̇ = crm([ω_f; 0]) J_LWA + blkdiag(R_f, R_f) ᶠJ̇    (ω_f = R_f ᶠω, J_LWA = [ω; v − p_f × ω])
#pragma once

#include "energy.hpp"
#include "frames.hpp"

namespace fdcore {

template <class S>
struct SupportVelocities {
  std::vector<Motion<S>> v;
  void resize(size_t nb) {
    if (v.size() < nb) v.resize(nb);
  }
};

template <class S>
inline void put_column(S* J, int nv, int col, const Motion<S>& m) {
  J[0 * nv + col] = m.w.x, J[1 * nv + col] = m.w.y, J[2 * nv + col] = m.w.z;
  J[3 * nv + col] = m.v.x, J[4 * nv + col] = m.v.y, J[5 * nv + col] = m.v.z;
}

// ⁰X_k S_k[:, c] from the world placement (R, p) of body k
template <class S>
inline Motion<S> world_column(const ModelView& mv, int k, int c, const Mat3<S>& R, const Vec3<S>& p) {
  const Motion<S> s = S_col<S>(mv, k, c);
  const Vec3<S> w = R * s.w;
  return {w, R * s.v + cross(p, w)};
}

// J (6, nv) row-major: every joint's columns in world coordinates.
template <class S>
void joint_jacobians(const ModelView& mv, const S* q, S* J) {
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(mv.nb);
  world_placements(mv, q, w.oR.data(), w.op.data());
  for (int k = 0; k < mv.nb; ++k)
    for (int c = 0; c < mv.nv_i[k]; ++c) put_column(J, mv.nv, mv.idx_v[k] + c, world_column(mv, k, c, w.oR[k], w.op[k]));
}

// ᶠX_0 m for the frame at (R_f, p_f): [R_fᵀ ω; R_fᵀ (v − p_f × ω)]
template <class S>
inline Motion<S> to_frame(const Mat3<S>& Rf, const Vec3<S>& pf, const Motion<S>& m) {
  return {mul_transpose(Rf, m.w), mul_transpose(Rf, m.v - cross(pf, m.w))};
}

// dJ (6, nv) row-major: J̇ of frame `frame` in `ref` along q̇ = qd.
template <class S>
void frame_jacobian_time_variation(const ModelView& mv, const S* q, const S* qd, int frame, int ref, S* dJ) {
  SupportWork<S>& w = thread_workspace<SupportWork<S>>(mv.nb);
  const int nv = mv.nv;
  for (int k = 0; k < 6 * nv; ++k) dJ[k] = S(0.0);
  const int body = mv.frame_body[frame];
  const int n = support_placements(mv, body, q, w);
  if (n == 0) return;  // a frame fixed to the world
  const Mat3<S> Rf = w.oR[n - 1] * load9<S>(mv.frame_R + 9 * frame);
  const Vec3<S> pf = w.op[n - 1] + w.oR[n - 1] * load3<S>(mv.frame_p + 3 * frame);
  const S z(0.0);
  Motion<S> v0{{z, z, z}, {z, z, z}};  // ⁰v of the current support body
  // pass 1: ⁰v_k along the support (the velocity of the frame's body is the last)
  std::vector<Motion<S>>& vk = thread_workspace<SupportVelocities<S>>(mv.nb).v;
  for (int s = 0; s < n; ++s) {
    const int k = w.path[s];
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const Motion<S> col = world_column(mv, k, c, w.oR[s], w.op[s]);
      const S x = qd[mv.idx_v[k] + c];
      v0 = {v0.w + x * col.w, v0.v + x * col.v};
    }
    vk[s] = v0;
  }
  const Motion<S> vf = to_frame(Rf, pf, v0);  // ᶠv
  const Vec3<S> wf = Rf * vf.w;               // ω_f in world axes
  for (int s = 0; s < n; ++s) {
    const int k = w.path[s];
    for (int c = 0; c < mv.nv_i[k]; ++c) {
      const Motion<S> col = world_column(mv, k, c, w.oR[s], w.op[s]);
      const Motion<S> dcol = cross_motion(vk[s], col);  // ⁰J̇[:, k]
      Motion<S> out = dcol;
      if (ref != WORLD) {
        const Motion<S> Jl = to_frame(Rf, pf, col);
        const Motion<S> a = to_frame(Rf, pf, dcol), b = cross_motion(vf, Jl);
        out = Motion<S>{a.w - b.w, a.v - b.v};  // ᶠJ̇
        if (ref == LOCAL_WORLD_ALIGNED) {
          const Motion<S> Jlwa{col.w, col.v - cross(pf, col.w)};
          out = Motion<S>{cross(wf, Jlwa.w) + Rf * out.w, cross(wf, Jlwa.v) + Rf * out.v};
        }
      }
      put_column(dJ, nv, mv.idx_v[k] + c, out);
    }
  }
}

}  // namespace fdcore
