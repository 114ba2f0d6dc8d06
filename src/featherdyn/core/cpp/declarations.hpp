// The declared algorithms (declare.hpp): each a name, its operands with symbolic shapes and its kernel on one
// state; `declared_kernels` lists them for the binding. Adding an algorithm here, its reference in
// featherdyn/algorithms/ and its declaration in featherdyn/api/declarations.py makes its public function,
// out=, batch, Dask and fd.compile forms (docs/architecture.md, "Adding an algorithm").
#pragma once

#include <algorithm>
#include <vector>

#include "aba.hpp"
#include "crba.hpp"
#include "declare.hpp"
#include "declarations_configuration.hpp"
#include "declarations_constraints.hpp"
#include "declarations_second_order.hpp"
#include "declarations_kinematics.hpp"
#include "vjp.hpp"
#include "centroidal.hpp"
#include "derivatives.hpp"
#include "energy.hpp"
#include "frame_derivatives.hpp"
#include "frames.hpp"
#include "jacobians.hpp"
#include "kinematics.hpp"
#include "ltl.hpp"
#include "regressor.hpp"
#include "scratch.hpp"
#include "rnea.hpp"

namespace fdcore {

// τ (nv,) = RNEA(q, q̇, q̈, f_ext): the joint forces that produce q̈ in state (q, q̇), with the body-frame
// external forces f_ext (nb, 6) when given, gravity unless gravity=False (rnea.hpp; RBDA table 5.1).
struct Rnea : Declared {
  static constexpr const char* name = "rnea";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a, operand::f_ext};
  static constexpr Operand outputs[] = {operand::vector("tau", NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::rnea;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    rnea(mv, in[0], in[1], in[2], in[3], opt.gravity, out[0]);
    return OK;
  }
};

// h (nv,) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0): RNEA with no acceleration given.
struct NonlinearEffects : Declared {
  static constexpr const char* name = "nonlinear_effects";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("h", NV)};
  static constexpr auto group = &fdgroup::GroupKernels::rnea;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    rnea<double>(mv, in[0], in[1], nullptr, nullptr, true, out[0]);
    return OK;
  }
};

// g (nv,) = RNEA(q, 0, 0): RNEA with neither velocity nor acceleration given.
struct GeneralizedGravity : Declared {
  static constexpr const char* name = "generalized_gravity";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::vector("g", NV)};
  static constexpr auto group = &fdgroup::GroupKernels::rnea;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    rnea<double>(mv, in[0], nullptr, nullptr, nullptr, true, out[0]);
    return OK;
  }
};

// M (nv, nv), full and exactly symmetric: T = ½ q̇ᵀ M q̇ (crba.hpp; RBDA table 6.2).
struct Crba : Declared {
  static constexpr const char* name = "crba";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("M", NV, NV)};
  static constexpr auto group = &fdgroup::GroupKernels::crba;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    crba(mv, in[0], out[0]);
    return OK;
  }
};

// q̈ (nv,) = M⁻¹ (τ − C q̇ − g + Σ J_iᵀ f_i) (aba.hpp; RBDA table 7.1). Status SINGULAR naming the joint (the
// leaf-most) whose articulated inertia Sᵀ Iᴬ S is not positive definite.
struct Aba : Declared {
  static constexpr const char* name = "aba";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::f_ext};
  static constexpr Operand outputs[] = {operand::vector("qdd", NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::aba;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    const int bad = aba<double>(mv, in[0], in[1], in[2], in[3], opt.gravity, out[0], nullptr);
    return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
  }
  // the singular joint (−1: none) and its D
  static constexpr SingularBlockFn singular_block = [](const ModelView& mv, const double* const* in,
                                                       const Options& opt, double* D36) -> std::int64_t {
    std::vector<double> qdd(static_cast<size_t>(mv.nv));
    return aba<double>(mv, in[0], in[1], in[2], in[3], opt.gravity, qdd.data(), D36);
  };
};

// J (6, nv), rows [ω; v], of a frame in a reference (frames.hpp): frame_velocity = J q̇ (getFrameJacobian).
struct FrameJacobian : Declared {
  static constexpr const char* name = "frame_jacobian";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("J", 6, NV)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_jacobian(mv, in[0], opt.frame, opt.reference, out[0]);
    return OK;
  }
};

// Every joint's columns in world coordinates (6, nv): J[:, k] = ⁰X_k S_k (jacobians.hpp; Pinocchio's data.J).
struct JointJacobians : Declared {
  static constexpr const char* name = "joint_jacobians";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("J", 6, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    joint_jacobians(mv, in[0], out[0]);
    return OK;
  }
};

