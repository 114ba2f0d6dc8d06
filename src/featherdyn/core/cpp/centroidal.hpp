// The centroidal momentum matrix (reference: featherdyn/algorithms/centroidal.py; Orin, Goswami &
// Lee 2013), in the frame G with world axes at the centre of mass c:
//
//     ᴳX_i = pose of body i seen from G (⁰R_i, ⁰p_i − c),   ᴳS_i = ᴳX_i S_i
//     ᴳI^C_i = ᴳX_i* I_i ᴳX_i⁻¹ + Σ_{children j} ᴳI^C_j          (i = nb−1 … 0)
//     A_G[:, k] = ᴳI^C_k ᴳS_k      (rows [k_G; p]),      h_G = A_G q̇ (summed over the bodies: below)
//
// The same matrix as the reference's world-origin composite shifted to c, with the moment arms
// taken from c (short) instead of from the world origin.
#pragma once

#include "energy.hpp"

namespace fdcore {

template <class S>
struct CentroidalWork {
  std::vector<RigidInertia<S>> IC;
  void resize(size_t nb) {
    if (IC.size() < nb) IC.resize(nb);
  }
};

// A (6, nv) row-major; `mass` the tree's total mass (> 0).
template <class S>
void centroidal_momentum_matrix(const ModelView& mv, const S* q, double mass, S* A) {
  const int nb = mv.nb, nv = mv.nv;
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(nb);
  RigidInertia<S>* IC = thread_workspace<CentroidalWork<S>>(nb).IC.data();
  Mat3<S>* oR = w.oR.data();
  Vec3<S>* op = w.op.data();
  world_placements(mv, q, oR, op);
  const S z(0.0);
  Vec3<S> sum{z, z, z};
  for (int i = 0; i < nb; ++i) sum += S(mv.mass[i]) * op[i] + oR[i] * load3<S>(mv.h + 3 * i);
  const S inv = S(1.0) / S(mass);
  const Vec3<S> c = inv * sum;
  for (int i = 0; i < nb; ++i) {
    op[i] = op[i] - c;  // from now on: ᴳp_i
    IC[i] = transform_to_parent(Xform<S>{oR[i].transpose(), op[i]}, body_inertia<S>(mv, i));
  }
  for (int i = nb - 1; i >= 0; --i) {
    const int lam = mv.parent[i];
    if (lam != -1) IC[lam] = IC[lam] + IC[i];
  }
  for (int i = 0; i < nb; ++i) {
    for (int col = 0; col < mv.nv_i[i]; ++col) {
      const Motion<S> s = S_col<S>(mv, i, col);
      const Vec3<S> wg = oR[i] * s.w;
      const Force<S> h = IC[i] * Motion<S>{wg, oR[i] * s.v + cross(op[i], wg)};
      const int k = mv.idx_v[i] + col;
      A[0 * nv + k] = h.n.x, A[1 * nv + k] = h.n.y, A[2 * nv + k] = h.n.z;
      A[3 * nv + k] = h.f.x, A[4 * nv + k] = h.f.y, A[5 * nv + k] = h.f.z;
    }
  }
}

// h_G = [k_G; p] (6,) = A_G q̇ without forming A_G: the bodies' momenta [n_i; f_i] = I_i v_i (body coordinates,
// v_i from the forward pass) summed about the world origin in world axes, then moved to c:
//
//     p = Σ_i ⁰R_i f_i,   k_O = Σ_i ⁰R_i n_i + ⁰p_i × ⁰R_i f_i,   k_G = k_O − c × p
//
// (the reference forms A_G, featherdyn/algorithms/centroidal.py; the two agree to rounding).
template <class S>
void centroidal_momentum(const ModelView& mv, const S* q, const S* qd, double mass, S* hG) {
  EnergyWork<S>& w = thread_workspace<EnergyWork<S>>(mv.nb);
  Mat3<S>* oR = w.oR.data();
  Vec3<S>* op = w.op.data();
  Motion<S>* v = w.v.data();
  const S z(0.0);
  Vec3<S> sum{z, z, z}, p{z, z, z}, k{z, z, z};
  for (int i = 0; i < mv.nb; ++i) {
    const int lam = mv.parent[i];
    Mat3<S> R;
    Vec3<S> t;
    place_body(mv, i, q, oR, op, R, t);
    sum += S(mv.mass[i]) * op[i] + oR[i] * load3<S>(mv.h + 3 * i);
    const Xform<S> X_up{R.transpose(), t};
    const Motion<S> vJ = S_times(mv, i, qd);
    v[i] = lam == -1 ? vJ : X_up.apply(v[lam]) + vJ;
    const Force<S> h = body_inertia<S>(mv, i) * v[i];
    const Vec3<S> f = oR[i] * h.f;
    p += f;
    k += oR[i] * h.n + cross(op[i], f);
  }
  const Vec3<S> c = (S(1.0) / S(mass)) * sum;
  k = k - cross(c, p);
  hG[0] = k.x, hG[1] = k.y, hG[2] = k.z, hG[3] = p.x, hG[4] = p.y, hG[5] = p.z;
}

}  // namespace fdcore
