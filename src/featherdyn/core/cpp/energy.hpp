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
