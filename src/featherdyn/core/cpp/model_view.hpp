// The model as the kernels see it: a flat, read-only struct of arrays built once per
// featherdyn.Model (featherdyn/core/_model_view.py builds the arrays; the binding copies
// them into a ModelData that owns them). A reader greps a field and finds every use.
#pragma once

#include <cstdint>
#include <vector>

namespace fdcore {

enum JointType : std::int32_t { REVOLUTE = 0, PRISMATIC = 1, SPHERICAL = 2, FREE_FLYER = 3, PLANAR = 4 };

struct ModelView {
  int nb = 0, nq = 0, nv = 0, nf = 0;
  // per body i
  const std::int32_t* parent = nullptr;  // λ(i), −1 = the world
  const std::int32_t* jtype = nullptr;   // JointType
  const std::int32_t* idx_q = nullptr;   // where q_i starts
  const std::int32_t* idx_v = nullptr;   // where v_i starts
  const std::int32_t* nv_i = nullptr;    // joint dofs
  const double* Xtree_R = nullptr;       // (nb, 9) joint frame's rotation in the parent body, row-major
  const double* Xtree_p = nullptr;       // (nb, 3) joint frame's origin in the parent body
  const double* mass = nullptr;          // (nb,)
  const double* h = nullptr;             // (nb, 3) m c
  const double* Ibar = nullptr;          // (nb, 6) Ī about the body origin: xx, xy, xz, yy, yz, zz
  const double* axis = nullptr;          // (nb, 3) revolute / prismatic axis, planar normal
  const double* basis = nullptr;         // (nb, 9) planar basis [e1 e2 n] as columns, row-major
  // revolute and planar joints: Xtree_R [a]× and Xtree_R [a]×² (axis or normal a), so that
  // Xtree_R · Rodrigues(a, θ) = Xtree_R + sin θ · RK + (1 − cos θ) · RK2 costs no matrix product
  const double* RK = nullptr;            // (nb, 9) row-major
  const double* RK2 = nullptr;           // (nb, 9) row-major
  // per model
  const double* gravity = nullptr;       // (3,) in world coordinates
  double singular_tol = 0.0;  // ABA: a pivot ≤ this is singular (SINGULAR_PIVOT_RTOL × the largest inertia entry)
  double quat_tol = 0.0;      // a quaternion in q may be off unit norm by this much (QUATERNION_NORM)
  // per frame k
  const std::int32_t* frame_body = nullptr;  // (nf,) −1 = the world
  const double* frame_R = nullptr;           // (nf, 9) placement in the body
  const double* frame_p = nullptr;           // (nf, 3)
  // unit quaternions in q (spherical q_i, free-flyer q_i[3:7]): where each starts, and its body
  const std::int32_t* quat_q = nullptr;     // (nquat,)
  const std::int32_t* quat_body = nullptr;  // (nquat,)
  int nquat = 0;
  // per degree of freedom
  const double* armature = nullptr;  // (nv,) reflected rotor inertia added to M's diagonal; nullptr when all zero
};

// Reals per body in ModelData::reals.
constexpr size_t BODY_REALS = 52;

// The storage behind a ModelView (owned by the Python object featherdyn.core._core.Model).
struct ModelData {
  std::vector<std::int32_t> ints;  // parent, jtype, idx_q, idx_v, nv_i (nb each), frame_body (nf)
  std::vector<std::int32_t> quats;  // quat_q then quat_body (nquat each)
  std::vector<double> reals;       // Xtree_R, Xtree_p, mass, h, Ibar, axis, basis, RK, RK2, gravity, frame_R, frame_p,
                                   // armature
  ModelView view;

  ModelData(int nb, int nq, int nv, int nf, const std::int32_t* body_ints, const double* body_reals,
            const double* gravity3, double singular_tol, double quat_tol, const std::int32_t* frame_body,
            const double* frame_reals, const double* armature)
      : ints(5 * static_cast<size_t>(nb) + nf),
        reals(static_cast<size_t>(nb) * BODY_REALS + 3 + static_cast<size_t>(nf) * 12 + static_cast<size_t>(nv)) {
    for (size_t k = 0; k < 5 * static_cast<size_t>(nb); ++k) ints[k] = body_ints[k];
    for (int k = 0; k < nf; ++k) ints[5 * static_cast<size_t>(nb) + k] = frame_body[k];
    const size_t nbr = static_cast<size_t>(nb) * BODY_REALS;
    for (size_t k = 0; k < nbr; ++k) reals[k] = body_reals[k];
    for (int k = 0; k < 3; ++k) reals[nbr + k] = gravity3[k];
    for (size_t k = 0; k < static_cast<size_t>(nf) * 12; ++k) reals[nbr + 3 + k] = frame_reals[k];
    const size_t arm = nbr + 3 + static_cast<size_t>(nf) * 12;
    bool any_armature = false;
    for (int k = 0; k < nv; ++k) {
      reals[arm + k] = armature[k];
      any_armature = any_armature || armature[k] != 0.0;
    }
    ModelView& m = view;
    m.nb = nb;
    m.nq = nq;
    m.nv = nv;
    m.nf = nf;
    const std::int32_t* I = ints.data();
    m.parent = I;
    m.jtype = I + nb;
    m.idx_q = I + 2 * nb;
    m.idx_v = I + 3 * nb;
    m.nv_i = I + 4 * nb;
    m.frame_body = I + 5 * nb;
    // body_reals is blocked by field: 9 + 3 + 1 + 3 + 6 + 3 + 9 + 9 + 9 = BODY_REALS per body
    const double* R = reals.data();
    m.Xtree_R = R;
    m.Xtree_p = R + 9 * nb;
    m.mass = R + 12 * nb;
    m.h = R + 13 * nb;
    m.Ibar = R + 16 * nb;
    m.axis = R + 22 * nb;
    m.basis = R + 25 * nb;
    m.RK = R + 34 * nb;
    m.RK2 = R + 43 * nb;
    m.gravity = R + nbr;
    m.singular_tol = singular_tol;
    m.quat_tol = quat_tol;
    m.frame_R = R + nbr + 3;
    m.frame_p = R + nbr + 3 + 9 * static_cast<size_t>(nf);
    m.armature = any_armature ? R + arm : nullptr;
    std::vector<std::int32_t> at, of;
    for (int i = 0; i < nb; ++i) {
      if (m.jtype[i] == SPHERICAL || m.jtype[i] == FREE_FLYER) {
        at.push_back(m.idx_q[i] + (m.jtype[i] == FREE_FLYER ? 3 : 0));
        of.push_back(i);
      }
    }
    quats = at;
    quats.insert(quats.end(), of.begin(), of.end());
    m.nquat = static_cast<int>(at.size());
    m.quat_q = quats.data();
    m.quat_body = quats.data() + m.nquat;
  }
};

// The tree's total mass m = Σ m_i, or 0 when it has none (the centre of mass is then undefined: status NO_MASS).
inline double total_mass(const ModelView& mv) {
  double m = 0.0;
  for (int i = 0; i < mv.nb; ++i) m += mv.mass[i];
  return m > 0.0 ? m : 0.0;
}

}  // namespace fdcore
