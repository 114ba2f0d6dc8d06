// Kinetic and potential energy and the centre of mass (reference: featherdyn/algorithms/energy.py;
// chapter §8, RBDA §9.2), from the forward kinematics of kinematics.hpp:
//
//     T = Σ_i ½ v_iᵀ I_i v_i                     (v_i, I_i in body coordinates)
//     U = −Σ_i m_i gᵀ ⁰c_i,     ⁰c_i = ⁰p_i + ⁰R_i c_i
//     c = Σ_i m_i ⁰c_i / m,     ċ = Σ_i ⁰R_i (m_i v_i + ω_i × h_i) / m     (h_i = m_i c_i)
#pragma once

#include "joints.hpp"
#include "kinematics.hpp"
#include "rnea.hpp"
#include "scratch.hpp"

namespace fdcore {

// the forward kinematics' workspace (world placements oR, op and body velocities v)
template <class S>
using EnergyWork = FkWork<S>;

// World placements of every body (⁰R_i, ⁰p_i) into oR, op.
template <class S>
inline void world_placements(const ModelView& mv, const S* q, Mat3<S>* oR, Vec3<S>* op) {
  Mat3<S> R;
  Vec3<S> p;
  for (int i = 0; i < mv.nb; ++i) place_body(mv, i, q, oR, op, R, p);
}

// T(q, q̇)
template <class S>
S kinetic_energy(const ModelView& mv, const S* q, const S* qd) {
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(mv.nb);
  Motion<S>* v = w.v.data();
  S T(0.0);
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i];
    const Xform<S> X_up = joint_X_up(mv, i, q);
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up.apply(v[lam]) + vJ;
    T = T + S(0.5) * dot(v[i], body_inertia<S>(mv, i) * v[i]);
  }
  if (mv.armature)  // the rotors: ½ Σ armature_k q̇_k², so that T = ½ q̇ᵀ M q̇ with M's armature
    for (int k = 0; k < mv.nv; ++k) T = T + S(0.5) * S(mv.armature[k]) * qd[k] * qd[k];
  return T;
}

// The kinetic energy's gradient (∂T/∂q along fd.integrate's tangent, ∂T/∂q̇ = M q̇), in O(nb): with body velocities
// v_i, the subtree's momentum h^C_i = Σ_{j ∈ subtree(i)} ⁱX_j* I_j v_j and v_λ(i) the parent's velocity (in body i's
// coordinates, v_i − S_i q̇_i), for each column k of joint i
//
//     ∂T/∂q_k = −S_kᵀ (v_λ(i) ×* h^C_i),     ∂T/∂q̇_k = S_kᵀ h^C_i + armature_k q̇_k
//
// (moving q_k turns subtree(i) and its momentum rigidly by S_k: only the ancestors' columns stay behind, and
// ⟨v, I v⟩ changes by −2 S_kᵀ (v_λ ×* h^C): docs/derivatives.md, "The kinetic energy's gradient").
template <class S>
struct KineticWork {
  std::vector<Xform<S>> X_up;
  std::vector<Motion<S>> v, vp;
  std::vector<Force<S>> hC;
  void resize(size_t nb) {
    if (v.size() < nb) X_up.resize(nb), v.resize(nb), vp.resize(nb), hC.resize(nb);
  }
};

template <class S>
void kinetic_energy_derivatives(const ModelView& mv, const S* q, const S* qd, S* dT_dq, S* dT_dv) {
  KineticWork<S>& w = thread_workspace<KineticWork<S>>(mv.nb);
  const S z(0.0);
  const Motion<S> zero{{z, z, z}, {z, z, z}};
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i];
    w.X_up[i] = joint_X_up(mv, i, q);
    w.vp[i] = lam == -1 ? zero : w.X_up[i].apply(w.v[lam]);
    w.v[i] = w.vp[i] + S_times(mv, i, qd);
    w.hC[i] = body_inertia<S>(mv, i) * w.v[i];
  }
  for (int i = mv.nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    if (lam != -1) w.hC[lam] += w.X_up[i].apply_transpose(w.hC[i]);
    const Force<S> turn = cross_force(w.vp[i], w.hC[i]);
    St_times(mv, i, turn, dT_dq + mv.idx_v[i]);
    St_times(mv, i, w.hC[i], dT_dv + mv.idx_v[i]);
    for (int c = 0; c < mv.nv_i[i]; ++c) dT_dq[mv.idx_v[i] + c] = -dT_dq[mv.idx_v[i] + c];
  }
  if (mv.armature)
    for (int k = 0; k < mv.nv; ++k) dT_dv[k] = dT_dv[k] + S(mv.armature[k]) * qd[k];
}

// U(q), zero at the world origin
template <class S>
S potential_energy(const ModelView& mv, const S* q) {
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(mv.nb);
  world_placements(mv, q, w.oR.data(), w.op.data());
  const Vec3<S> g{S(mv.gravity[0]), S(mv.gravity[1]), S(mv.gravity[2])};
  S U(0.0);
  for (int i = 0; i < mv.nb; ++i) {
    const Vec3<S> mc = S(mv.mass[i]) * w.op[i] + w.oR[i] * load3<S>(mv.h + 3 * i);  // m_i ⁰c_i
    U = U - dot(g, mc);
  }
  return U;
}

// c (3,) and, when qd is given, ċ (3,) into cd; `mass` the tree's total mass (> 0).
template <class S>
void center_of_mass(const ModelView& mv, const S* q, const S* qd, double mass, S* c, S* cd) {
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(mv.nb);
  Mat3<S>* oR = w.oR.data();
  Vec3<S>* op = w.op.data();
  Motion<S>* v = w.v.data();
  const S z(0.0);
  Vec3<S> sum{z, z, z}, vsum{z, z, z};
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i];
    Mat3<S> R;
    Vec3<S> p;
    place_body(mv, i, q, oR, op, R, p);
    const Vec3<S> h = load3<S>(mv.h + 3 * i);
    const S m(mv.mass[i]);
    sum += m * op[i] + oR[i] * h;
    if (qd == nullptr) continue;
    const Xform<S> X_up{R.transpose(), p};
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up.apply(v[lam]) + vJ;
    vsum += oR[i] * (m * v[i].v + cross(v[i].w, h));
  }
  const S inv = S(1.0) / S(mass);
  c[0] = sum.x * inv, c[1] = sum.y * inv, c[2] = sum.z * inv;
  if (cd) cd[0] = vsum.x * inv, cd[1] = vsum.y * inv, cd[2] = vsum.z * inv;
}

}  // namespace fdcore