// J̇ (6, nv) of a frame's Jacobian along q̇, in a reference (jacobians.hpp; getFrameJacobianTimeVariation).
struct FrameJacobianTimeVariation : Declared {
  static constexpr const char* name = "frame_jacobian_time_variation";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::matrix("dJ", 6, NV)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_jacobian_time_variation(mv, in[0], in[1], opt.frame, opt.reference, out[0]);
    return OK;
  }
};

// T = Σ ½ v_iᵀ I_i v_i (energy.hpp), one number.
struct KineticEnergy : Declared {
  static constexpr const char* name = "kinetic_energy";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::scalar("T")};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    out[0][0] = kinetic_energy(mv, in[0], in[1]);
    return OK;
  }
};

// (∂T/∂q, ∂T/∂q̇) (nv,) each, ∂/∂q along fd.integrate's tangent, in O(nb) (energy.hpp): the gradient of
// ⟨W, M(q)⟩ = Σ_i (x_iᵀ M y_i) that featherdyn.torch's backward of crba takes by polarisation (api/jacobians.py).
struct KineticEnergyDerivatives : Declared {
  static constexpr const char* name = "kinetic_energy_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("dT_dq", NV), operand::vector("dT_dv", NV)};
  static constexpr auto group = &fdgroup::GroupKernels::kinetic_energy_derivatives;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    kinetic_energy_derivatives(mv, in[0], in[1], out[0], out[1]);
    return OK;
  }
};

// wᵀ ∂τ/∂(q, q̇, q̈) (nv,) each: the gradient of wᵀ RNEA(q, q̇, q̈, f_ext) in O(nb), no Jacobian formed (vjp.hpp).
struct RneaVjp : Declared {
  static constexpr const char* name = "rnea_vjp";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a, operand::w, operand::f_ext};
  static constexpr Operand outputs[] = {operand::vector("grad_q", NV), operand::vector("grad_v", NV),
                                        operand::vector("grad_a", NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::rnea_vjp;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    rnea_vjp<double>(mv, in[0], in[1], in[2], in[3], in[4], opt.gravity, out[0], out[1], out[2]);
    return OK;
  }
};

// ∂⟨W, M(q)⟩/∂q (nv,): the mass matrix's vector–Jacobian product, O(Σ depth + subtree) (vjp.hpp).
struct CrbaVjp : Declared {
  static constexpr const char* name = "crba_vjp";
  static constexpr Operand inputs[] = {operand::q, operand::W};
  static constexpr Operand outputs[] = {operand::vector("grad_q", NV)};
  static constexpr auto group = &fdgroup::GroupKernels::crba_vjp;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    crba_vjp<double>(mv, in[0], in[1], out[0]);
    return OK;
  }
};

// wᵀ ∂q̈/∂(q, q̇, τ) (nv,) each: the gradient of wᵀ ABA(q, q̇, τ, f_ext) in O(nb) (vjp.hpp: RNEA's at q̈ with
// λ = M⁻¹ w).
struct AbaVjp : Declared {
  static constexpr const char* name = "aba_vjp";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::w, operand::f_ext};
  static constexpr Operand outputs[] = {operand::vector("grad_q", NV), operand::vector("grad_v", NV),
                                        operand::vector("grad_tau", NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::aba_vjp;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    const int bad = aba_vjp<double>(mv, in[0], in[1], in[2], in[3], in[4], opt.gravity, out[0], out[1], out[2]);
    return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
  }
  // the singular joint (−1: none) and its D (of q alone: ABA's on the state)
  static constexpr SingularBlockFn singular_block = [](const ModelView& mv, const double* const* in,
                                                       const Options& opt, double* D36) -> std::int64_t {
    const double* state[] = {in[0], in[1], in[2], in[4]};
    return Aba::singular_block(mv, state, opt, D36);
  };
};

// U = −Σ m_i gᵀ ⁰c_i (energy.hpp), zero at the world origin, one number.
struct PotentialEnergy : Declared {
  static constexpr const char* name = "potential_energy";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::scalar("U")};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    out[0][0] = potential_energy(mv, in[0]);
    return OK;
  }
};

// ⁰M_i (nb, 4, 4), the bodies' world placements, as homogeneous matrices: fd.compile's fk (kinematics.hpp).
struct Placements : Declared {
  static constexpr const char* name = "placements";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::placements("H")};
  static constexpr auto group = &fdgroup::GroupKernels::fk;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    forward_kinematics<double>(mv, in[0], nullptr, nullptr, out[0], nullptr, nullptr);
    return OK;
  }
};

