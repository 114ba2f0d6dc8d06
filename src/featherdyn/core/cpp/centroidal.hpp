// The centroidal momentum matrix (reference: featherdyn/algorithms/centroidal.py; Orin, Goswami &
// Lee 2013), in the frame G with world axes at the centre of mass c:
//
//     ᴳX_i = pose of body i seen from G (⁰R_i, ⁰p_i − c),   ᴳS_i = ᴳX_i S_i
//     ᴳI^C_i = ᴳX_i* I_i ᴳX_i⁻¹ + Σ_{children j} ᴳI^C_j          (i = nb−1 … 0)
//     A_G[:, k] = ᴳI^C_k ᴳS_k      (rows [k_G; p]),      h_G = A_G q̇
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

// h_G = A_G q̇ (6,); A (6, nv) receives A_G.
template <class S>
void centroidal_momentum(const ModelView& mv, const S* q, const S* qd, double mass, S* A, S* h) {
  centroidal_momentum_matrix(mv, q, mass, A);
  for (int r = 0; r < 6; ++r) {
    S x(0.0);
    for (int k = 0; k < mv.nv; ++k) x = x + A[r * mv.nv + k] * qd[k];
    h[r] = x;
  }
}

}  // namespace fdcore