// Every body's world placement ⁰M_i and placement in its parent ᵖM_i (nb, 4, 4), and with q̇ (and q̈) its
// velocity v_i and spatial acceleration a_i without gravity (nb, 6) in body coordinates (kinematics.hpp):
//     ᵖM_i = Xtree_i · M_J(q_i),   ⁰M_i = ⁰M_λ(i) · ᵖM_i
//     v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
struct ForwardKinematics : Declared {
  static constexpr const char* name = "forward_kinematics";
  static constexpr Operand inputs[] = {operand::q, operand::optional(operand::v), operand::optional(operand::a)};
  static constexpr Operand outputs[] = {operand::placements("H"), operand::placements("Hp"),
                                        operand::when_given(operand::matrix("vel", NB, 6), 1),
                                        operand::when_given(operand::matrix("acc", NB, 6), 2)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    if (in[2] != nullptr && in[1] == nullptr) return make_status(LENGTH, ARG_V, -1);  // q̈ needs q̇
    forward_kinematics(mv, in[0], in[1], in[2], out[0], out[2], out[3], out[1]);
    return OK;
  }
};

// ⁰M_f of a frame as its rotation R (3, 3) and translation p (3,): ⁰M_f = ⁰M_body(f) · placement_f (frames.hpp).
struct FramePlacement : Declared {
  static constexpr const char* name = "frame_placement";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("rotation", 3, 3), operand::vector("translation", 3)};
  static constexpr unsigned options = FRAME;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    Mat3<double> R;
    Vec3<double> p;
    frame_pose(mv, in[0], opt.frame, R, p);
    for (int k = 0; k < 9; ++k) out[0][k] = R.m[k];
    out[1][0] = p.x, out[1][1] = p.y, out[1][2] = p.z;
    return OK;
  }
};

// A_G (6, nv), h_G = A_G q̇ (rows [k_G; p], world axes about the centre of mass; centroidal.hpp).
struct CentroidalMomentumMatrix : Declared {
  static constexpr const char* name = "centroidal_momentum_matrix";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("A", 6, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const double mass = total_mass(mv);
    if (mass == 0.0) return make_status(NO_MASS, ARG_Q, 0);
    centroidal_momentum_matrix(mv, in[0], mass, out[0]);
    return OK;
  }
};

// The centre of mass c (3,) in world coordinates and, with q̇, its velocity ċ (3,) (energy.hpp):
//     c = Σ m_i ⁰c_i / m,    ċ = Σ ⁰R_i (m_i v_i + ω_i × h_i) / m
struct CenterOfMass : Declared {
  static constexpr const char* name = "center_of_mass";
  static constexpr Operand inputs[] = {operand::q, operand::optional(operand::v)};
  static constexpr Operand outputs[] = {operand::vector("position", 3),
                                        operand::when_given(operand::vector("velocity", 3), 1)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const double mass = total_mass(mv);
    if (mass == 0.0) return make_status(NO_MASS, ARG_Q, 0);
    center_of_mass(mv, in[0], in[1], mass, out[0], out[1]);
    return OK;
  }
};

// The centroidal momentum h_G = [k_G; p] = A_G(q) q̇ (6,) (centroidal.hpp).
struct CentroidalMomentum : Declared {
  static constexpr const char* name = "centroidal_momentum";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::vector("h", 6)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const double mass = total_mass(mv);
    if (mass == 0.0) return make_status(NO_MASS, ARG_Q, 0);
    centroidal_momentum(mv, in[0], in[1], mass, out[0]);
    return OK;
  }
};

// (∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈ = M) (nv, nv) of τ = RNEA(q, q̇, q̈, f_ext): the analytical derivatives (derivatives.hpp),
// ∂/∂q along the tangent of fd.integrate.
struct RneaDerivatives : Declared {
  static constexpr const char* name = "rnea_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a, operand::f_ext};
  static constexpr Operand outputs[] = {operand::matrix("dtau_dq", NV, NV), operand::matrix("dtau_dv", NV, NV),
                                        operand::matrix("M", NV, NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::rnea_derivatives_group;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    group_kernels().rnea_derivatives(mv, in[0], in[1], in[2], in[3], opt.gravity, out[0], out[1], out[2]);
    return OK;
  }
};

// L (nv, nv), lower triangular with the tree's sparsity, M(q) = Lᵀ L (ltl.hpp; RBDA §6.5): L_kj ≠ 0 only for j = k
// or j an ancestor dof of k. Status SINGULAR naming the body of the first non-positive pivot.
struct MassMatrixFactor : Declared {
  static constexpr const char* name = "mass_matrix_factor";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("L", NV, NV)};
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    return factor(mv, in[0], out[0]);
  }
  // M(q) = Lᵀ L into L, zeros above the diagonal; the dofs' parents into lambda (nv)
  static std::int64_t factor(const ModelView& mv, const double* q, double* L, std::vector<int>* lambda = nullptr) {
    thread_local std::vector<int> parents;
    std::vector<int>& lam = lambda != nullptr ? *lambda : parents;
    lam.resize(static_cast<size_t>(mv.nv));
    dof_parents(mv, lam.data());
    crba(mv, q, L);
    const int bad = ltl_factor(mv, lam.data(), L);
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    for (int i = 0; i < mv.nv; ++i)
      for (int j = i + 1; j < mv.nv; ++j) L[i * mv.nv + j] = 0.0;
    return OK;
  }
};

// x = M(q)⁻¹ b (nv,) through the tree-sparse factor, M never inverted: Lᵀ y = b, L x = y, M = Lᵀ L.
struct MassSolve : Declared {
  static constexpr const char* name = "mass_solve";
  static constexpr Operand inputs[] = {operand::q, {"b", ARG_A, {NV}, 1, false}};
  static constexpr Operand outputs[] = {operand::vector("x", NV)};
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    thread_local std::vector<double> L;
    thread_local std::vector<int> lambda;
    L.resize(static_cast<size_t>(mv.nv) * mv.nv);
    FD_TRY(MassMatrixFactor::factor(mv, in[0], L.data(), &lambda));
    std::copy(in[1], in[1] + mv.nv, out[0]);
    ltl_solve_Lt(mv, lambda.data(), L.data(), out[0]);
    ltl_solve_L(mv, lambda.data(), L.data(), out[0]);
    return OK;
  }
};

// (∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹) (nv, nv) of q̈ = ABA(q, q̇, τ, f_ext): −M⁻¹ ∂τ/∂q, −M⁻¹ ∂τ/∂q̇ at q̈ = ABA.
struct AbaDerivatives : Declared {
  static constexpr const char* name = "aba_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::tau, operand::f_ext};
  static constexpr Operand outputs[] = {operand::matrix("ddq_dq", NV, NV), operand::matrix("ddq_dv", NV, NV),
                                        operand::matrix("Minv", NV, NV)};
  static constexpr unsigned options = GRAVITY;
  static constexpr auto group = &fdgroup::GroupKernels::aba_derivatives_group;
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    thread_local std::vector<double> qdd;
    qdd.resize(static_cast<size_t>(mv.nv));
    const int bad = group_kernels().aba_derivatives(mv, dof_tree(mv).lambda.data(), in[0], in[1], in[2], in[3],
                                                    opt.gravity, qdd.data(), out[0], out[1], out[2],
                                                    aligned_scratch(aba_derivatives_scratch(mv.nv)));
    return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
  }
};

// M⁻¹ (nv, nv) from M's tree-sparse factor M = Lᵀ L: M⁻¹ = Zᵀ Z, Z = L⁻ᵀ (ltl.hpp).
struct MassMatrixInverse : Declared {
  static constexpr const char* name = "mass_matrix_inverse";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("Minv", NV, NV)};
  static constexpr SingularBlockFn singular_block = singular_at_rest;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    const int bad = group_kernels().minverse(mv, in[0], out[0]);
    return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
  }
};

// Y (nv, 10 nb) with RNEA(q, q̇, q̈) = Y π (regressor.hpp; π: fd.dynamic_parameters).
struct JointTorqueRegressor : Declared {
  static constexpr const char* name = "joint_torque_regressor";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a};
  static constexpr Operand outputs[] = {operand::matrix("Y", NV, NP)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    joint_torque_regressor(mv, in[0], in[1], in[2], out[0]);
    return OK;
  }
};

// (∂v_f/∂q, ∂v_f/∂q̇) (6, nv) of a frame's velocity in a reference (frame_derivatives.hpp).
struct FrameVelocityDerivatives : Declared {
  static constexpr const char* name = "frame_velocity_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v};
  static constexpr Operand outputs[] = {operand::matrix("dv_dq", 6, NV), operand::matrix("dv_dv", 6, NV)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    frame_motion_derivatives(mv, in[0], in[1], nullptr, opt.frame, opt.reference, out[0], out[1], nullptr, nullptr,
                             nullptr);
    return OK;
  }
};

// (∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈) (6, nv) of a frame's spatial acceleration in a reference.
struct FrameAccelerationDerivatives : Declared {
  static constexpr const char* name = "frame_acceleration_derivatives";
  static constexpr Operand inputs[] = {operand::q, operand::v, operand::a};
  static constexpr Operand outputs[] = {operand::matrix("da_dq", 6, NV), operand::matrix("da_dv", 6, NV),
                                        operand::matrix("da_da", 6, NV)};
  static constexpr unsigned options = FRAME | REFERENCE;
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options& opt) {
    thread_local std::vector<double> velocity;  // the velocity derivatives, formed on the way
    velocity.resize(12 * static_cast<size_t>(mv.nv));
    frame_motion_derivatives(mv, in[0], in[1], in[2], opt.frame, opt.reference, velocity.data(),
                             velocity.data() + 6 * mv.nv, out[0], out[1], out[2]);
    return OK;
  }
};

// ∂g/∂q (nv, nv): the generalized gravity g(q) = RNEA(q, 0, 0) differentiated along q's tangent — the
// analytical RNEA derivatives (derivatives.hpp) at rest, q̇ = q̈ = 0: no q̇ given, the velocity terms not formed
// (Pinocchio's computeGeneralizedGravityDerivatives).
struct GeneralizedGravityDerivatives : Declared {
  static constexpr const char* name = "generalized_gravity_derivatives";
  static constexpr Operand inputs[] = {operand::q};
  static constexpr Operand outputs[] = {operand::matrix("dg_dq", NV, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    group_kernels().rnea_derivatives(mv, in[0], nullptr, nullptr, nullptr, true, out[0], nullptr, nullptr);  // at rest
    return OK;
  }
};

// ∂τ_s/∂q (nv, nv) of the static torque τ_s(q) = g(q) − Σ_i J_iᵀ f_i = RNEA(q, 0, 0, f_ext), the body-frame
// forces f_ext (nb, 6) held fixed in their bodies (Pinocchio's computeStaticTorqueDerivatives).
struct StaticTorqueDerivatives : Declared {
  static constexpr const char* name = "static_torque_derivatives";
  static constexpr Operand inputs[] = {operand::q, {"f_ext", ARG_FEXT, {NB, 6}, 2, false}};
  static constexpr Operand outputs[] = {operand::matrix("dtau_dq", NV, NV)};
  static std::int64_t run(const ModelView& mv, const double* const* in, double* const* out, const Options&) {
    group_kernels().rnea_derivatives(mv, in[0], nullptr, nullptr, in[1], true, out[0], nullptr, nullptr);  // at rest
    return OK;
  }
};

// Every declared algorithm's Kernel, in the binding's order: made once, by declared_kernels() (declare.hpp; defined
// in bindings.cpp, the one translation unit that instantiates the kernels: the others only read the list).
inline std::vector<Kernel> make_declared_kernels() {
  return {
      declare<Rnea>(), declare<NonlinearEffects>(), declare<GeneralizedGravity>(), declare<Crba>(), declare<Aba>(), declare<FrameJacobian>(), declare<RneaDerivatives>(),
      declare<AbaDerivatives>(), declare<MassMatrixInverse>(), declare<JointTorqueRegressor>(),
      declare<FrameVelocityDerivatives>(), declare<FrameAccelerationDerivatives>(), declare<JointJacobians>(),
      declare<FrameJacobianTimeVariation>(), declare<KineticEnergy>(), declare<KineticEnergyDerivatives>(), declare<PotentialEnergy>(),
      declare<RneaVjp>(), declare<AbaVjp>(), declare<CrbaVjp>(),
      declare<CentroidalMomentumMatrix>(),
      declare<GeneralizedGravityDerivatives>(), declare<StaticTorqueDerivatives>(), declare<Placements>(),
      declare<ForwardKinematics>(), declare<FramePlacement>(), declare<CenterOfMass>(), declare<CentroidalMomentum>(),
      declare<MassMatrixFactor>(), declare<MassSolve>(), declare<RneaSecondDerivatives>(), declare<AbaSecondDerivatives>(),
      declare<Delassus>(), declare<ConstrainedSolve>(), declare<ContactDynamics>(), declare<OperationalSpaceInertia>(),
      declare<ContactDynamicsDerivatives>(), declare<ImpulseDynamicsDerivatives>(), declare<ImpulseDynamics>(),
      declare<KinematicsDerivatives>(), declare<CenterOfMassDerivatives>(),
      declare<CentroidalDynamicsDerivatives>(), declare<FrameVelocity>(), declare<FrameAcceleration>(),
      declare<FrameClassicalAcceleration>(), declare<Integrate>(), declare<Difference>(),
      declare<IntegrateDerivatives>(), declare<DifferenceDerivatives>()};
}

}  // namespace fdcore
